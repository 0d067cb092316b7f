/* `mpirun -np 2 treetrace render` against one process: every shared view
 * (views.tsv) renders to the same PNG and hit buffer bytes with both tile
 * splits, with statistics (the same counts) and a heatmap, with a mapped
 * saved structure, and with --frames (the same files per frame); a rank
 * that cannot load its scene ends the job with that rank's message and a
 * non-zero status, not a hang. Skipped (77) in a build without MPI, where
 * instead the MPI option must say the build has none. */
#include <stdarg.h>
#include <stdio.h>
#include <sys/wait.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "cli_run.h"

#ifdef TT_BUILT_WITH_MPI
/* Under LeakSanitizer (the sanitized CI run) Open MPI's own process-lifetime
 * allocations, made in plugins it loads and unloads, cannot be attributed
 * or suppressed by name: leak checking is off for the ranks (ASan and UBSan
 * stay on); the same code paths are leak-checked by the one-process tests. */
#define MPIRUN "ASAN_OPTIONS=${ASAN_OPTIONS:-}${ASAN_OPTIONS:+:}detect_leaks=0 " TT_MPIEXEC \
               " -np 2 --oversubscribe --allow-run-as-root"

/* Runs a shell command with a time limit; returns its exit status. The
 * output goes to out.txt in the test's folder. */
