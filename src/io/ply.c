/* PLY bodies (ascii, binary little- and big-endian), per
 * ../shared/scenes/README.md: vertex x, y, z of any numeric type, the face
 * list of vertex indices with any count and index types, every other element
 * and property skipped, elements in any order. Polygons become fans.
 *
 * The header (ply_header.c) has already checked that every element count
 * fits in the file, so reserving vertices and faces by those counts is
 * bounded by the file size. Indices are checked against the header's vertex
 * count as they are read, so a face may precede the vertices. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "io/mesh_builder.h"
#include "io/number.h"
#include "io/parsers.h"
#include "io/ply_header.h"

typedef struct ply_reader {
    tt_context *ctx;
    const char *name;
    const ply_header *h;
    const char *data;
    size_t size;
    size_t pos;  /* next byte                                              */
    size_t line; /* ascii: line of data[pos]                               */
    size_t value_pos, value_line; /* where the value being read starts     */
    /* for messages: what is being read */
    const ply_element *element;
    uint64_t item;
    const ply_property *property;
    tt_mesh_builder mb;
} ply_reader;

/* "NAME:LINE: element E item I, property P: MESSAGE" (ascii) or
 * "NAME: byte OFFSET: ..." (binary). */
static tt_status fail(ply_reader *r, const char *fmt, ...) TT_PRINTF(2, 3);
static tt_status fail(ply_reader *r, const char *fmt, ...)
{
    char msg[512], where[256] = "";
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (r->element && r->property)
        snprintf(where, sizeof where, "element %.*s item %llu, property %.*s: ",
                 NAME_ARG(r->element->name, r->element->name_len), (unsigned long long)r->item,
                 NAME_ARG(r->property->name, r->property->name_len));
    else if (r->element)
        snprintf(where, sizeof where, "element %.*s item %llu: ",
                 NAME_ARG(r->element->name, r->element->name_len), (unsigned long long)r->item);
    if (r->h->format == PLY_ASCII)
        return tt_error(r->ctx, TT_ERR_PARSE, "%s:%zu: %s%s", r->name, r->value_line, where, msg);
    return tt_error(r->ctx, TT_ERR_PARSE, "%s: byte %zu: %s%s", r->name, r->value_pos, where, msg);
}

/* ------------------------------------------------------------ binary values */

/* The raw bits of one value of n bytes in the file's byte order. */
static uint64_t load_bits(const unsigned char *p, size_t n, int big_endian)
{
    uint64_t v = 0;
    if (big_endian)
        for (size_t i = 0; i < n; i++) v = (v << 8) | p[i];
    else
        for (size_t i = n; i-- > 0;) v = (v << 8) | p[i];
    return v;
}

typedef struct value {
    int is_float;
    int64_t i;  /* integer types                                          */
    double d;   /* float types                                            */
} value;

static value decode(uint64_t bits, ply_type t)
{
    value v = {0, 0, 0.0};
    switch (t) {
    case PLY_INT8: v.i = (int8_t)(uint8_t)bits; break;
    case PLY_UINT8: v.i = (uint8_t)bits; break;
    case PLY_INT16: v.i = (int16_t)(uint16_t)bits; break;
    case PLY_UINT16: v.i = (uint16_t)bits; break;
    case PLY_INT32: v.i = (int32_t)(uint32_t)bits; break;
    case PLY_UINT32: v.i = (uint32_t)bits; break;
    case PLY_FLOAT32: {
        uint32_t b = (uint32_t)bits;
        float f;
        memcpy(&f, &b, sizeof f);
        v.is_float = 1;
        v.d = f;
        break;
    }
    case PLY_FLOAT64:
        memcpy(&v.d, &bits, sizeof v.d);
        v.is_float = 1;
        break;
    }
    return v;
}

static tt_status binary_value(ply_reader *r, ply_type t, value *out)
{
    size_t n = tt_ply_type_size(t);
    r->value_pos = r->pos;
    if (r->size - r->pos < n)
        return fail(r, "truncated: the %s value needs %zu bytes, the file has %zu left",
                    tt_ply_type_name(t), n, r->size - r->pos);
    *out = decode(load_bits((const unsigned char *)r->data + r->pos, n, r->h->format == PLY_BINARY_BE), t);
    r->pos += n;
    return TT_OK;
}

/* ------------------------------------------------------------- ascii values */

static int is_line_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* The next token on the current line; an item never spans lines. */
static tt_status ascii_token(ply_reader *r, const char **s, size_t *len)
{
    while (r->pos < r->size && is_line_blank(r->data[r->pos])) r->pos++;
    r->value_pos = r->pos;
    r->value_line = r->line;
    if (r->pos == r->size || r->data[r->pos] == '\n')
        return fail(r, "%s before the item's last value",
                    r->pos == r->size ? "unexpected end of file" : "the line ends");
    size_t b = r->pos;
    while (r->pos < r->size && !tt_is_space(r->data[r->pos])) r->pos++;
    *s = r->data + b;
    *len = r->pos - b;
    return TT_OK;
}

