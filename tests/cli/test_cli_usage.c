/* The CLI's help, version and usage errors: every bad command line exits 2
 * with one message on stderr naming the option and the bad value (and never
 * crashes); run-time failures exit 1 with the library's message. */
#include <string.h>

#include "check.h"
#include "cli_run.h"
#include "known_scene.h"

static void expect_status(int status, const char *must_contain, const char *args)
{
    tt_cli_result r;
    tt_cli_run(&r, "%s", args);
    CHECK_MSG(r.status == status, "treetrace %s: exit %d, expected %d (stderr: %s)", args, r.status,
              status, r.err);
    if (must_contain)
        CHECK_MSG(strstr(r.err, must_contain) != NULL, "treetrace %s: stderr lacks '%s': %s", args,
                  must_contain, r.err);
    if (status != 0) CHECK_MSG(r.out[0] == '\0', "treetrace %s printed results: %s", args, r.out);
    tt_cli_result_free(&r);
}

static void test_help_and_version(void)
{
    tt_cli_result r;
    CHECK(tt_cli_run(&r, "--version") == 0);
    CHECK(strncmp(r.out, "treetrace " TT_VERSION_STRING "\n", strlen(TT_VERSION_STRING) + 11) == 0);
    tt_cli_result_free(&r);

    const char *helps[] = {"--help", "-h", "help"};
    for (int i = 0; i < 3; i++) {
        CHECK(tt_cli_run(&r, "%s", helps[i]) == 0);
        CHECK(strstr(r.out, "usage: treetrace") && strstr(r.out, "render") && strstr(r.out, "info"));
        CHECK(strstr(r.out, "bruteforce") != NULL); /* the structures of the build */
        tt_cli_result_free(&r);
    }
    const char *cmd_helps[] = {"help render", "render --help", "render -h", "render --size 8x8 --help"};
    for (int i = 0; i < 4; i++) {
        CHECK(tt_cli_run(&r, "%s", cmd_helps[i]) == 0);
        CHECK_MSG(strstr(r.out, "usage: treetrace render") && strstr(r.out, "--heatmap-metric") &&
                      strstr(r.out, "--strategy") && strstr(r.out, "--kd-build"),
                  "%s: %s", cmd_helps[i], r.out);
        tt_cli_result_free(&r);
    }
    CHECK(tt_cli_run(&r, "help info") == 0);
    CHECK(strstr(r.out, "usage: treetrace info") != NULL);
    tt_cli_result_free(&r);
    CHECK(tt_cli_run(&r, "info --help") == 0);
    CHECK(strstr(r.out, "usage: treetrace info") != NULL);
    tt_cli_result_free(&r);
}

static void test_usage_errors(void)
{
    expect_status(2, "usage", "");
    expect_status(2, "'frobnicate'", "frobnicate");
    expect_status(2, "'--bogus'", "--bogus");
    expect_status(2, "'nope'", "help nope");
    expect_status(2, "'--bogus'", "render --bogus");
    expect_status(2, "'--bogus'", "info x.ply --bogus");
    expect_status(2, "--size", "render --size");
    expect_status(2, "--png", "render --png");
    expect_status(2, "--png", "render --png=");
    expect_status(2, "0x16", "render --size 0x16");
    expect_status(2, "16x0", "render --size 16x0");
    expect_status(2, "'16'", "render --size 16");
    expect_status(2, "'16x'", "render --size 16x");
    expect_status(2, "'-4x4'", "render --size -4x4");
    expect_status(2, "99999x4", "render --size 99999x4");
    expect_status(2, "'axb'", "render --size axb");
    expect_status(2, "--threads: -1", "render --threads -1");
    expect_status(2, "'1.5'", "render --threads 1.5");
    expect_status(2, "'two'", "render --threads two");
    expect_status(2, "99999999999999999999", "render --threads 99999999999999999999");
    expect_status(2, "--repeat: 0", "render --repeat 0");
    expect_status(2, "--fov: 0", "render --fov 0");
    expect_status(2, "180", "render --fov 180");
    expect_status(2, "--fov: -5", "render --fov -5");
    expect_status(2, "'nan'", "render --fov nan");
    expect_status(2, "'inf'", "render --fov inf");
    expect_status(2, "'1,2,inf'", "render --eye 1,2,inf --look 0,0,0");
    expect_status(2, "'nan,0,0'", "render --eye 0,0,1 --look nan,0,0");
    expect_status(2, "'1,2'", "render --eye 1,2 --look 0,0,0");
    expect_status(2, "'1,2,3,4'", "render --light 1,2,3,4");
    expect_status(2, "'1,,3'", "render --up 1,,3");
    expect_status(2, "'1e39,0,0'", "render --light 1e39,0,0");
    expect_status(2, "--up", "render --up 0,0,0");
    expect_status(2, "--look", "render --eye 1,1,1");
    expect_status(2, "--eye", "render --look 1,1,1");
    expect_status(2, "same point", "render --eye 1,1,1 --look 1,1,1");
    expect_status(2, "--view", "render --view a:b --eye 1,1,1 --look 0,0,0");
    expect_status(2, "--views", "render --views v.tsv");
    expect_status(2, "--heatmap", "render --heatmap-metric leaves");
    expect_status(2, "'depth'", "render --heatmap out.png --heatmap-metric depth");
    expect_status(2, "more than one scene", "render a.ply b.ply");
    expect_status(2, "'nosuch'", "render --accel nosuch");
    expect_status(2, "--traversal", "render --accel bruteforce --traversal stack");
    expect_status(2, "--strategy", "render --accel bruteforce --strategy rstar");
    expect_status(2, "--dmin", "render --accel bruteforce --dmin 3");
    expect_status(2, "--shadow-hint", "info x.ply --accel bruteforce --shadow-hint caster");
    expect_status(2, "--stats=1", "render --stats=1");
    expect_status(2, "SCENE", "info");
    expect_status(2, "more than one scene", "info a.ply b.ply");
    expect_status(2, "expected one command", "help render info");
}