static int shell(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static int shell(const char *fmt, ...)
{
    char cmd[8192], full[8600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    char script[1024];
    snprintf(script, sizeof script, "%s", tt_cli_tmp("cmd.sh"));
    FILE *f = fopen(script, "w");
    if (!f) return 127;
    fprintf(f, "%s\n", cmd);
    fclose(f);
    snprintf(full, sizeof full, "timeout 300 bash %s >%s 2>&1", script, tt_cli_tmp("out.txt"));
    int st = system(full);
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

static char *output(void)
{
    long n;
    return (char *)tt_test_read_file(tt_cli_tmp("out.txt"), &n);
}

static int same_file(const char *a, const char *b)
{
    long na = -1, nb = -2;
    unsigned char *x = tt_test_read_file(a, &na), *y = tt_test_read_file(b, &nb);
    int same = x && y && na == nb && memcmp(x, y, (size_t)na) == 0;
    free(x);
    free(y);
    return same;
}

static void one_view(const char *scene_file, const char *view, const char *extra)
{
    char scene[1024], one_png[1024], one_hits[1024];
    snprintf(scene, sizeof scene, "%s", tt_test_scene_path(scene_file));
    snprintf(one_png, sizeof one_png, "%s", tt_cli_tmp("one.png"));
    snprintf(one_hits, sizeof one_hits, "%s", tt_cli_tmp("one.hits"));
    int st = shell("%s render %s --view %s --size 96x72 --threads 1 --png %s --hits %s %s",
                   TT_CLI_PATH, scene, view, one_png, one_hits, extra);
    CHECK_MSG(st == 0, "one process, %s %s: status %d", view, extra, st);
    for (int split = 0; split < 2; split++) {
        const char *name = split ? "interleave" : "queue";
        st = shell("%s %s render %s --view %s --size 96x72 --threads 1 --png %s --hits %s "
                   "--mpi-split %s %s", MPIRUN, TT_CLI_PATH, scene, view, tt_cli_tmp("two.png"),
                   tt_cli_tmp("two.hits"), name, extra);
        char *out = output();
        CHECK_MSG(st == 0 && out && strstr(out, "mpi_ranks: 2"), "%s %s %s: status %d: %s",
                  view, name, extra, st, out ? out : "");
        free(out);
        CHECK_MSG(same_file(one_png, tt_cli_tmp("two.png")), "%s %s %s: PNG differs", view, name,
                  extra);
        CHECK_MSG(same_file(one_hits, tt_cli_tmp("two.hits")), "%s %s %s: hits differ", view,
                  name, extra);
    }
}

/* The counting statistics are the same numbers either way. */
static void same_stats(void)
{
    const char *scene = tt_test_scene_path("bun_zipper.ply");
    char one[4096] = "", *out;
    shell("%s render %s --view bunny:main --size 64x64 --stats --accel kdtree "
          "--heatmap %s", TT_CLI_PATH, scene, tt_cli_tmp("h1.png"));
    out = output();
    const char *p = out ? strstr(out, "primary_nodes_per_ray") : NULL;
    if (p) snprintf(one, sizeof one, "%.400s", p);
    free(out);
    shell("%s %s render %s --view bunny:main --size 64x64 --stats --accel kdtree --heatmap %s",
          MPIRUN, TT_CLI_PATH, scene, tt_cli_tmp("h2.png"));
    out = output();
    p = out ? strstr(out, "primary_nodes_per_ray") : NULL;
    CHECK_MSG(p && one[0] && strncmp(p, one, strcspn(one, "p") + 300) == 0,
              "statistics differ:\n%s\nvs\n%s", one, p ? p : "(none)");
    CHECK_MSG(same_file(tt_cli_tmp("h1.png"), tt_cli_tmp("h2.png")), "heatmaps differ");
    free(out);
}

static void frames(void)
{
    const char *scene = tt_test_scene_path("bun_zipper_res4.ply");
    int st = shell("%s render %s --view bunny_res4:main --size 48x48 --frames 3 --png %s",
                   TT_CLI_PATH, scene, tt_cli_tmp("f1.png"));
    CHECK(st == 0);
    st = shell("%s %s render %s --view bunny_res4:main --size 48x48 --frames 3 --png %s", MPIRUN,
               TT_CLI_PATH, scene, tt_cli_tmp("f2.png"));
    char *out = output();
    CHECK_MSG(st == 0 && out && strstr(out, "ranks: 2"), "frames: %s", out ? out : "");
    free(out);
    for (int k = 0; k < 3; k++) {
        char a[64], b[64], pa[1024];
        snprintf(a, sizeof a, "f1_%04d.png", k);
        snprintf(b, sizeof b, "f2_%04d.png", k);
        snprintf(pa, sizeof pa, "%s", tt_cli_tmp(a));
        CHECK_MSG(same_file(pa, tt_cli_tmp(b)), "frame %d differs", k);
    }
    /* frames differ from each other (the camera moves) */
    char p0[1024];
    snprintf(p0, sizeof p0, "%s", tt_cli_tmp("f1_0000.png"));
    CHECK(!same_file(p0, tt_cli_tmp("f1_0001.png")));
}

static void failing_rank(void)
{
    const char *scene = tt_test_scene_path("bun_zipper_res4.ply");
    int st = shell("%s sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then exec %s render "
                   "/nonexistent/missing.ply --size 16x16; else exec %s render %s --size "
                   "16x16; fi'", MPIRUN, TT_CLI_PATH, TT_CLI_PATH, scene);
    char *out = output();
    CHECK_MSG(st != 0 && st != 124, "a failing rank: status %d (124: it hung)", st);
    CHECK_MSG(out && strstr(out, "rank 1 of 2") && strstr(out, "/nonexistent/missing.ply"),
              "the failing rank's message is missing: %s", out ? out : "");
    free(out);
}

/* `treetrace bench` across ranks: the same runs and results (the columns
 * that are not timings) as one process, written once by rank 0. */
static void bench(void)
{
    const char *opts = "bench --only F3 --scene bunny_res4,cornell --size 32x32 --repeat 1 "
                       "--no-heatmaps --threads 1";
    char one[1024], two[1024];
    snprintf(one, sizeof one, "%s", tt_cli_tmp("bench1"));
    snprintf(two, sizeof two, "%s", tt_cli_tmp("bench2"));
    int st = shell("%s %s --scenes %s --out %s", TT_CLI_PATH, opts, TT_SCENES_DIR, one);
    CHECK(st == 0);
    st = shell("%s %s %s --scenes %s --out %s", MPIRUN, TT_CLI_PATH, opts, TT_SCENES_DIR, two);
    CHECK(st == 0);
    st = shell("cmp <(cut -d, -f1-5,8-13,20-23 %s/results.csv) <(cut -d, -f1-5,8-13,20-23 "
               "%s/results.csv) && [ $(wc -l < %s/results.csv) -eq 9 ]", one, two, two);
    char *out = output();
    CHECK_MSG(st == 0, "bench across ranks differs from one process: %s", out ? out : "");
    free(out);
}

static void saved_structure(void)
{
    const char *scene = tt_test_scene_path("sibenik.obj");
    const char *file = tt_cli_tmp("sibenik.tta");
    char path[1024];
    snprintf(path, sizeof path, "%s", file);
    int st = shell("%s build %s -o %s", TT_CLI_PATH, scene, path);
    CHECK(st == 0);
    char extra[1200];
    snprintf(extra, sizeof extra, "--accel-file %s", path);
    one_view("sibenik.obj", "sibenik:main", extra);
}
#endif

int main(void)
{
#ifndef TT_BUILT_WITH_MPI
    tt_cli_result r;
    int st = tt_cli_run(&r, "render --mpi-split queue --size 8x8");
    CHECK(st == 2 && strstr(r.err, "this build has no MPI"));
    tt_cli_result_free(&r);
    tt_test_finish();
    printf("skipped: this build has no MPI\n");
    return tt_test_failed ? 1 : 77;
#else
    static const char *const views[][2] = {
        {"bun_zipper.ply", "bunny:main"},         {"bun_zipper.ply", "bunny:side"},
        {"bun_zipper_res4.ply", "bunny_res4:main"}, {"cornell_box.obj", "cornell:main"},
        {"sibenik.obj", "sibenik:main"},          {"sibenik.obj", "sibenik:back"},
        {"conference.ply", "conference:main"},    {"conference.ply", "conference:corner"}};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) one_view(views[i][0], views[i][1], "");
    one_view("bun_zipper.ply", "bunny:side", "--accel kdtree --traversal sltr --no-shadows");
    same_stats();
    frames();
    failing_rank();
    saved_structure();
    bench();
    return tt_test_finish();
#endif
}
