/* tt_scene_load from files and memory: I/O errors, format selection, the
 * same scene either way, error messages naming the path; allocation failure
 * at every allocation (reported, nothing leaked); and bounded memory for
 * hostile inputs (huge declared counts, one enormous line). */
#include <sys/stat.h>
#include <unistd.h>

#include "io_util.h"

static const char *const quad_obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
static const char *const quad_ply =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";

static void write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, size, f) != size) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
    fclose(f);
}

static int same_scene(const tt_scene *a, const tt_scene *b)
{
    if (!a || !b || tt_scene_triangle_count(a) != tt_scene_triangle_count(b) ||
        tt_scene_vertex_count(a) != tt_scene_vertex_count(b))
        return 0;
    for (size_t t = 0; t < tt_scene_triangle_count(a); t++) {
        float x[9], y[9];
        tt_scene_triangle(a, t, x);
        tt_scene_triangle(b, t, y);
        if (memcmp(x, y, sizeof x)) return 0;
    }
    return 1;
}

static void check_files(tt_context *ctx, const char *dir)
{
    char path[4096];
    tt_scene *s = (tt_scene *)1, *m = NULL;
    EXPECT_ERR(ctx, tt_scene_load(ctx, "/nonexistent/dir/scene.obj", &s), TT_ERR_IO,
               "/nonexistent/dir/scene.obj", "cannot open", "No such file");
    CHECK(s == NULL);
    EXPECT_ERR(ctx, tt_scene_load(ctx, dir, &s), TT_ERR_IO, dir);
    /* an unreadable file (unless we run as root, who can read anything) */
    snprintf(path, sizeof path, "%s/locked.obj", dir);
    write_file(path, quad_obj, strlen(quad_obj));
    chmod(path, 0);
    if (access(path, R_OK) != 0)
        EXPECT_ERR(ctx, tt_scene_load(ctx, path, &s), TT_ERR_IO, path, "Permission denied");
    unlink(path);

    /* by file and from memory: the same scene, detected by content whatever the name */
    static const char *const names[] = {"quad.obj", "quad.ply", "quad_ply_named.obj", "quad_obj_named.ply"};
    static const int is_ply[] = {0, 1, 1, 0};
    for (int i = 0; i < 4; i++) {
        const char *text = is_ply[i] ? quad_ply : quad_obj;
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        write_file(path, text, strlen(text));
        s = NULL;
        m = NULL;
        CHECK_OK(ctx, tt_scene_load(ctx, path, &s));
        CHECK_OK(ctx, tt_scene_load_memory(ctx, names[i], NULL, text, strlen(text), &m));
        CHECK_MSG(same_scene(s, m) && tt_scene_triangle_count(s) == 2, "%s", names[i]);
        tt_scene_destroy(s);
        tt_scene_destroy(m);
        unlink(path);
    }
    /* an error in a file names its path and line */
    snprintf(path, sizeof path, "%s/broken.obj", dir);
    const char *broken = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n";
    write_file(path, broken, strlen(broken));
    char want[4200];
    snprintf(want, sizeof want, "%s:4:", path);
    EXPECT_ERR(ctx, tt_scene_load(ctx, path, &s), TT_ERR_PARSE, want, "index 4 is out of range");
    unlink(path);
    /* an empty file */
    snprintf(path, sizeof path, "%s/empty.ply", dir);
    write_file(path, "", 0);
    EXPECT_ERR(ctx, tt_scene_load(ctx, path, &s), TT_ERR_PARSE, path, "empty");
    unlink(path);
}

