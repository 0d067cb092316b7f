/* views.tsv: the shared file's views, light or no light, and every malformed
 * line refused with TT_ERR_PARSE naming the file and the line. */
#include "io_util.h"

#define HEADER "scene\tview\teye\tlook\tup\tfov_deg\tlight\n"

static tt_status find(tt_context *ctx, const char *text, const char *name, tt_camera *cam)
{
    return tt_view_find_memory(ctx, "v.tsv", text, strlen(text), name, cam);
}

static void check_shared(tt_context *ctx)
{
    tt_camera c;
    tt_test_view(ctx, "conference:main", &c);
    static const tt_camera want = {{-400, 380, -194}, {1200, 120, -194}, {0, 1, 0}, 60, {333, 550, -194}, 1};
    CHECK(memcmp(c.eye, want.eye, sizeof c.eye) == 0 && memcmp(c.look, want.look, sizeof c.look) == 0 &&
          memcmp(c.up, want.up, sizeof c.up) == 0 && c.fov_deg == 60.0f &&
          memcmp(c.light, want.light, sizeof c.light) == 0 && c.has_light == 1);
    tt_test_view(ctx, "cornell:main", &c);
    CHECK(c.fov_deg == 39.3f && c.light[2] == 279.6f && c.eye[2] == -800.0f);
    tt_test_view(ctx, "bunny:side", &c);
    CHECK(c.eye[0] == 0.22f && c.look[1] == 0.105f && c.light[1] == 0.18f);
    /* an unknown name lists what there is */
    tt_status st = tt_view_find(ctx, tt_test_scene_path("views.tsv"), "bunny:top", &c);
    EXPECT_ERR(ctx, st, TT_ERR_PARSE, "views.tsv", "no view bunny:top", "bunny:main", "conference:corner");
}

static void check_good(tt_context *ctx)
{
    tt_camera c;
    const char *text = HEADER
        "a\tone\t0,0,5\t0,0,0\t0,1,0\t45\t1,2,3\n"
        "\n"
        "a\ttwo\t0, 0, 5\t0,0,0\t0,1,0\t30.5\t\n"  /* empty light */
        "b\tone\t1,2,3\t4,5,6\t0,0,1\t90\r\n"     /* no light column, CRLF */
        "a:b\tc\t0,0,1\t0,0,0\t1,0,0\t10\t0,0,0\n";
    CHECK_OK(ctx, find(ctx, text, "a:one", &c));
    CHECK(c.has_light == 1 && c.light[0] == 1.0f && c.light[2] == 3.0f && c.fov_deg == 45.0f && c.eye[2] == 5.0f);
    CHECK_OK(ctx, find(ctx, text, "a:two", &c));
    CHECK(c.has_light == 0 && c.fov_deg == 30.5f);
    CHECK_OK(ctx, find(ctx, text, "b:one", &c));
    CHECK(c.has_light == 0 && c.fov_deg == 90.0f && c.look[2] == 6.0f && c.up[2] == 1.0f);
    /* a ':' inside a name: matched as a whole "scene:view" */
    CHECK_OK(ctx, find(ctx, text, "a:b:c", &c));
    CHECK(c.up[0] == 1.0f && c.has_light == 1);
    /* not SCENE:VIEW */
    EXPECT_ERR(ctx, find(ctx, text, "aone", &c), TT_ERR_INVALID_ARGUMENT, "v.tsv", "SCENE:VIEW");
    EXPECT_ERR(ctx, find(ctx, text, ":one", &c), TT_ERR_INVALID_ARGUMENT, "SCENE:VIEW");
    EXPECT_ERR(ctx, find(ctx, text, "a:", &c), TT_ERR_INVALID_ARGUMENT, "SCENE:VIEW");
    EXPECT_ERR(ctx, find(ctx, text, "a:three", &c), TT_ERR_PARSE, "v.tsv", "no view a:three",
               "available: a:one, a:two, b:one, a:b:c");
}

static void check_errors(tt_context *ctx)
{
    tt_camera c;
    const tt_status P = TT_ERR_PARSE;
    static const struct {
        const char *line;
        const char *needle;
    } bad[] = {
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\n", "5 tab-separated fields"},
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\t45\t1,2,3\textra\n", "more than 7 tab-separated fields"},
        {"a\tv\t0,0\t0,0,0\t0,1,0\t45\t1,2,3\n", "eye: expected three comma-separated numbers"},
        {"a\tv\t0,0,5,7\t0,0,0\t0,1,0\t45\t1,2,3\n", "eye: malformed number '5,7'"},
        {"a\tv\t0,0,5\t0,x,0\t0,1,0\t45\t1,2,3\n", "look: malformed number 'x'"},
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\t45deg\t1,2,3\n", "fov_deg: malformed number '45deg'"},
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\t45\t1,2,z\n", "light: malformed number 'z'"},
        {"a\tv\t0,nan,5\t0,0,0\t0,1,0\t45\t1,2,3\n", "eye: not a finite number 'nan'"},
        {"a\tv\t0,0,5\t0,0,0\t0,inf,0\t45\t1,2,3\n", "up: not a finite number"},
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\t1e39\t1,2,3\n", "fov_deg: number out of range"},
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\t0\t1,2,3\n", "fov_deg 0 is not in (0, 180)"},
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\t180\t1,2,3\n", "fov_deg 180 is not in (0, 180)"},
        {"a\tv\t0,0,5\t0,0,0\t0,1,0\t-10\t1,2,3\n", "not in (0, 180)"},
        {"a\tv\t0,0,5\t0,0,0\t0,0,0\t45\t1,2,3\n", "the up vector is zero"},
        {"a\tv\t1,2,3\t1,2,3\t0,1,0\t45\t1,2,3\n", "eye and look are the same point"},
        {"a\tv\t0,5,0\t0,0,0\t0,1,0\t45\t1,2,3\n", "parallel to the view direction"},
        {"\tv\t0,0,5\t0,0,0\t0,1,0\t45\t1,2,3\n", "empty scene or view name"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char text[512];
        /* line 3, after a good line: the whole file is checked, whichever view is asked for */
        snprintf(text, sizeof text, HEADER "ok\tv\t0,0,5\t0,0,0\t0,1,0\t45\t1,2,3\n%s", bad[i].line);
        EXPECT_ERR(ctx, find(ctx, text, "ok:v", &c), P, "v.tsv:3:", bad[i].needle);
    }
    EXPECT_ERR(ctx, find(ctx, "scene\tview\teye\n", "a:b", &c), P, "v.tsv:1:", "expected the header");
    EXPECT_ERR(ctx, find(ctx, "", "a:b", &c), P, "v.tsv", "empty");
    EXPECT_ERR(ctx, find(ctx, HEADER "a\tv\t0,0,5\t0,0,0\t0,1,0\t45\t1,2,3\n\na\tv\t0,0,5\t0,0,0\t0,1,0\t40\t1,2,3\n", "a:v", &c),
               P, "v.tsv:4:", "defined again", "line 2");
    EXPECT_ERR(ctx, tt_view_find(ctx, "/nonexistent/dir/views.tsv", "a:b", &c), TT_ERR_IO,
               "/nonexistent/dir/views.tsv", "cannot open");
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    check_good(ctx);
    check_errors(ctx);
    check_shared(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