static int fits(int64_t v, ply_type t)
{
    switch (t) {
    case PLY_INT8: return v >= INT8_MIN && v <= INT8_MAX;
    case PLY_UINT8: return v >= 0 && v <= UINT8_MAX;
    case PLY_INT16: return v >= INT16_MIN && v <= INT16_MAX;
    case PLY_UINT16: return v >= 0 && v <= UINT16_MAX;
    case PLY_INT32: return v >= INT32_MIN && v <= INT32_MAX;
    case PLY_UINT32: return v >= 0 && v <= (int64_t)UINT32_MAX;
    default: return 1;
    }
}

/* What a value is read for: skipped (only checked to be well-formed), a
 * coordinate (a correctly rounded float), or a count or index (an integer,
 * even when stored in a float type). */
typedef enum want { WANT_SKIP, WANT_FLOAT, WANT_INTEGER } want;

static tt_status ascii_value(ply_reader *r, ply_type t, want w, value *out)
{
    const char *s = NULL;
    size_t len = 0;
    char q[64];
    tt_status st = ascii_token(r, &s, &len);
    if (st) return st;
    out->is_float = tt_ply_type_is_float(t);
    if (!out->is_float || w == WANT_INTEGER) {
        tt_num_result res = tt_parse_int64(s, len, &out->i);
        if (res == TT_NUM_OK && !fits(out->i, t)) res = TT_NUM_RANGE;
        if (res == TT_NUM_OK) {
            out->is_float = 0;
            return TT_OK;
        }
        if (!out->is_float)
            return fail(r, "%s %s for type %s", res == TT_NUM_RANGE ? "value out of range" : "malformed integer",
                        tt_quote_token(q, sizeof q, s, len), tt_ply_type_name(t));
        /* a float type holding an integer as "3.0" or "3e0": checked by the caller */
    }
    if (w == WANT_SKIP) {
        if (!tt_is_float_token(s, len))
            return fail(r, "malformed number %s", tt_quote_token(q, sizeof q, s, len));
        out->d = 0.0;
        return TT_OK;
    }
    float f;
    tt_num_result res = tt_parse_float(s, len, &f);
    if (res != TT_NUM_OK)
        return fail(r, "%s %s", tt_num_result_text(res), tt_quote_token(q, sizeof q, s, len));
    out->d = f;
    return TT_OK;
}

/* ------------------------------------------------------ typed, either format */

static tt_status read_value(ply_reader *r, ply_type t, want w, value *out)
{
    return r->h->format == PLY_ASCII ? ascii_value(r, t, w, out) : binary_value(r, t, out);
}

/* A coordinate: finite and within float range. */
static tt_status read_coord(ply_reader *r, ply_type t, float *out)
{
    value v;
    tt_status st = read_value(r, t, WANT_FLOAT, &v);
    if (st) return st;
    if (!v.is_float) {
        *out = (float)v.i;
        return TT_OK;
    }
    if (!isfinite(v.d)) return fail(r, "coordinate is not a finite number (%g)", v.d);
    if (fabs(v.d) > FLT_MAX) return fail(r, "coordinate %g is out of float range", v.d);
    *out = (float)v.d;
    return TT_OK;
}

/* A list count or vertex index: an integer value, whatever the type. */
static tt_status read_integer(ply_reader *r, ply_type t, const char *what, int64_t *out)
{
    value v;
    tt_status st = read_value(r, t, WANT_INTEGER, &v);
    if (st) return st;
    if (!v.is_float) {
        *out = v.i;
        return TT_OK;
    }
    /* 2^62: a bound well inside int64 where every double is an integer */
    if (!(fabs(v.d) < 4611686018427387904.0) || v.d != floor(v.d))
        return fail(r, "%s %g is not an integer", what, v.d);
    *out = (int64_t)v.d;
    return TT_OK;
}

/* ------------------------------------------------------------------ elements */

static tt_status read_face_list(ply_reader *r, const ply_property *p)
{
    int64_t count;
    tt_status st = read_integer(r, p->count_type, "list count", &count);
    if (st) return st;
    if (count < 0) return fail(r, "list count %lld is negative", (long long)count);
    if (count < 3) return fail(r, "face has %lld vertices, needs at least 3", (long long)count);
    if (r->h->format != PLY_ASCII && (uint64_t)count > (r->size - r->pos) / tt_ply_type_size(p->type))
        return fail(r, "truncated: list count %lld needs %llu bytes, the file has %zu left",
                    (long long)count, (unsigned long long)count * tt_ply_type_size(p->type),
                    r->size - r->pos);
    uint64_t nv = r->h->elements[r->h->vertex_element].count;
    uint32_t first = 0, prev = 0;
    for (int64_t k = 0; k < count; k++) {
        int64_t i;
        if ((st = read_integer(r, p->type, "vertex index", &i))) return st;
        if (i < 0 || (uint64_t)i >= nv)
            return fail(r, "vertex index %lld (face vertex %lld) is out of range: %llu vertices",
                        (long long)i, (long long)k + 1, (unsigned long long)nv);
        uint32_t v = (uint32_t)i;
        if (k == 0) first = v;
        else if (k >= 2 && (st = tt_mb_push_triangle(&r->mb, first, prev, v))) return st;
        prev = v;
    }
    return TT_OK;
}

