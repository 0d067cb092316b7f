#include "io/ply_header.h"

#include <stdio.h>
#include <string.h>

#include "io/number.h"
#include "io/parsers.h"

static const struct {
    const char *name;
    ply_type type;
} type_names[] = {
    {"char", PLY_INT8},      {"int8", PLY_INT8},       {"uchar", PLY_UINT8},
    {"uint8", PLY_UINT8},    {"short", PLY_INT16},     {"int16", PLY_INT16},
    {"ushort", PLY_UINT16},  {"uint16", PLY_UINT16},   {"int", PLY_INT32},
    {"int32", PLY_INT32},    {"uint", PLY_UINT32},     {"uint32", PLY_UINT32},
    {"float", PLY_FLOAT32},  {"float32", PLY_FLOAT32}, {"double", PLY_FLOAT64},
    {"float64", PLY_FLOAT64},
};

size_t tt_ply_type_size(ply_type t)
{
    static const size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[t];
}

const char *tt_ply_type_name(ply_type t)
{
    static const char *const names[] = {"char",  "uchar", "short", "ushort",
                                        "int",   "uint",  "float", "double"};
    return names[t];
}

int tt_ply_type_is_float(ply_type t) { return t == PLY_FLOAT32 || t == PLY_FLOAT64; }

typedef struct token {
    const char *s;
    size_t len;
} token;

static int tok_is(token t, const char *word)
{
    size_t n = strlen(word);
    return t.len == n && memcmp(t.s, word, n) == 0;
}

/* Splits one header line into at most `max` tokens; returns the count, or
 * max + 1 when there are more. */
static size_t split(const char *p, const char *end, token *toks, size_t max)
{
    size_t n = 0;
    for (;;) {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) p++;
        if (p == end) return n;
        const char *s = p;
        while (p < end && !(*p == ' ' || *p == '\t' || *p == '\r')) p++;
        if (n == max) return max + 1;
        toks[n].s = s;
        toks[n++].len = (size_t)(p - s);
    }
}

static int lookup_type(token t, ply_type *out)
{
    for (size_t i = 0; i < sizeof type_names / sizeof type_names[0]; i++)
        if (tok_is(t, type_names[i].name)) {
            *out = type_names[i].type;
            return 1;
        }
    return 0;
}

/* Saturating arithmetic for the size bound: anything past UINT64_MAX is
 * "more than the file can hold" anyway. */
static uint64_t sat_add(uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }
static uint64_t sat_mul(uint64_t a, uint64_t b)
{
    return (a && b > UINT64_MAX / a) ? UINT64_MAX : a * b;
}

void tt_ply_header_free(tt_context *ctx, ply_header *h)
{
    tt_free(ctx, h->elements);
    tt_free(ctx, h->properties);
    tt_free(ctx, h->names);
    h->elements = NULL;
    h->properties = NULL;
    h->names = NULL;
}

/* ------------------------------------------------------------ name index */

/* Duplicate element names, and duplicate property names within an element,
 * are found through a hash set rather than by scanning the names read so
 * far: a scan makes a header of n names cost n^2 comparisons, and a few
 * megabytes of "property uchar pN" lines took minutes (a time bomb). A slot
 * holds 2 i for element i, 2 j + 1 for property j, or NAME_EMPTY; a
 * property's key includes its element. */
#define NAME_EMPTY SIZE_MAX
#define NO_OWNER SIZE_MAX

static uint64_t name_hash(const char *s, size_t len, size_t owner)
{
    uint64_t x = 14695981039346656037ull ^ ((uint64_t)owner * 0x9E3779B97F4A7C15ull);
    for (size_t i = 0; i < len; i++) x = (x ^ (unsigned char)s[i]) * 1099511628211ull;
    return x ^ (x >> 29);
}

static void slot_key(const ply_header *h, size_t v, const char **s, size_t *len, size_t *owner)
{
    if (v & 1) {
        const ply_property *p = &h->properties[v >> 1];
        *s = p->name, *len = p->name_len, *owner = p->element;
    } else {
        const ply_element *e = &h->elements[v >> 1];
        *s = e->name, *len = e->name_len, *owner = NO_OWNER;
    }
}

/* The slot holding the key, or the empty slot where it would go. */
static size_t name_slot(const ply_header *h, const char *s, size_t len, size_t owner)
{
    size_t mask = h->name_cap - 1;
    for (size_t i = (size_t)name_hash(s, len, owner) & mask;; i = (i + 1) & mask) {
        size_t v = h->names[i];
        if (v == NAME_EMPTY) return i;
        const char *ks;
        size_t kl, ko;
        slot_key(h, v, &ks, &kl, &ko);
        if (ko == owner && kl == len && memcmp(ks, s, len) == 0) return i;
    }
}

