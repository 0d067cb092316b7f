/* PLY loading: the same mesh written as ascii, binary little- and big-endian
 * with every coordinate, count and index type, with extra elements and
 * properties (lists too) to skip and elements in either order, must give
 * identical scenes; the small files under data/ (written by an independent
 * Python script) too. Then every malformed input: TT_ERR_PARSE, with the file
 * and the line (ascii) or byte offset (binary) in the message. */
#include <math.h>

#include "io_util.h"

enum { ASCII, LE, BE };
static const char *const format_name[] = {"ascii", "binary_little_endian", "binary_big_endian"};

static const char *const types[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                    "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};

static size_t type_size(const char *t)
{
    if (strstr(t, "char") || strstr(t, "int8")) return 1;
    if (strstr(t, "short") || strstr(t, "int16")) return 2;
    if (!strcmp(t, "double") || !strcmp(t, "float64")) return 8;
    return 4;
}

static int type_is_float(const char *t) { return t[0] == 'f' || t[0] == 'd'; }

/* Writes one value of type t in the given format. */
static void put(buf *b, int format, const char *t, double v)
{
    if (format == ASCII) {
        if (type_is_float(t)) buf_printf(b, "%.9g ", v);
        else buf_printf(b, "%lld ", (long long)v);
        return;
    }
    unsigned char bytes[8];
    size_t n = type_size(t);
    uint64_t bits;
    if (!strcmp(t, "float") || !strcmp(t, "float32")) {
        float f = (float)v;
        uint32_t u;
        memcpy(&u, &f, 4);
        bits = u;
    } else if (n == 8) {
        memcpy(&bits, &v, 8);
    } else {
        bits = (uint64_t)(int64_t)v;
    }
    for (size_t i = 0; i < n; i++) {
        size_t shift = format == LE ? i : n - 1 - i;
        bytes[i] = (unsigned char)(bits >> (8 * shift));
    }
    buf_put(b, bytes, n);
}

/* The test mesh: 6 vertices with small integer (or, for float types,
 * fractional) coordinates; a triangle, a quad and a pentagon. */
static const double vx[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 3, 4}, {5, 6, 7}};
static const double vfrac[6][3] = {{0.5, -0.25, 0.125}, {1.5, 0, 0}, {1, 1.75, 0}, {0, 1, -3.5}, {2, 3, 4}, {5, 6, 7.25}};
static const int faces[3][6] = {{3, 0, 1, 2}, {4, 0, 2, 3, 4}, {5, 5, 4, 3, 2, 1}};
/* fans of the above */
static const uint32_t fan[][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {5, 4, 3}, {5, 3, 2}, {5, 2, 1}};

typedef struct spec {
    int format;
    const char *coord, *count, *index;
    int faces_first; /* the face element before the vertex element       */
    int extras;      /* extra elements and properties to skip            */
} spec;

static void write_ply(buf *b, const spec *s)
{
    const double(*v)[3] = type_is_float(s->coord) ? vfrac : vx;
    b->size = 0;
    buf_printf(b, "ply\nformat %s 1.0\ncomment test mesh\n", format_name[s->format]);
    if (s->extras) buf_printf(b, "obj_info generated\nelement material 2\nproperty uchar red\nproperty list int float weights\n");
    const char *vertex_header, *face_header;
    char vh[512], fh[512];
    snprintf(vh, sizeof vh, "element vertex 6\n%sproperty %s x\nproperty %s y\n%sproperty %s z\n%s", s->extras ? "property float confidence\n" : "",
             s->coord, s->coord, s->extras ? "property list uchar short neighbours\n" : "", s->coord,
             s->extras ? "property double intensity\n" : "");
    snprintf(fh, sizeof fh, "element face 3\n%sproperty list %s %s vertex_indices\n%s", s->extras ? "property uchar flags\n" : "",
             s->count, s->index, s->extras ? "property list uint8 float32 texcoord\n" : "");
    vertex_header = vh;
    face_header = fh;
    buf_printf(b, "%s%s", s->faces_first ? face_header : vertex_header, s->faces_first ? vertex_header : face_header);
    if (s->extras) buf_printf(b, "element tail 1\nproperty int value\n");
    buf_printf(b, "end_header\n");
    if (s->extras) {
        for (int m = 0; m < 2; m++) {
            put(b, s->format, "uchar", 200 + m);
            put(b, s->format, "int", m + 1);
            for (int k = 0; k <= m; k++) put(b, s->format, "float", 0.5 * k);
            if (s->format == ASCII) buf_printf(b, "\n");
        }
    }
    for (int pass = 0; pass < 2; pass++) {
        int vertices = (pass == 0) != (s->faces_first != 0);
        if (vertices) {
            for (int i = 0; i < 6; i++) {
                if (s->extras) put(b, s->format, "float", 0.75);
                put(b, s->format, s->coord, v[i][0]);
                put(b, s->format, s->coord, v[i][1]);
                if (s->extras) {
                    put(b, s->format, "uchar", 2);
                    put(b, s->format, "short", -i);
                    put(b, s->format, "short", i);
                }
                put(b, s->format, s->coord, v[i][2]);
                if (s->extras) put(b, s->format, "double", 1e300);
                if (s->format == ASCII) buf_printf(b, "\n");
            }
        } else {
            for (int f = 0; f < 3; f++) {
                if (s->extras) put(b, s->format, "uchar", 255);
                put(b, s->format, s->count, faces[f][0]);
                for (int k = 1; k <= faces[f][0]; k++) put(b, s->format, s->index, faces[f][k]);
                if (s->extras) {
                    put(b, s->format, "uint8", f);
                    for (int k = 0; k < f; k++) put(b, s->format, "float32", k);
                }
                if (s->format == ASCII) buf_printf(b, "\n");
            }
        }
    }
    if (s->extras) {
        put(b, s->format, "int", -5);
        if (s->format == ASCII) buf_printf(b, "\n");
    }
}

