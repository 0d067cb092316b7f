/* Wavefront OBJ, per ../shared/scenes/README.md: only `v` and `f` lines
 * matter; a face vertex is i, i/j, i/j/k or i//k; negative indices count back
 * from the last vertex read; a polygon becomes the fan (v0, vi, vi+1).
 *
 * A positive index must name a vertex already read: every OBJ writer emits
 * vertices before the faces that use them, and checking as we go lets the
 * error name the offending line. */
#include <string.h>

#include "io/mesh_builder.h"
#include "io/number.h"
#include "io/parsers.h"

typedef struct obj_parser {
    tt_context *ctx;
    const char *name;
    size_t line;
    tt_mesh_builder mb;
} obj_parser;

/* Space or tab: OBJ tokens never span lines. */
static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

static const char *skip_blank(const char *p, const char *end)
{
    while (p < end && is_blank(*p)) p++;
    return p;
}

static const char *token_end(const char *p, const char *end)
{
    while (p < end && !is_blank(*p)) p++;
    return p;
}

const char *tt_quote_token(char *buf, size_t buf_size, const char *s, size_t len)
{
    size_t max = buf_size - 6, n = 0;
    buf[n++] = '\'';
    for (size_t i = 0; i < len && n < max; i++) {
        unsigned char c = (unsigned char)s[i];
        buf[n++] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    if (len > max - 1) {
        buf[n++] = '.';
        buf[n++] = '.';
        buf[n++] = '.';
    }
    buf[n++] = '\'';
    buf[n] = '\0';
    return buf;
}

/* A '#' token starts a trailing comment ("v 1 2 3 # top"). */
static int is_comment(const char *p, const char *end) { return p < end && *p == '#'; }

/* v x y z [w | r g b ...]: the extra numbers are checked but ignored. */
static tt_status parse_vertex(obj_parser *o, const char *p, const char *end)
{
    static const char *const axis[3] = {"x", "y", "z"};
    float xyz[3];
    char q[64];
    int k = 0;
    for (;; k++) {
        p = skip_blank(p, end);
        if (p == end || is_comment(p, end)) break;
        const char *e = token_end(p, end);
        float f;
        tt_num_result r = tt_parse_float(p, (size_t)(e - p), &f);
        if (r != TT_NUM_OK)
            return tt_error(o->ctx, TT_ERR_PARSE, "%s:%zu: vertex %s: %s %s", o->name, o->line,
                            k < 3 ? axis[k] : "extra value", tt_num_result_text(r),
                            tt_quote_token(q, sizeof q, p, (size_t)(e - p)));
        if (k < 3) xyz[k] = f;
        p = e;
    }
    if (k < 3)
        return tt_error(o->ctx, TT_ERR_PARSE, "%s:%zu: vertex has %d coordinates, needs 3",
                        o->name, o->line, k);
    return tt_mb_push_vertex(&o->mb, xyz[0], xyz[1], xyz[2]);
}

/* One face vertex "i", "i/j", "i/j/k" or "i//k" to a 0-based vertex index;
 * the texture and normal indices must be integers but are ignored. */
static tt_status parse_face_vertex(obj_parser *o, const char *p, const char *e, int which,
                                   uint32_t *out)
{
    char q[64];
    const char *part[3], *part_end[3];
    int parts = 0;
    for (const char *s = p;;) {
        const char *slash = memchr(s, '/', (size_t)(e - s));
        if (parts == 3) { parts = 4; break; } /* a third slash */
        part[parts] = s;
        part_end[parts++] = slash ? slash : e;
        if (!slash) break;
        s = slash + 1;
    }
    int64_t i = 0, ignored;
    tt_num_result r = parts > 3 ? TT_NUM_MALFORMED : tt_parse_int64(p, (size_t)(part_end[0] - p), &i);
    for (int k = 1; k < parts && k < 3 && r == TT_NUM_OK; k++) {
        if (k == 1 && parts == 3 && part_end[1] == part[1]) continue; /* i//k */
        r = tt_parse_int64(part[k], (size_t)(part_end[k] - part[k]), &ignored);
    }
    if (r != TT_NUM_OK)
        return tt_error(o->ctx, TT_ERR_PARSE,
                        "%s:%zu: face vertex %d: %s %s (expected i, i/j, i/j/k or i//k)", o->name,
                        o->line, which + 1, r == TT_NUM_RANGE ? "index out of range" : "malformed",
                        tt_quote_token(q, sizeof q, p, (size_t)(e - p)));
    size_t n = o->mb.vertex_count;
    if (i == 0)
        return tt_error(o->ctx, TT_ERR_PARSE,
                        "%s:%zu: face vertex %d: index 0 is invalid (OBJ indices start at 1)",
                        o->name, o->line, which + 1);
    if (i > 0 && (uint64_t)i > n)
        return tt_error(o->ctx, TT_ERR_PARSE,
                        "%s:%zu: face vertex %d: index %lld is out of range (%zu vertices read so far)",
                        o->name, o->line, which + 1, (long long)i, n);
    if (i < 0 && (uint64_t)(-(i + 1)) >= n) /* -(i+1) cannot overflow */
        return tt_error(o->ctx, TT_ERR_PARSE,
                        "%s:%zu: face vertex %d: relative index %lld is out of range (%zu vertices read so far)",
                        o->name, o->line, which + 1, (long long)i, n);
    *out = i > 0 ? (uint32_t)(i - 1) : (uint32_t)(n - (uint64_t)(-(i + 1)) - 1);
    return TT_OK;
}

/* f a b c ...: the fan (a, b, c), (a, c, d), ... */
static tt_status parse_face(obj_parser *o, const char *p, const char *end)
{
    uint32_t first = 0, prev = 0;
    int k = 0;
    tt_status st;
    for (;; k++) {
        p = skip_blank(p, end);
        if (p == end || is_comment(p, end)) break;
        const char *e = token_end(p, end);
        uint32_t v = 0;
        if ((st = parse_face_vertex(o, p, e, k, &v))) return st;
        if (k == 0) first = v;
        else if (k >= 2 && (st = tt_mb_push_triangle(&o->mb, first, prev, v))) return st;
        prev = v;
        p = e;
    }
    if (k < 3)
        return tt_error(o->ctx, TT_ERR_PARSE, "%s:%zu: face has %d vertices, needs at least 3",
                        o->name, o->line, k);
    return TT_OK;
}

tt_status tt_obj_parse(tt_context *ctx, const char *name, const char *data, size_t size,
                       tt_scene **out)
{
    obj_parser o;
    o.ctx = ctx;
    o.name = name;
    o.line = 0;
    tt_mb_init(&o.mb, ctx, name);
    const char *p = data, *end = data + size;
    tt_status st = TT_OK;
    while (p < end) {
        o.line++;
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end;
        const char *s = skip_blank(p, le);
        const char *se = token_end(s, le);
        if (se - s == 1 && s[0] == 'v') st = parse_vertex(&o, se, le);
        else if (se - s == 1 && s[0] == 'f') st = parse_face(&o, se, le);
        if (st) {
            tt_mb_free(&o.mb);
            return st;
        }
        p = nl ? nl + 1 : end;
    }
    return tt_mb_finish(&o.mb, out);
}