/* The slot value of an existing element (owner NO_OWNER) or property of
 * element `owner` with this name, or NAME_EMPTY. */
static size_t name_find(const ply_header *h, const char *s, size_t len, size_t owner)
{
    if (h->name_cap == 0) return NAME_EMPTY;
    return h->names[name_slot(h, s, len, owner)];
}

/* Adds slot value v (its name not yet present), growing the table to keep
 * it at most half full. */
static tt_status name_add(tt_context *ctx, const char *name, size_t line, ply_header *h, size_t v)
{
    if (2 * (h->name_count + 1) > h->name_cap) {
        size_t cap = h->name_cap ? 2 * h->name_cap : 64;
        size_t *t = tt_alloc_array(ctx, cap, sizeof *t);
        if (!t) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s:%zu: out of memory", name, line);
        size_t *old = h->names, old_cap = h->name_cap;
        for (size_t i = 0; i < cap; i++) t[i] = NAME_EMPTY;
        h->names = t;
        h->name_cap = cap;
        for (size_t i = 0; i < old_cap; i++) {
            if (old[i] == NAME_EMPTY) continue;
            const char *ks;
            size_t kl, ko;
            slot_key(h, old[i], &ks, &kl, &ko);
            t[name_slot(h, ks, kl, ko)] = old[i];
        }
        tt_free(ctx, old);
    }
    const char *ks;
    size_t kl, ko;
    slot_key(h, v, &ks, &kl, &ko);
    h->names[name_slot(h, ks, kl, ko)] = v;
    h->name_count++;
    return TT_OK;
}

/* The fewest bytes one element can take in the body. Binary: every scalar
 * and list count at its size, and the face index list with its 3 indices.
 * Ascii: one character and one separator a value, lists counted by their
 * count alone (so that a short face is reported by the body parser, with its
 * line). */
static uint64_t min_element_bytes(const ply_header *h, const ply_element *e)
{
    uint64_t n = 0;
    for (size_t i = 0; i < e->property_count; i++) {
        const ply_property *p = &h->properties[e->first_property + i];
        if (h->format == PLY_ASCII)
            n = sat_add(n, 2);
        else if (p->is_list)
            n = sat_add(n, tt_ply_type_size(p->count_type) +
                               (p->role == ROLE_INDICES ? 3 : 0) * tt_ply_type_size(p->type));
        else
            n = sat_add(n, tt_ply_type_size(p->type));
    }
    return n;
}

static tt_status add_element(tt_context *ctx, const char *name, ply_header *h, token t,
                             uint64_t count, size_t line)
{
    if (h->element_count == h->element_cap) {
        size_t cap = h->element_cap ? h->element_cap * 2 : 8;
        ply_element *p = tt_realloc_array(ctx, h->elements, cap, sizeof *p);
        if (!p) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s:%zu: out of memory", name, line);
        h->elements = p;
        h->element_cap = cap;
    }
    ply_element *e = &h->elements[h->element_count++];
    e->name = t.s;
    e->name_len = t.len;
    e->count = count;
    e->first_property = h->property_count;
    e->property_count = 0;
    e->line = line;
    return name_add(ctx, name, line, h, 2 * (h->element_count - 1));
}

static tt_status add_property(tt_context *ctx, const char *name, ply_header *h,
                              const ply_property *prop, size_t line)
{
    if (h->property_count == h->property_cap) {
        size_t cap = h->property_cap ? h->property_cap * 2 : 16;
        ply_property *p = tt_realloc_array(ctx, h->properties, cap, sizeof *p);
        if (!p) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s:%zu: out of memory", name, line);
        h->properties = p;
        h->property_cap = cap;
    }
    ply_property *p = &h->properties[h->property_count++];
    *p = *prop;
    p->element = h->element_count - 1;
    h->elements[h->element_count - 1].property_count++;
    return name_add(ctx, name, line, h, 2 * (h->property_count - 1) + 1);
}

