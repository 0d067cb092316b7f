/* Memory and time bombs: inputs that claim far more than they hold, or that
 * make a naive parser allocate or loop far beyond the input's size. Each is
 * refused with a parse error naming the cause (or, when it is a legal file,
 * loaded) with a peak of allocated bytes bounded by a small multiple of the
 * file's size, and in time roughly linear in it.
 *
 * The bound: a legal input may cost what its content justifies (an OBJ face
 * vertex "1 " of 2 bytes is one more triangle: 48 bytes of indices and
 * vertex copies, plus growth slack); a refused input must be refused before
 * any allocation sized by its claims. */
#include <stdarg.h>
#include <string.h>

#include "core/context.h" /* tt_now */
#include "check.h"

typedef struct peak_alloc {
    size_t live, peak;
} peak_alloc;

#define HEADER 16

static void *p_alloc(void *user, size_t size)
{
    peak_alloc *a = user;
    if (size > SIZE_MAX - HEADER) return NULL;
    unsigned char *p = malloc(size + HEADER);
    if (!p) return NULL;
    memcpy(p, &size, sizeof size);
    a->live += size;
    if (a->live > a->peak) a->peak = a->live;
    return p + HEADER;
}

static void p_free(void *user, void *ptr)
{
    peak_alloc *a = user;
    if (!ptr) return;
    unsigned char *p = (unsigned char *)ptr - HEADER;
    size_t size;
    memcpy(&size, p, sizeof size);
    a->live -= size;
    free(p);
}

static void *p_realloc(void *user, void *ptr, size_t size)
{
    if (!ptr) return p_alloc(user, size);
    void *q = p_alloc(user, size);
    if (!q) return NULL;
    size_t old;
    memcpy(&old, (unsigned char *)ptr - HEADER, sizeof old);
    memcpy(q, ptr, old < size ? old : size);
    p_free(user, ptr);
    return q;
}

static peak_alloc A;
static tt_context *ctx;

/* A growable input. */
typedef struct input {
    char *data;
    size_t size, cap;
} input;

static void put(input *in, const void *p, size_t n)
{
    if (in->size + n > in->cap) {
        in->cap = 2 * (in->size + n) + 4096;
        in->data = realloc(in->data, in->cap);
        if (!in->data) exit(1);
    }
    memcpy(in->data + in->size, p, n);
    in->size += n;
}

static void puts_(input *in, const char *s) { put(in, s, strlen(s)); }

static void putf(input *in, const char *fmt, ...)
{
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    put(in, line, (size_t)n);
}

static void repeat(input *in, const char *s, size_t times)
{
    for (size_t i = 0; i < times; i++) puts_(in, s);
}

/* Loads the input; `want` TT_OK or the expected error with a needle in the
 * message. The peak must stay within per_byte * size + slack bytes, and the
 * load must take less than max_s seconds (generous: the point is to catch
 * quadratic behaviour, which costs minutes here). Returns the scene's
 * triangle count (0 on an error). */
static size_t expect(const char *what, const input *in, tt_status want, const char *needle,
                     double per_byte, size_t slack, double max_s)
{
    tt_scene *s = NULL;
    size_t before = A.live;
    A.peak = A.live;
    double t0 = tt_now();
    tt_status st = tt_scene_load_memory(ctx, what, NULL, in->data, in->size, &s);
    double dt = tt_now() - t0;
    size_t peak = A.peak - before;
    size_t bound = (size_t)(per_byte * (double)in->size) + slack;
    CHECK_MSG(st == want, "%s: expected %s, got %s: %s", what, tt_strerror(want), tt_strerror(st),
              tt_context_last_error(ctx));
    if (st != TT_OK && needle)
        CHECK_MSG(strstr(tt_context_last_error(ctx), needle) && strstr(tt_context_last_error(ctx), what),
                  "%s: the message \"%s\" lacks \"%s\" or the name", what, tt_context_last_error(ctx),
                  needle);
    CHECK_MSG(strlen(tt_context_last_error(ctx)) < 400, "%s: a %zu-byte message", what,
              strlen(tt_context_last_error(ctx)));
    CHECK_MSG(peak <= bound, "%s: %zu bytes allocated at the peak for a %zu-byte input (bound %zu)",
              what, peak, in->size, bound);
    CHECK_MSG(dt < max_s, "%s: %.2f s for a %zu-byte input", what, dt, in->size);
    size_t n = st == TT_OK ? tt_scene_triangle_count(s) : 0;
    tt_scene_destroy(s);
    CHECK_MSG(A.live == before, "%s: %zu bytes leaked", what, A.live - before);
    printf("%-44s %9zu bytes in, %9zu bytes peak, %.3f s: %s\n", what, in->size, peak, dt,
           st == TT_OK ? "loaded" : tt_context_last_error(ctx));
    return n;
}