/* The loaded scene is exactly the test mesh. */
static int is_test_mesh(const tt_scene *s, const char *coord)
{
    const double(*v)[3] = type_is_float(coord) ? vfrac : vx;
    if (!s || tt_scene_triangle_count(s) != 6 || tt_scene_vertex_count(s) != 6) return 0;
    for (size_t t = 0; t < 6; t++) {
        float want[9];
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++) want[3 * k + a] = (float)v[fan[t][k]][a];
        if (!triangle_is(s, t, want)) return 0;
    }
    return 1;
}

static void check_all_types(tt_context *ctx)
{
    buf b = {0};
    size_t n_types = sizeof types / sizeof types[0];
    int loaded = 0;
    for (int format = 0; format < 3; format++)
        for (size_t c = 0; c < n_types; c++)
            for (int extras = 0; extras < 2; extras++) {
                /* every coordinate type; count and index types cycle through all */
                spec s = {format, types[c], types[(c + 1 + extras) % n_types], types[(c + 3) % n_types],
                          (int)(c & 1), extras};
                if (strstr(s.index, "char") || strstr(s.index, "int8")) s.index = format ? "uint16" : "int";
                write_ply(&b, &s);
                tt_scene *scene = NULL;
                tt_status st = tt_scene_load_memory(ctx, "mesh.ply", NULL, b.data, b.size, &scene);
                CHECK_MSG(st == TT_OK && is_test_mesh(scene, s.coord),
                          "%s coord %s count %s index %s faces_first %d extras %d: %s", format_name[format],
                          s.coord, s.count, s.index, s.faces_first, extras,
                          st ? tt_context_last_error(ctx) : "wrong mesh");
                loaded += st == TT_OK;
                tt_scene_destroy(scene);
            }
    /* char/uchar indices too (the loop above avoids them for the index) */
    for (int format = 0; format < 3; format++) {
        spec s = {format, "float", "uchar", "uchar", 0, 0};
        write_ply(&b, &s);
        tt_scene *scene = NULL;
        CHECK_OK(ctx, tt_scene_load_memory(ctx, "mesh.ply", "ply", b.data, b.size, &scene));
        CHECK(is_test_mesh(scene, "float"));
        tt_scene_destroy(scene);
    }
    printf("%d PLY variants loaded\n", loaded);
    free(b.data);
}

/* The files under data/: the same 2-quad mesh as ascii, LE and BE, written
 * by a Python script, load to the same scene. */