static tt_status parse_lines(tt_context *ctx, const char *name, const char *data, size_t size,
                             ply_header *h)
{
    const char *p = data, *end = data + size;
    size_t line = 0;
    int have_format = 0;
    char q[64];
    for (;;) {
        if (p >= end)
            return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: the header has no end_header line", name,
                            line);
        line++;
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl)
            return tt_error(ctx, TT_ERR_PARSE,
                            "%s:%zu: the header ends without a newline after its last line", name,
                            line);
        token t[6];
        size_t n = split(p, nl, t, 5);
        p = nl + 1;
        if (line == 1) {
            if (n != 1 || !tok_is(t[0], "ply"))
                return tt_error(ctx, TT_ERR_PARSE, "%s:1: not a PLY file (the first line is not \"ply\")",
                                name);
            continue;
        }
        if (n == 0) continue; /* blank line: harmless */
        if (tok_is(t[0], "comment") || tok_is(t[0], "obj_info")) continue;
        if (tok_is(t[0], "format")) {
            if (have_format)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: a second format line", name, line);
            if (n != 3)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: expected \"format TYPE 1.0\"", name, line);
            if (tok_is(t[1], "ascii")) h->format = PLY_ASCII;
            else if (tok_is(t[1], "binary_little_endian")) h->format = PLY_BINARY_LE;
            else if (tok_is(t[1], "binary_big_endian")) h->format = PLY_BINARY_BE;
            else
                return tt_error(ctx, TT_ERR_PARSE,
                                "%s:%zu: unknown PLY format %s (expected ascii, binary_little_endian or binary_big_endian)",
                                name, line, tt_quote_token(q, sizeof q, t[1].s, t[1].len));
            if (!tok_is(t[2], "1.0") && !tok_is(t[2], "1"))
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: unsupported PLY version %s (expected 1.0)",
                                name, line, tt_quote_token(q, sizeof q, t[2].s, t[2].len));
            have_format = 1;
            continue;
        }
        if (!have_format)
            return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: expected the format line before %s", name,
                            line, tt_quote_token(q, sizeof q, t[0].s, t[0].len));
        if (tok_is(t[0], "element")) {
            int64_t count;
            if (n != 3)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: expected \"element NAME COUNT\"", name, line);
            tt_num_result r = tt_parse_int64(t[2].s, t[2].len, &count);
            if (r != TT_NUM_OK || count < 0)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: element count %s is not a non-negative integer%s",
                                name, line, tt_quote_token(q, sizeof q, t[2].s, t[2].len),
                                r == TT_NUM_RANGE ? " (too large)" : "");
            size_t first = name_find(h, t[1].s, t[1].len, NO_OWNER);
            if (first != NAME_EMPTY)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: a second element %s (first on line %zu)",
                                name, line, tt_quote_token(q, sizeof q, t[1].s, t[1].len),
                                h->elements[first >> 1].line);
            tt_status st = add_element(ctx, name, h, t[1], (uint64_t)count, line);
            if (st) return st;
            continue;
        }
        if (tok_is(t[0], "property")) {
            if (h->element_count == 0)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: a property before any element", name, line);
            ply_property prop;
            memset(&prop, 0, sizeof prop);
            token type_tok, count_tok, name_tok;
            if (n >= 2 && tok_is(t[1], "list")) {
                if (n != 5)
                    return tt_error(ctx, TT_ERR_PARSE,
                                    "%s:%zu: expected \"property list COUNT_TYPE ITEM_TYPE NAME\"",
                                    name, line);
                prop.is_list = 1;
                count_tok = t[2], type_tok = t[3], name_tok = t[4];
                if (!lookup_type(count_tok, &prop.count_type))
                    return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: unknown property type %s", name, line,
                                    tt_quote_token(q, sizeof q, count_tok.s, count_tok.len));
            } else {
                if (n != 3)
                    return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: expected \"property TYPE NAME\"", name, line);
                type_tok = t[1], name_tok = t[2];
            }
            if (!lookup_type(type_tok, &prop.type))
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: unknown property type %s", name, line,
                                tt_quote_token(q, sizeof q, type_tok.s, type_tok.len));
            prop.name = name_tok.s;
            prop.name_len = name_tok.len;
            const ply_element *e = &h->elements[h->element_count - 1];
            if (name_find(h, prop.name, prop.name_len, h->element_count - 1) != NAME_EMPTY)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: a second property %s in element %.*s",
                                name, line, tt_quote_token(q, sizeof q, prop.name, prop.name_len),
                                NAME_ARG(e->name, e->name_len));
            tt_status st = add_property(ctx, name, h, &prop, line);
            if (st) return st;
            continue;
        }
        if (tok_is(t[0], "end_header")) {
            if (n != 1)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: unexpected text after end_header", name, line);
            h->body_offset = (size_t)(p - data);
            h->body_line = line + 1;
            return TT_OK;
        }
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: unknown header keyword %s", name, line,
                        tt_quote_token(q, sizeof q, t[0].s, t[0].len));
    }
}

