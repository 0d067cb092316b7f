/* OBJ loading per the conventions: v/f only, face vertex forms, negative
 * indices, fan order, ignored lines; and every malformed input refused with
 * TT_ERR_PARSE and a message naming the file, the line and the problem. */
#include "io_util.h"

static tt_scene *load_ok(tt_context *ctx, const char *text)
{
    tt_scene *s = NULL;
    tt_status st = load_str(ctx, "ok.obj", text, &s);
    CHECK_MSG(st == TT_OK && s, "%s: %s", tt_strerror(st), tt_context_last_error(ctx));
    return st == TT_OK ? s : NULL;
}

/* The triangles' vertex indices, flattened. */
static int indices_are(const tt_scene *s, const uint32_t *want, size_t triangles)
{
    if (!s || tt_scene_triangle_count(s) != triangles) return 0;
    for (size_t t = 0; t < triangles; t++) {
        float tri[9];
        tt_scene_triangle(s, t, tri);
        /* vertices are placed at (i, 0, 0) so a coordinate names its index */
        for (int k = 0; k < 3; k++)
            if (tri[3 * k] != (float)want[3 * t + k] || tri[3 * k + 1] != 0.0f) return 0;
    }
    return 1;
}

#define SIX_VERTICES "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 4 0 0\nv 5 0 0\n"

static void check_forms(tt_context *ctx)
{
    /* every face vertex form gives the same triangle */
    static const char *const forms[] = {
        SIX_VERTICES "f 1 2 3\n",          SIX_VERTICES "f 1/1 2/2 3/3\n",
        SIX_VERTICES "f 1/1/1 2/2/2 3/3/3\n", SIX_VERTICES "f 1//1 2//2 3//3\n",
        SIX_VERTICES "f -6 -5 -4\n",       SIX_VERTICES "f -6/1 2//-1 -4/-3/-2\n",
        SIX_VERTICES "f\t1   2\t\t3  \r\n", SIX_VERTICES "  f 1 2 3",
    };
    static const uint32_t want[] = {0, 1, 2};
    for (size_t i = 0; i < sizeof forms / sizeof forms[0]; i++) {
        tt_scene *s = load_ok(ctx, forms[i]);
        CHECK_MSG(indices_are(s, want, 1), "form %zu", i);
        tt_scene_destroy(s);
    }
}