static void check_shipped_files(tt_context *ctx)
{
    static const char *const files[] = {"quads_ascii.ply", "quads_le.ply", "quads_be.ply", "quads.obj"};
    tt_scene *s[4] = {0};
    char path[4096];
    for (int i = 0; i < 4; i++) {
        snprintf(path, sizeof path, "%s/io/data/%s", TT_TESTS_DIR, files[i]);
        CHECK_OK(ctx, tt_scene_load(ctx, path, &s[i]));
    }
    if (s[0] && s[1] && s[2] && s[3]) {
        CHECK(tt_scene_triangle_count(s[0]) == 4 && tt_scene_vertex_count(s[0]) == 6);
        for (int i = 1; i < 4; i++) {
            CHECK_MSG(tt_scene_triangle_count(s[i]) == 4 && tt_scene_vertex_count(s[i]) == 6, "%s", files[i]);
            for (size_t t = 0; t < 4; t++) {
                float a[9], b[9];
                tt_scene_triangle(s[0], t, a);
                tt_scene_triangle(s[i], t, b);
                CHECK_MSG(memcmp(a, b, sizeof a) == 0, "%s triangle %zu", files[i], t);
            }
        }
        /* vertex 1 of the file is (1.5, -2.25, 1e-3) */
        float t0[9];
        tt_scene_triangle(s[0], 0, t0);
        CHECK(t0[3] == 1.5f && t0[4] == -2.25f && t0[5] == 1e-3f);
    }
    for (int i = 0; i < 4; i++) tt_scene_destroy(s[i]);
}

/* ------------------------------------------------------------------ errors */

#define HDR_ASCII "ply\nformat ascii 1.0\n"
#define VERT3 "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
#define FACE1 "element face 1\nproperty list uchar int vertex_indices\n"
#define BODY3 "0 0 0\n1 0 0\n0 1 0\n"

static void check_header_errors(tt_context *ctx)
{
    const tt_status P = TT_ERR_PARSE;
    EXPECT_LOAD_ERR(ctx, "bad.ply", "ply\nformat binary_middle_endian 1.0\n" VERT3 FACE1 "end_header\n", P,
                    "bad.ply:2:", "unknown PLY format", "binary_middle_endian");
    EXPECT_LOAD_ERR(ctx, "bad.ply", "ply\nformat ascii 2.0\n" VERT3 FACE1 "end_header\n", P, "bad.ply:2:", "version");
    EXPECT_LOAD_ERR(ctx, "bad.ply", "ply\nformat ascii\n" VERT3 FACE1 "end_header\n", P, "bad.ply:2:", "format");
    EXPECT_LOAD_ERR(ctx, "bad.ply", "ply\n" VERT3 FACE1 "end_header\n", P, "bad.ply:2:", "format line");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex 3\nproperty float128 x\n", P, "bad.ply:4:",
                    "unknown property type", "float128");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 "element face 1\nproperty list uchar long vertex_indices\nend_header\n",
                    P, "bad.ply:8:", "unknown property type", "long");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 "element face 1\nproperty list huge int vertex_indices\nend_header\n",
                    P, "bad.ply:8:", "unknown property type", "huge");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex 3\nproperty float x\nproperty float z\n" FACE1 "end_header\n" BODY3,
                    P, "bad.ply:3:", "no property y");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex 3\nproperty float x\nproperty float y\nproperty list uchar float z\n" FACE1 "end_header\n",
                    P, "bad.ply:3:", "z is a list");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 "element face 1\nproperty list uchar int corners\nend_header\n" BODY3 "3 0 1 2\n",
                    P, "bad.ply:7:", "no vertex_indices");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 "element face 1\nproperty int vertex_indices\nend_header\n" BODY3 "3\n",
                    P, "bad.ply:7:", "not a list");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 "end_header\n" BODY3, P, "bad.ply", "no face element");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII FACE1 "end_header\n3 0 1 2\n", P, "bad.ply", "no vertex element");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 FACE1, P, "bad.ply", "no end_header");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 FACE1 "end_header", P, "bad.ply:9:", "newline");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 FACE1 "bogus line\nend_header\n", P, "bad.ply:9:", "unknown header keyword", "bogus");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "property float x\n", P, "bad.ply:3:", "before any element");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex -3\n", P, "bad.ply:3:", "not a non-negative integer");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex 3x\n", P, "bad.ply:3:", "'3x'");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex 99999999999999999999999\n", P, "bad.ply:3:", "too large");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 "element vertex 3\n", P, "bad.ply:7:", "second element");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 "property float x\n", P, "bad.ply:7:", "second property");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex 3 4\n", P, "bad.ply:3:", "element NAME COUNT");
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII VERT3 FACE1 "end_header extra\n", P, "bad.ply:9:", "after end_header");
    /* more vertices than 32-bit indices can address */
    EXPECT_LOAD_ERR(ctx, "bad.ply", HDR_ASCII "element vertex 4294967296\nproperty float x\nproperty float y\nproperty float z\n" FACE1 "end_header\n",
                    P, "bad.ply:3:", "32-bit");
    /* not "ply" on the first line: detected as OBJ unless forced */
    tt_scene *s = NULL;
    const char *text = "plyx\nformat ascii 1.0\n";
    EXPECT_ERR(ctx, tt_scene_load_memory(ctx, "bad.ply", "ply", text, strlen(text), &s), P, "bad.ply:1:", "not a PLY file");
}