/* Options of the structures, when they are in the build: values are
 * checked against the chosen --accel. */
static void test_structure_option_errors(void)
{
    if (tt_test_has_accel("rtree")) {
        expect_status(2, "'best'", "render --accel rtree --strategy best");
        expect_status(2, "--M: 17", "render --accel rtree --M 17");
        expect_status(2, "--m: 1", "render --accel rtree --m 1");
        expect_status(2, "--m 3", "render --accel rtree --m 3 --M 5");
        expect_status(2, "'maybe'", "render --accel rtree --reinsert maybe");
        expect_status(2, "--reinsert-fraction: 1.5", "render --accel rtree --reinsert-fraction 1.5");
        expect_status(2, "--reinsert-fraction: 0", "render --accel rtree --reinsert-fraction 0");
        expect_status(2, "--reinsert-fraction", "render --accel rtree --M 4 --reinsert-fraction 0.1");
        expect_status(2, "'near'", "render --accel rtree --reinsert-mode near");
        expect_status(2, "'linear'", "render --accel rtree --split linear");
        expect_status(2, "'htr'", "render --accel rtree --traversal htr");
        expect_status(2, "--dmin", "render --accel rtree --dmin 2");
        expect_status(2, "'quick'", "render --accel rtree --build quick");
        /* the insertion options with a bulk loader: refused, never ignored */
        expect_status(2, "--strategy applies to --build insert, not sah",
                      "render --build sah --strategy rstar");
        expect_status(2, "--reinsert applies to --build insert, not str",
                      "render --reinsert off --build str");
        expect_status(2, "--split applies to --build insert, not hilbert",
                      "render --accel rtree --build hilbert --split quadratic");
    }
    if (tt_test_has_accel("kdtree")) {
        expect_status(2, "'nlogn2'", "render --accel kdtree --kd-build nlogn2");
        expect_status(2, "--dmin: 0", "render --accel kdtree --dmin 0");
        expect_status(2, "--ct: -1", "render --accel kdtree --ct -1");
        expect_status(2, "'nan'", "render --accel kdtree --ci nan");
        expect_status(2, "--empty-bonus: 1", "render --accel kdtree --empty-bonus 1");
        expect_status(2, "--max-depth: -2", "render --accel kdtree --max-depth -2");
        expect_status(2, "'last'", "render --accel kdtree --shadow-hint last");
        expect_status(2, "--shadow-hint caster", "render --accel kdtree --shadow-hint caster");
        expect_status(2, "'stack'", "render --accel kdtree --traversal stack");
        expect_status(2, "--strategy", "render --accel kdtree --strategy rstar");
        expect_status(2, "--build", "render --accel kdtree --build sah");
    }
}

static void test_runtime_errors(void)
{
    char scene[512]; /* a copy: tt_cli_tmp's strings are reused */
    snprintf(scene, sizeof scene, "%s", tt_cli_tmp("known.ply"));
    CHECK(tt_known_write_ply(scene) == 0);
    char args[1024];
    expect_status(1, "/nonexistent/scene.ply", "render /nonexistent/scene.ply --accel bruteforce");
    expect_status(1, "/nonexistent/scene.ply", "info /nonexistent/scene.ply --accel bruteforce");
    snprintf(args, sizeof args, "render '%s' --accel bruteforce --size 8x8 --png /nonexistent/x.png",
             scene);
    expect_status(1, "/nonexistent/x.png", args);
    snprintf(args, sizeof args, "render '%s' --accel bruteforce --size 8x8 --hits /nonexistent/x.hits",
             scene);
    expect_status(1, "/nonexistent/x.hits", args);
    snprintf(args, sizeof args,
             "render '%s' --accel bruteforce --size 8x8 --heatmap /nonexistent/h.png", scene);
    expect_status(1, "/nonexistent/h.png", args);
    /* the view file beside the scene does not exist */
    snprintf(args, sizeof args, "render '%s' --accel bruteforce --size 8x8 --view known:main", scene);
    expect_status(1, "views.tsv", args);
    /* a garbage scene file */
    FILE *fp = fopen(tt_cli_tmp("garbage.ply"), "w");
    if (fp) {
        fputs("ply\nthis is not a header\n", fp);
        fclose(fp);
    }
    snprintf(args, sizeof args, "info '%s' --accel bruteforce", tt_cli_tmp("garbage.ply"));
    expect_status(1, "garbage.ply", args);
    if (!tt_test_has_accel("embree")) {
        snprintf(args, sizeof args, "info '%s' --accel embree", scene);
        expect_status(1, "embree", args);
    }
}

int main(void)
{
    test_help_and_version();
    test_usage_errors();
    test_structure_option_errors();
    test_runtime_errors();
    return tt_test_finish();
}