static tt_status skip_list(ply_reader *r, const ply_property *p)
{
    int64_t count;
    tt_status st = read_integer(r, p->count_type, "list count", &count);
    if (st) return st;
    if (count < 0) return fail(r, "list count %lld is negative", (long long)count);
    if (r->h->format != PLY_ASCII) {
        size_t n = tt_ply_type_size(p->type);
        if ((uint64_t)count > (r->size - r->pos) / n)
            return fail(r, "truncated: list count %lld needs %llu bytes, the file has %zu left",
                        (long long)count, (unsigned long long)count * n, r->size - r->pos);
        r->pos += (size_t)count * n;
        return TT_OK;
    }
    value v;
    for (int64_t k = 0; k < count; k++)
        if ((st = ascii_value(r, p->type, WANT_SKIP, &v))) return st;
    return TT_OK;
}

static tt_status read_element(ply_reader *r, const ply_element *e, int is_vertex)
{
    const ply_property *props = r->h->properties + e->first_property;
    tt_status st;
    if (e->property_count == 0) return TT_OK; /* takes no bytes, whatever its count */
    if (is_vertex && (st = tt_mb_reserve_vertices(&r->mb, (size_t)e->count))) return st;
    for (uint64_t item = 0; item < e->count; item++) {
        r->element = e;
        r->item = item;
        r->property = NULL;
        if (r->h->format == PLY_ASCII) { /* an item starts on a new line */
            while (r->pos < r->size && tt_is_space(r->data[r->pos]))
                if (r->data[r->pos++] == '\n') r->line++;
            r->value_pos = r->pos;
            r->value_line = r->line;
            if (r->pos == r->size) return fail(r, "unexpected end of file (%llu items declared)",
                                               (unsigned long long)e->count);
        }
        float xyz[3] = {0, 0, 0};
        for (size_t i = 0; i < e->property_count; i++) {
            const ply_property *p = &props[i];
            r->property = p;
            value v;
            if (p->role >= ROLE_X && p->role <= ROLE_Z) st = read_coord(r, p->type, &xyz[p->role - ROLE_X]);
            else if (p->role == ROLE_INDICES) st = read_face_list(r, p);
            else if (p->is_list) st = skip_list(r, p);
            else st = read_value(r, p->type, WANT_SKIP, &v);
            if (st) return st;
        }
        r->property = NULL;
        if (is_vertex && (st = tt_mb_push_vertex(&r->mb, xyz[0], xyz[1], xyz[2]))) return st;
        if (r->h->format == PLY_ASCII) { /* ... and ends its line */
            while (r->pos < r->size && is_line_blank(r->data[r->pos])) r->pos++;
            r->value_pos = r->pos;
            r->value_line = r->line;
            if (r->pos < r->size && r->data[r->pos] != '\n')
                return fail(r, "more values on the line than the element's properties declare");
        }
    }
    r->element = NULL;
    return TT_OK;
}

tt_status tt_ply_parse(tt_context *ctx, const char *name, const char *data, size_t size,
                       tt_scene **out)
{
    ply_header h;
    tt_status st = tt_ply_header_parse(ctx, name, data, size, &h);
    if (st) return st;
    ply_reader r;
    memset(&r, 0, sizeof r);
    r.ctx = ctx;
    r.name = name;
    r.h = &h;
    r.data = data;
    r.size = size;
    r.pos = h.body_offset;
    r.line = h.body_line;
    tt_mb_init(&r.mb, ctx, name);
    const ply_element *faces = &h.elements[h.face_element];
    /* every face gives at least one triangle */
    st = tt_mb_reserve_triangles(&r.mb, faces->count > TT_MAX_TRIANGLES ? TT_MAX_TRIANGLES : (size_t)faces->count);
    for (size_t i = 0; i < h.element_count && !st; i++)
        st = read_element(&r, &h.elements[i], i == h.vertex_element);
    if (!st) {
        r.element = NULL;
        if (h.format == PLY_ASCII) {
            while (r.pos < size && tt_is_space(data[r.pos]))
                if (data[r.pos++] == '\n') r.line++;
            r.value_line = r.line;
        }
        r.value_pos = r.pos;
        if (r.pos != size)
            st = fail(&r, "unexpected data after the last element (%zu bytes)", size - r.pos);
    }
    tt_ply_header_free(ctx, &h);
    if (st) {
        tt_mb_free(&r.mb);
        return st;
    }
    return tt_mb_finish(&r.mb, out);
}