static void check_ascii_body_errors(tt_context *ctx)
{
    const tt_status P = TT_ERR_PARSE;
    /* header lines 1-9; the body starts on line 10 */
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", P,
                    "a.ply:11:", "element vertex item 1, property y", "malformed number", "'x'");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n0 0 0\n1 0.5abc 0\n0 1 0\n3 0 1 2\n", P,
                    "a.ply:11:", "'0.5abc'");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n", P,
                    "a.ply:11:", "not a finite number");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n0 0 0\n1 0 -inf\n0 1 0\n3 0 1 2\n", P,
                    "a.ply:11:", "not a finite number");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n0 0 0\n1 0 1e40\n0 1 0\n3 0 1 2\n", P,
                    "a.ply:11:", "out of range");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "3 0 1 3\n", P, "a.ply:13:",
                    "element face item 0, property vertex_indices", "vertex index 3", "out of range");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "3 0 -1 2\n", P, "a.ply:13:",
                    "vertex index -1");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "2 0 1\n", P, "a.ply:13:",
                    "2 vertices, needs at least 3");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "300 0 1 2\n", P, "a.ply:13:",
                    "out of range", "uchar");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "3 0 1.5 2\n", P, "a.ply:13:",
                    "malformed integer", "'1.5'");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "4 0 1 2\n", P, "a.ply:13:",
                    "the line ends");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "3 0 1", P, "a.ply:13:",
                    "end of file");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", P,
                    "a.ply:11:", "property z", "the line ends");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", P,
                    "a.ply:10:", "more values");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "end_header\n" BODY3 "3 0 1 2\n9\n", P, "a.ply:14:",
                    "after the last element");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "element extra 1\nproperty list int float w\nend_header\n" BODY3 "3 0 1 2\n-1\n",
                    P, "a.ply:16:", "element extra item 0, property w", "list count -1 is negative");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "element extra 1\nproperty list int float w\nend_header\n" BODY3 "3 0 1 2\n2000000000 1 2\n",
                    P, "a.ply:16:", "the line ends");
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "element extra 1\nproperty float w\nend_header\n" BODY3 "3 0 1 2\n1.0.0\n",
                    P, "a.ply:16:", "malformed number");
    /* skipped float values may be nan; skipped integers must fit their type */
    tt_scene *s = NULL;
    const char *ok = HDR_ASCII VERT3 FACE1 "element extra 1\nproperty float w\nend_header\n" BODY3 "3 0 1 2\nnan\n";
    CHECK_OK(ctx, load_str(ctx, "a.ply", ok, &s));
    tt_scene_destroy(s);
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 FACE1 "element extra 1\nproperty char w\nend_header\n" BODY3 "3 0 1 2\n-129\n",
                    P, "a.ply:16:", "out of range", "char");
    /* an empty scene */
    EXPECT_LOAD_ERR(ctx, "a.ply", HDR_ASCII VERT3 "element face 0\nproperty list uchar int vertex_indices\nend_header\n" BODY3,
                    P, "a.ply", "no triangles");
    /* ... and blank lines between items, CRLF line ends and a zero-area triangle are fine */
    const char *crlf = "ply\r\nformat ascii 1.0\r\n" "element vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
                       "element face 2\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                       "0 0 0\r\n\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n3 0 0 0\r\n";
    s = NULL;
    CHECK_OK(ctx, load_str(ctx, "crlf.ply", crlf, &s));
    CHECK(s && tt_scene_triangle_count(s) == 2);
    tt_scene_destroy(s);
}

/* A binary little-endian file: header + body bytes. */
static void bin_header(buf *b, const char *extra_header)
{
    b->size = 0;
    buf_printf(b, "ply\nformat binary_little_endian 1.0\n" VERT3 FACE1 "%send_header\n", extra_header);
}

static tt_status load_buf(tt_context *ctx, const buf *b, tt_scene **s)
{
    return tt_scene_load_memory(ctx, "b.ply", NULL, b->data, b->size, s);
}