static int name_is(const char *s, size_t len, const char *word)
{
    size_t n = strlen(word);
    return len == n && memcmp(s, word, n) == 0;
}

/* Finds the vertex and face elements and marks the properties we use. */
static tt_status assign_roles(tt_context *ctx, const char *name, ply_header *h)
{
    static const char *const axis[3] = {"x", "y", "z"};
    size_t nv = SIZE_MAX, nf = SIZE_MAX;
    for (size_t i = 0; i < h->element_count; i++) {
        if (name_is(h->elements[i].name, h->elements[i].name_len, "vertex")) nv = i;
        if (name_is(h->elements[i].name, h->elements[i].name_len, "face")) nf = i;
    }
    if (nv == SIZE_MAX)
        return tt_error(ctx, TT_ERR_PARSE, "%s: the header declares no vertex element", name);
    if (nf == SIZE_MAX)
        return tt_error(ctx, TT_ERR_PARSE, "%s: the header declares no face element", name);
    ply_element *v = &h->elements[nv], *f = &h->elements[nf];
    for (int k = 0; k < 3; k++) {
        ply_property *found = NULL;
        for (size_t i = 0; i < v->property_count; i++) {
            ply_property *p = &h->properties[v->first_property + i];
            if (name_is(p->name, p->name_len, axis[k])) found = p;
        }
        if (!found)
            return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: element vertex has no property %s", name,
                            v->line, axis[k]);
        if (found->is_list)
            return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: vertex property %s is a list, not a number",
                            name, v->line, axis[k]);
        found->role = (ply_role)(ROLE_X + k);
    }
    ply_property *list = NULL;
    for (size_t i = 0; i < f->property_count && !list; i++) {
        ply_property *p = &h->properties[f->first_property + i];
        if (name_is(p->name, p->name_len, "vertex_indices") || name_is(p->name, p->name_len, "vertex_index"))
            list = p;
    }
    if (!list)
        return tt_error(ctx, TT_ERR_PARSE,
                        "%s:%zu: element face has no vertex_indices (or vertex_index) list", name,
                        f->line);
    if (!list->is_list)
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: face property %.*s is not a list", name, f->line,
                        NAME_ARG(list->name, list->name_len));
    list->role = ROLE_INDICES;
    if (v->count > 0xFFFFFFFFull)
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: %llu vertices, more than 32-bit indices can address",
                        name, v->line, (unsigned long long)v->count);
    h->vertex_element = nv;
    h->face_element = nf;
    return TT_OK;
}

/* Refuses counts that the file's remaining bytes cannot hold, before any
 * allocation sized by them: a few header bytes cannot make us reserve
 * gigabytes. The error is a truncation at the end of the file. */
static tt_status check_sizes(tt_context *ctx, const char *name, const ply_header *h, size_t size)
{
    uint64_t body = size - h->body_offset;
    /* ascii: the last value needs no separator */
    uint64_t avail = h->format == PLY_ASCII ? body + 1 : body;
    uint64_t need = 0;
    for (size_t i = 0; i < h->element_count; i++) {
        const ply_element *e = &h->elements[i];
        uint64_t one = min_element_bytes(h, e);
        need = sat_add(need, sat_mul(e->count, one));
        if (need <= avail) continue;
        char where[64];
        if (h->format == PLY_ASCII) snprintf(where, sizeof where, "%zu", e->line);
        else snprintf(where, sizeof where, " byte %zu", size);
        return tt_error(ctx, TT_ERR_PARSE,
                        "%s:%s: truncated: element %.*s (header line %zu) declares %llu items of at "
                        "least %llu bytes each; with the elements before it that needs at least "
                        "%llu%s bytes after the header, but the file has only %llu",
                        name, where, NAME_ARG(e->name, e->name_len), e->line,
                        (unsigned long long)e->count, (unsigned long long)one,
                        (unsigned long long)need, need == UINT64_MAX ? "+" : "",
                        (unsigned long long)body);
    }
    return TT_OK;
}

tt_status tt_ply_header_parse(tt_context *ctx, const char *name, const char *data, size_t size,
                              ply_header *h)
{
    memset(h, 0, sizeof *h);
    tt_status st = parse_lines(ctx, name, data, size, h);
    if (!st) st = assign_roles(ctx, name, h);
    if (!st) st = check_sizes(ctx, name, h, size);
    if (st) tt_ply_header_free(ctx, h);
    return st;
}