static void check_format_argument(tt_context *ctx)
{
    tt_scene *s = NULL;
    CHECK_OK(ctx, tt_scene_load_memory(ctx, "q", "obj", quad_obj, strlen(quad_obj), &s));
    tt_scene_destroy(s);
    CHECK_OK(ctx, tt_scene_load_memory(ctx, "q", "ply", quad_ply, strlen(quad_ply), &s));
    tt_scene_destroy(s);
    /* a PLY forced to be read as OBJ: its lines are not v/f lines, so no triangles */
    EXPECT_ERR(ctx, tt_scene_load_memory(ctx, "q", "obj", quad_ply, strlen(quad_ply), &s), TT_ERR_PARSE,
               "no triangles");
    EXPECT_ERR(ctx, tt_scene_load_memory(ctx, "q", "ply", quad_obj, strlen(quad_obj), &s), TT_ERR_PARSE,
               "q:1:", "not a PLY file");
    EXPECT_ERR(ctx, tt_scene_load_memory(ctx, "q", "stl", quad_obj, strlen(quad_obj), &s),
               TT_ERR_INVALID_ARGUMENT, "unknown format", "stl");
    EXPECT_ERR(ctx, tt_scene_load_memory(ctx, "q", NULL, NULL, 5, &s), TT_ERR_INVALID_ARGUMENT, "NULL");
    CHECK(tt_scene_load_memory(ctx, "q", NULL, quad_obj, strlen(quad_obj), NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_scene_load_memory(NULL, "q", NULL, quad_obj, strlen(quad_obj), &s) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_scene_load(ctx, NULL, &s) == TT_ERR_INVALID_ARGUMENT);
}

/* Fails the 1st, 2nd, ... allocation until the load succeeds: each failure
 * must be TT_ERR_OUT_OF_MEMORY and leave nothing allocated. */
static void check_out_of_memory(const char *dir)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/oom.ply", dir);
    write_file(path, quad_ply, strlen(quad_ply));
    for (int kind = 0; kind < 3; kind++) {
        int succeeded = 0;
        for (long n = 0; n < 100 && !succeeded; n++) {
            counting_alloc a;
            tt_context *ctx = counting_context(&a);
            a.fail_after = a.allocations + n;
            tt_scene *s = NULL;
            tt_status st = kind == 0   ? load_str(ctx, "q.obj", quad_obj, &s)
                           : kind == 1 ? load_str(ctx, "q.ply", quad_ply, &s)
                                       : tt_scene_load(ctx, path, &s);
            if (st == TT_OK) {
                succeeded = 1;
                CHECK(tt_scene_triangle_count(s) == 2);
                tt_scene_destroy(s);
            } else {
                CHECK_MSG(st == TT_ERR_OUT_OF_MEMORY && strstr(tt_context_last_error(ctx), "out of memory"),
                          "kind %d, failing allocation %ld: %s", kind, n, tt_context_last_error(ctx));
                CHECK(s == NULL);
            }
            CHECK_MSG(a.live_blocks == 1, "kind %d, failing allocation %ld: %ld blocks left", kind, n,
                      a.live_blocks - 1); /* the context itself */
            tt_context_destroy(ctx);
        }
        CHECK_MSG(succeeded, "kind %d never succeeded", kind);
    }
    unlink(path);
}

/* Declared counts far beyond the file are refused before allocating, and an
 * enormous single line costs no more than the file itself. */
static void check_bounded_memory(void)
{
    counting_alloc a;
    tt_context *ctx = counting_context(&a);
    static const char *const bombs[] = {
        "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0123456789",
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1000000000000\nproperty list uchar int vertex_indices\nend_header\n0123456789",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 18446744073709551\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
        "element face 1\nproperty list uchar int vertex_indices\nelement junk 9223372036854775807\nproperty list int int a\nend_header\n",
    };
    for (size_t i = 0; i < sizeof bombs / sizeof bombs[0]; i++) {
        a.peak_bytes = a.live_bytes;
        tt_scene *s = NULL;
        EXPECT_ERR(ctx, load_str(ctx, "bomb.ply", bombs[i], &s), TT_ERR_PARSE, "bomb.ply", "truncated");
        CHECK_MSG(a.peak_bytes - a.live_bytes < 4096, "bomb %zu allocated %zu bytes", i,
                  a.peak_bytes - a.live_bytes);
    }
    /* a zero-property element may declare any count: it takes no bytes */
    const char *empty_el = "ply\nformat ascii 1.0\nelement nothing 18446744073709551\nelement vertex 3\n"
                           "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                           "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    tt_scene *s = NULL;
    CHECK_OK(ctx, load_str(ctx, "empty_el.ply", empty_el, &s));
    tt_scene_destroy(s);

    /* one 8 MB line: a comment, then a vertex with 4 MB of spaces */
    size_t n = 8u << 20;
    char *big = malloc(n + 64);
    memset(big, ' ', n);
    memcpy(big, "# ", 2);
    big[n / 2] = '\n';
    memcpy(big + n / 2 + 1, "v 1", 3);
    strcpy(big + n, "2 3\nv 0 0 0\nv 1 1 1\nf 1 2 3\n");
    size_t before = a.live_bytes;
    a.peak_bytes = before;
    CHECK_OK(ctx, tt_scene_load_memory(ctx, "big.obj", NULL, big, strlen(big), &s));
    CHECK(s && tt_scene_triangle_count(s) == 1);
    CHECK_MSG(a.peak_bytes - before < (1u << 20), "a long line cost %zu bytes", a.peak_bytes - before);
    tt_scene_destroy(s);
    /* the same as one enormous malformed number */
    memset(big, '1', n);
    memcpy(big, "v ", 2);
    strcpy(big + n, "x 2 3\nf 1 1 1\n");
    a.peak_bytes = a.live_bytes;
    EXPECT_ERR(ctx, tt_scene_load_memory(ctx, "big.obj", NULL, big, strlen(big), &s), TT_ERR_PARSE,
               "big.obj:1:", "malformed number", "...");
    CHECK(strlen(tt_context_last_error(ctx)) < 200);
    CHECK(a.peak_bytes - a.live_bytes < (1u << 20));
    free(big);
    tt_context_destroy(ctx);
}

int main(void)
{
    char dir[] = "/tmp/tt_test_load_XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    tt_context *ctx = tt_test_context();
    check_files(ctx, dir);
    check_format_argument(ctx);
    tt_context_destroy(ctx);
    check_out_of_memory(dir);
    check_bounded_memory();
    rmdir(dir);
    return tt_test_finish();
}