static const char *const ply_vertex3 =
    "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
static const char *const ply_face =
    "element face 1\nproperty list uchar int vertex_indices\n";

/* Headers claiming billions of items that the file cannot hold. */
static void claimed_counts(void)
{
    static const char *const formats[3] = {"ascii", "binary_little_endian", "binary_big_endian"};
    for (int f = 0; f < 3; f++) {
        char name[64];
        input in = {0};
        putf(&in, "ply\nformat %s 1.0\nelement vertex 4000000000\nproperty float x\n"
                  "property float y\nproperty float z\n%send_header\n0 0 0\n",
             formats[f], ply_face);
        snprintf(name, sizeof name, "4e9-vertices-%s.ply", formats[f]);
        expect(name, &in, TT_ERR_PARSE, "truncated", 0.0, 65536, 2.0);
        in.size = 0;
        putf(&in, "ply\nformat %s 1.0\n%selement face 3000000000\n"
                  "property list uint uint vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n",
             formats[f], ply_vertex3);
        snprintf(name, sizeof name, "3e9-faces-%s.ply", formats[f]);
        expect(name, &in, TT_ERR_PARSE, "truncated", 0.0, 65536, 2.0);
        in.size = 0;
        putf(&in, "ply\nformat %s 1.0\n%s%selement junk 9223372036854775807\n"
                  "property list int int a\nend_header\n",
             formats[f], ply_vertex3, ply_face);
        snprintf(name, sizeof name, "2^63-junk-%s.ply", formats[f]);
        expect(name, &in, TT_ERR_PARSE, "truncated", 0.0, 65536, 2.0);
        free(in.data);
    }
}