#define EXPECT_BUF_ERR(ctx, b, ...)                                                          \
    do {                                                                                     \
        tt_scene *s_ = (tt_scene *)1;                                                        \
        tt_status st_ = load_buf(ctx, b, &s_);                                               \
        CHECK(s_ == NULL);                                                                   \
        if (st_ == TT_OK) tt_scene_destroy(s_);                                              \
        EXPECT_ERR(ctx, st_, TT_ERR_PARSE, __VA_ARGS__);                                     \
    } while (0)

static void put_vertices(buf *b)
{
    static const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 9; i++) put(b, LE, "float", v[i]);
}

static void check_binary_errors(tt_context *ctx)
{
    buf b = {0};
    char where[64];
    bin_header(&b, "");
    size_t body = b.size;
    put_vertices(&b);
    put(&b, LE, "uchar", 3);
    put(&b, LE, "int", 0);
    put(&b, LE, "int", 1);
    put(&b, LE, "int", 2);
    tt_scene *s = NULL;
    CHECK_OK(ctx, load_buf(ctx, &b, &s)); /* the good file */
    tt_scene_destroy(s);
    size_t good = b.size;

    /* cut short: the header's size check refuses it at the end of the file */
    b.size = good - 2;
    snprintf(where, sizeof where, "b.ply: byte %zu:", good - 2);
    EXPECT_BUF_ERR(ctx, &b, where, "truncated", "element face (header line 7) declares 1 items");
    b.size = body + 13;
    snprintf(where, sizeof where, "b.ply: byte %zu:", body + 13);
    EXPECT_BUF_ERR(ctx, &b, where, "truncated", "element vertex", "the file has only 13");
    /* trailing bytes */
    b.size = good;
    put(&b, LE, "uchar", 0);
    snprintf(where, sizeof where, "b.ply: byte %zu:", good);
    EXPECT_BUF_ERR(ctx, &b, where, "after the last element");
    /* an index out of range */
    b.size = good - 4;
    put(&b, LE, "int", 3);
    snprintf(where, sizeof where, "b.ply: byte %zu:", good - 4);
    EXPECT_BUF_ERR(ctx, &b, where, "vertex index 3", "out of range");
    b.size = good - 4;
    put(&b, LE, "int", -1);
    EXPECT_BUF_ERR(ctx, &b, where, "vertex index -1");
    /* a face with 2 vertices */
    b.size = good - 13;
    put(&b, LE, "uchar", 2);
    snprintf(where, sizeof where, "b.ply: byte %zu:", good - 13);
    b.size = good; /* keep the length (the rest is now the trailing bytes) */
    EXPECT_BUF_ERR(ctx, &b, where, "2 vertices, needs at least 3");
    /* NaN and Inf coordinates */
    b.size = body + 4;
    put(&b, LE, "float", NAN);
    b.size = good;
    snprintf(where, sizeof where, "b.ply: byte %zu:", body + 4);
    EXPECT_BUF_ERR(ctx, &b, where, "element vertex item 0, property y", "not a finite number");
    b.size = body + 4;
    put(&b, LE, "float", 0);
    b.size = body + 32;
    put(&b, LE, "float", -INFINITY);
    b.size = good;
    snprintf(where, sizeof where, "b.ply: byte %zu:", body + 32);
    EXPECT_BUF_ERR(ctx, &b, where, "element vertex item 2, property z", "not a finite number");

    /* double coordinates beyond float range */
    b.size = 0;
    buf_printf(&b, "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n" FACE1 "end_header\n");
    body = b.size;
    for (int i = 0; i < 9; i++) put(&b, LE, "double", i == 4 ? 1e300 : 0.0);
    put(&b, LE, "uchar", 3);
    for (int i = 0; i < 3; i++) put(&b, LE, "int", i);
    snprintf(where, sizeof where, "b.ply: byte %zu:", body + 32);
    EXPECT_BUF_ERR(ctx, &b, where, "out of float range");

    /* cut inside a quad's last index: the body parser names the list */
    bin_header(&b, "");
    put_vertices(&b);
    size_t quad = b.size;
    put(&b, LE, "uchar", 4);
    for (int i = 0; i < 4; i++) put(&b, LE, "int", i % 3);
    b.size -= 2;
    snprintf(where, sizeof where, "b.ply: byte %zu:", quad);
    EXPECT_BUF_ERR(ctx, &b, where, "truncated: list count 4 needs 16 bytes, the file has 14 left",
                   "element face item 0, property vertex_indices");
    /* cut inside a scalar of a later element (the quad's extra index passes
     * the header's minimum-size check, so the body parser finds it) */
    bin_header(&b, "element tail 1\nproperty double d\n");
    put_vertices(&b);
    put(&b, LE, "uchar", 4);
    for (int i = 0; i < 4; i++) put(&b, LE, "int", i % 3);
    size_t tail = b.size;
    put(&b, LE, "double", 1.0);
    b.size -= 3;
    snprintf(where, sizeof where, "b.ply: byte %zu:", tail);
    EXPECT_BUF_ERR(ctx, &b, where, "element tail item 0, property d",
                   "truncated: the double value needs 8 bytes, the file has 5 left");

    /* a negative list count (signed count type) on a skipped list */
    bin_header(&b, "element extra 1\nproperty list int float w\n");
    put_vertices(&b);
    put(&b, LE, "uchar", 3);
    for (int i = 0; i < 3; i++) put(&b, LE, "int", i);
    size_t extra = b.size;
    put(&b, LE, "int", -2);
    snprintf(where, sizeof where, "b.ply: byte %zu:", extra);
    EXPECT_BUF_ERR(ctx, &b, where, "list count -2 is negative");
    /* a huge list count */
    b.size = extra;
    put(&b, LE, "int", 2000000000);
    put(&b, LE, "float", 1);
    EXPECT_BUF_ERR(ctx, &b, where, "truncated", "list count 2000000000");
    /* a huge face list count (uint) */
    bin_header(&b, "");
    b.size = 0;
    buf_printf(&b, "ply\nformat binary_little_endian 1.0\n" VERT3 "element face 1\nproperty list uint int vertex_indices\nend_header\n");
    put_vertices(&b);
    size_t face = b.size;
    put(&b, LE, "uint", 4294967295.0);
    for (int i = 0; i < 3; i++) put(&b, LE, "int", i);
    snprintf(where, sizeof where, "b.ply: byte %zu:", face);
    EXPECT_BUF_ERR(ctx, &b, where, "truncated", "list count 4294967295");
    /* float-typed indices must be integers */
    b.size = 0;
    buf_printf(&b, "ply\nformat binary_little_endian 1.0\n" VERT3 "element face 1\nproperty list uchar float vertex_indices\nend_header\n");
    put_vertices(&b);
    put(&b, LE, "uchar", 3);
    put(&b, LE, "float", 0);
    put(&b, LE, "float", 1.5);
    put(&b, LE, "float", 2);
    snprintf(where, sizeof where, "b.ply: byte %zu:", b.size - 8);
    EXPECT_BUF_ERR(ctx, &b, where, "vertex index 1.5 is not an integer");
    /* ascii: float-typed indices written as integers or as integral floats */
    const char *ascii_float_idx = HDR_ASCII VERT3 "element face 2\nproperty list float double vertex_indices\nend_header\n"
                                  BODY3 "3 0 1 2\n3.0 2e0 1.0 16777217\n";
    EXPECT_LOAD_ERR(ctx, "f.ply", ascii_float_idx, TT_ERR_PARSE, "f.ply:14:", "vertex index 16777217", "out of range");
    ascii_float_idx = HDR_ASCII VERT3 "element face 2\nproperty list float double vertex_indices\nend_header\n"
                      BODY3 "3 0 1 2\n3.0 2e0 1.0 0\n";
    s = NULL;
    CHECK_OK(ctx, load_str(ctx, "f.ply", ascii_float_idx, &s));
    static const float t1[9] = {0, 1, 0, 1, 0, 0, 0, 0, 0};
    CHECK(s && tt_scene_triangle_count(s) == 2 && triangle_is(s, 1, t1));
    tt_scene_destroy(s);
    EXPECT_LOAD_ERR(ctx, "f.ply", HDR_ASCII VERT3 "element face 1\nproperty list float double vertex_indices\nend_header\n"
                    BODY3 "3 0 1 1.25\n", TT_ERR_PARSE, "f.ply:13:", "vertex index 1.25 is not an integer");
    b.size -= 8;
    put(&b, LE, "float", 1);
    put(&b, LE, "float", 2);
    s = NULL;
    CHECK_OK(ctx, load_buf(ctx, &b, &s));
    CHECK(s && tt_scene_triangle_count(s) == 1);
    tt_scene_destroy(s);
    free(b.data);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    check_all_types(ctx);
    check_shipped_files(ctx);
    check_header_errors(ctx);
    check_ascii_body_errors(ctx);
    check_binary_errors(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