static void check_negative_and_fans(tt_context *ctx)
{
    /* negative indices count back from the last vertex read so far */
    tt_scene *s = load_ok(ctx, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf -3 -2 -1\nv 3 0 0\nf -3 -2 -1\nf -1 -4 2\n");
    static const uint32_t neg[] = {0, 1, 2, 1, 2, 3, 3, 0, 1};
    CHECK(indices_are(s, neg, 3));
    tt_scene_destroy(s);
    /* fans (v0, vi, vi+1), in order, triangle ids in load order */
    s = load_ok(ctx, SIX_VERTICES "f 1 2 3 4 5 6\nf 6 5 4 3\nf 2 4 6\n");
    static const uint32_t fan[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 5, 4, 3, 5, 3, 2, 1, 3, 5};
    CHECK(indices_are(s, fan, 7));
    tt_scene_destroy(s);
}

static void check_ignored_lines(tt_context *ctx)
{
    const char *text =
        "# a comment\n"
        "mtllib x.mtl\n"
        "o object\n"
        "g group\n"
        "\n"
        "   \n"
        "v 0 0 0\n"
        "vn 0 0 1\n"
        "vt 0.5 0.5\n"
        "vp 1 2 3\n"
        "v 1 0 0 1.0\n"        /* w */
        "v 2 0 0 0.1 0.2 0.3\n" /* vertex colours */
        "usemtl m\n"
        "s off\n"
        "l 1 2\n"
        "p 1\n"
        "f 1/1/1 2/1/1 3/1/1\n"
        "vx is not a v line\n"
        "fo neither is this f\n"
        "f 1 2 3 # a trailing comment\n"
        "v 9 9 9 # another\n";
    tt_scene *s = load_ok(ctx, text);
    static const uint32_t want[] = {0, 1, 2, 0, 1, 2};
    CHECK(indices_are(s, want, 2));
    CHECK(s && tt_scene_vertex_count(s) == 4);
    tt_scene_destroy(s);
}

static void check_numbers_and_degenerate(tt_context *ctx)
{
    tt_scene *s = load_ok(ctx, "v +1.5 -.5 5.\nv 1e2 -2.5E-1 +3e+0\nv 0 0 0\nf 1 2 3\nf 1 1 1\n");
    float t[9];
    static const float want[9] = {1.5f, -0.5f, 5.0f, 100.0f, -0.25f, 3.0f, 0.0f, 0.0f, 0.0f};
    CHECK(s && tt_scene_triangle(s, 0, t) == TT_OK && memcmp(t, want, sizeof t) == 0);
    /* a zero-area triangle loads like any other */
    CHECK(s && tt_scene_triangle_count(s) == 2);
    tt_scene_destroy(s);
}

static void check_errors(tt_context *ctx)
{
    const tt_status P = TT_ERR_PARSE;
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 1 2 x\nf 1 1 1\n", P, "bad.obj:1:", "malformed number", "'x'", "vertex z");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 0 0 0\nv 1 2 3.5x\n", P, "bad.obj:2:", "malformed number", "'3.5x'");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 0 0 0\nv 1 2 3 w\n", P, "bad.obj:2:", "'w'");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 1 2\n", P, "bad.obj:1:", "2 coordinates, needs 3");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v\n", P, "bad.obj:1:", "0 coordinates");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "\n\nv nan 0 0\n", P, "bad.obj:3:", "not a finite number", "'nan'");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 0 inf 0\n", P, "bad.obj:1:", "not a finite number", "'inf'");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 0 0 -Infinity\n", P, "bad.obj:1:", "not a finite number");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 1e39 0 0\n", P, "bad.obj:1:", "out of range", "'1e39'");
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 0x10 0 0\n", P, "bad.obj:1:", "malformed");
    EXPECT_LOAD_ERR(ctx, "bad.obj", SIX_VERTICES "f 0 1 2\n", P, "bad.obj:7:", "index 0 is invalid");
    EXPECT_LOAD_ERR(ctx, "bad.obj", SIX_VERTICES "f 1 2 7\n", P, "bad.obj:7:", "face vertex 3", "index 7 is out of range", "6 vertices");
    EXPECT_LOAD_ERR(ctx, "bad.obj", SIX_VERTICES "f -1 -2 -7\n", P, "bad.obj:7:", "relative index -7 is out of range");
    /* a positive index must name a vertex already read */
    EXPECT_LOAD_ERR(ctx, "bad.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 2 0 0\n", P, "bad.obj:2:", "index 2 is out of range");
    EXPECT_LOAD_ERR(ctx, "bad.obj", SIX_VERTICES "f 1 2 99999999999999999999999\n", P, "bad.obj:7:", "index out of range");
    EXPECT_LOAD_ERR(ctx, "bad.obj", SIX_VERTICES "f 1 -9223372036854775808 3\n", P, "bad.obj:7:", "out of range");
    EXPECT_LOAD_ERR(ctx, "bad.obj", SIX_VERTICES "f 1 2\n", P, "bad.obj:7:", "2 vertices, needs at least 3");
    EXPECT_LOAD_ERR(ctx, "bad.obj", SIX_VERTICES "f\n", P, "bad.obj:7:", "0 vertices");
    static const char *const bad_forms[] = {"1/", "1/2/", "1//", "/1", "1/2/3/4", "1/x", "1//x", "a", "1.0", "1//2/"};
    for (size_t i = 0; i < sizeof bad_forms / sizeof bad_forms[0]; i++) {
        char text[256];
        snprintf(text, sizeof text, SIX_VERTICES "f 1 2 %s\n", bad_forms[i]);
        EXPECT_LOAD_ERR(ctx, "bad.obj", text, P, "bad.obj:7:", "face vertex 3", bad_forms[i]);
    }
    /* empty scenes */
    EXPECT_LOAD_ERR(ctx, "empty.obj", SIX_VERTICES, P, "empty.obj", "no triangles");
    EXPECT_LOAD_ERR(ctx, "empty.obj", "# nothing\n", P, "empty.obj", "no triangles");
    EXPECT_LOAD_ERR(ctx, "empty.obj", "", P, "empty.obj", "empty");
    /* a NUL byte inside a number */
    static const char nul[] = "v 1 2 3\0\nv 0 0 0\nv 1 1 1\nf 1 2 3\n";
    tt_scene *s = (tt_scene *)1;
    tt_status st = tt_scene_load_memory(ctx, "nul.obj", NULL, nul, sizeof nul - 1, &s);
    EXPECT_ERR(ctx, st, P, "nul.obj:1:", "malformed");
    CHECK(s == NULL);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    check_forms(ctx);
    check_negative_and_fans(ctx);
    check_ignored_lines(ctx);
    check_numbers_and_degenerate(ctx);
    check_errors(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