/* One face claiming a huge vertex count in a small file. */
static void huge_face(void)
{
    input in = {0};
    /* binary: a uint count of 4e9 */
    putf(&in, "ply\nformat binary_little_endian 1.0\n%selement face 1\n"
              "property list uint int vertex_indices\nend_header\n", ply_vertex3);
    float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    put(&in, v, sizeof v);
    uint32_t count = 4000000000u;
    int32_t idx[3] = {0, 1, 2};
    put(&in, &count, sizeof count);
    put(&in, idx, sizeof idx);
    expect("huge-face-binary.ply", &in, TT_ERR_PARSE, "list count", 0.0, 65536, 2.0);
    /* ascii: a count of 2^31 - 1, then three indices */
    in.size = 0;
    putf(&in, "ply\nformat ascii 1.0\n%selement face 1\nproperty list int int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n2147483647 0 1 2\n", ply_vertex3);
    expect("huge-face-ascii.ply", &in, TT_ERR_PARSE, "face", 0.0, 65536, 2.0);
    /* a float-typed count far past any integer */
    in.size = 0;
    putf(&in, "ply\nformat ascii 1.0\n%selement face 1\nproperty list float int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n1e30 0 1 2\n", ply_vertex3);
    expect("float-count.ply", &in, TT_ERR_PARSE, "not an integer", 0.0, 65536, 2.0);
    /* a legal OBJ face with a million vertices: a million triangles, and
     * the memory they justify */
    in.size = 0;
    puts_(&in, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    repeat(&in, " 1 2 3", 333334);
    puts_(&in, "\n");
    size_t n = expect("million-vertex-face.obj", &in, TT_OK, NULL, 64.0, 1 << 20, 10.0);
    CHECK(n == 1000000);
    free(in.data);
}

/* Enormous single lines. */
static void long_lines(void)
{
    input in = {0};
    puts_(&in, "# ");
    repeat(&in, "comment ", 2u << 20);
    puts_(&in, "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(expect("16MB-comment.obj", &in, TT_OK, NULL, 0.0, 1 << 20, 10.0) == 1);
    in.size = 0;
    puts_(&in, "v 0 0 0");
    repeat(&in, " 0.5", 1u << 20); /* extra values: checked, ignored */
    puts_(&in, "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(expect("million-value-vertex.obj", &in, TT_OK, NULL, 0.0, 1 << 20, 10.0) == 1);
    in.size = 0;
    puts_(&in, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 ");
    repeat(&in, "9", 4u << 20);
    puts_(&in, "\n");
    expect("4M-digit-index.obj", &in, TT_ERR_PARSE, "out of range", 0.0, 1 << 20, 10.0);
    in.size = 0;
    puts_(&in, "v 0.");
    repeat(&in, "0", 4u << 20);
    puts_(&in, "1e4194305 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(expect("4M-digit-coordinate.obj", &in, TT_OK, NULL, 0.0, 1 << 20, 10.0) == 1);
    in.size = 0;
    puts_(&in, "ply\nformat ascii 1.0\ncomment ");
    repeat(&in, "x", 8u << 20);
    putf(&in, "\n%s%send_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ply_vertex3, ply_face);
    CHECK(expect("8MB-header-comment.ply", &in, TT_OK, NULL, 0.0, 1 << 20, 10.0) == 1);

    /* views.tsv: one enormous field */
    in.size = 0;
    puts_(&in, "scene\tview\teye\tlook\tup\tfov_deg\tlight\ns\tv\t0,0,");
    repeat(&in, "5", 8u << 20);
    puts_(&in, "\t0,0,0\t0,1,0\t45\t\n");
    tt_camera cam;
    size_t before = A.live;
    A.peak = A.live;
    double t0 = tt_now();
    tt_status st = tt_view_find_memory(ctx, "long.tsv", in.data, in.size, "s:v", &cam);
    double dt = tt_now() - t0;
    CHECK_MSG(st == TT_ERR_PARSE && strstr(tt_context_last_error(ctx), "long.tsv:2"),
              "8 MB view field: %s: %s", tt_strerror(st), tt_context_last_error(ctx));
    CHECK(strlen(tt_context_last_error(ctx)) < 400);
    CHECK(A.peak - before < (1u << 20));
    CHECK_MSG(dt < 10.0, "8 MB view field: %.2f s", dt);
    printf("%-44s %9zu bytes in, %9zu bytes peak, %.3f s: %s\n", "8MB-field.tsv", in.size,
           A.peak - before, dt, tt_context_last_error(ctx));
    free(in.data);
}

/* Headers of many names: each element and property name is checked
 * against the others (a second "x" is an error), which must not cost the
 * square of their number. */
static void many_names(void)
{
    input in = {0};
    puts_(&in, "ply\nformat binary_little_endian 1.0\nelement vertex 3\n");
    puts_(&in, "property float x\nproperty float y\nproperty float z\n");
    for (int i = 0; i < 200000; i++) putf(&in, "property uchar p%d\n", i);
    puts_(&in, ply_face);
    puts_(&in, "end_header\n");
    expect("200k-properties.ply", &in, TT_ERR_PARSE, "truncated", 64.0, 1 << 20, 5.0);
    in.size = 0;
    puts_(&in, "ply\nformat ascii 1.0\n");
    for (int i = 0; i < 100000; i++) putf(&in, "element e%d 0\n", i);
    putf(&in, "%s%send_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ply_vertex3, ply_face);
    CHECK(expect("100k-elements.ply", &in, TT_OK, NULL, 64.0, 1 << 20, 5.0) == 1);
    /* and the duplicate checks still work at that size */
    in.size = 0;
    puts_(&in, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n");
    for (int i = 0; i < 50000; i++) putf(&in, "property uchar p%d\n", i);
    puts_(&in, "property uchar p31337\nproperty float z\n");
    expect("duplicate-property.ply", &in, TT_ERR_PARSE, "a second property 'p31337'", 64.0, 1 << 20, 5.0);
    in.size = 0;
    puts_(&in, "ply\nformat ascii 1.0\n");
    for (int i = 0; i < 50000; i++) putf(&in, "element e%d 0\n", i);
    puts_(&in, "element e4242 1\n");
    expect("duplicate-element.ply", &in, TT_ERR_PARSE, "a second element 'e4242' (first on line 4245)",
           64.0, 1 << 20, 5.0);
    /* the same name as an element and as a property of different elements */
    in.size = 0;
    putf(&in, "ply\nformat ascii 1.0\nelement x 0\nproperty float x\n%s%selement y 0\n"
              "property float x\nproperty float y\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         ply_vertex3, ply_face);
    CHECK(expect("shared-names.ply", &in, TT_OK, NULL, 64.0, 1 << 20, 5.0) == 1);
    free(in.data);
}

int main(void)
{
    tt_context_options o;
    tt_context_options_default(&o);
    o.allocator.alloc = p_alloc;
    o.allocator.realloc = p_realloc;
    o.allocator.free = p_free;
    o.allocator.user = &A;
    REQUIRE_OK(ctx, tt_context_create(&o, &ctx));
    claimed_counts();
    huge_face();
    long_lines();
    many_names();
    tt_context_destroy(ctx);
    CHECK(A.live == 0);
    return tt_test_finish();
}
