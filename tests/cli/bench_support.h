/* Helpers of the `treetrace bench` tests: running the CLI and a tiny scenes
 * folder (bunny_res4 and cornell, copied from the shared scenes). Included by
 * the test programs (each test_*.c is its own program). */
#ifndef TT_TEST_BENCH_SUPPORT_H
#define TT_TEST_BENCH_SUPPORT_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"

/* Runs `treetrace bench ARGS` with stdout and stderr to LOG; returns its
 * exit status (-1 if it did not exit normally). */
static int run_bench(const char *args, const char *log)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "'%s' bench %s >'%s' 2>&1", TT_CLI_PATH, args, log);
    int st = system(cmd);
    if (st == -1 || !WIFEXITED(st)) return -1;
    return WEXITSTATUS(st);
}

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    if (buf) buf[n] = '\0';
    fclose(f);
    return buf;
}

static int copy_file(const char *from, const char *to)
{
    char *t = read_text(from);
    if (!t) return -1;
    FILE *f = fopen(to, "wb");
    int ok = f && fputs(t, f) >= 0;
    if (f && fclose(f) != 0) ok = 0;
    free(t);
    return ok ? 0 : -1;
}

/* A temporary folder with the two tiny scenes and their views; returns its
 * path (static storage). Skips the test (77) without the shared scenes. */
static const char *make_tiny_scenes(void)
{
    static char dir[] = "/tmp/tt_bench_scenes_XXXXXX";
    if (!mkdtemp(dir)) {
        fprintf(stderr, "mkdtemp failed\n");
        exit(1);
    }
    char to[512];
    const char *files[] = {"bun_zipper_res4.ply", "cornell_box.obj"};
    for (int i = 0; i < 2; i++) {
        snprintf(to, sizeof to, "%s/%s", dir, files[i]);
        if (copy_file(tt_test_scene_path(files[i]), to) != 0) {
            fprintf(stderr, "cannot copy %s\n", files[i]);
            exit(1);
        }
    }
    snprintf(to, sizeof to, "%s/scenes.tsv", dir);
    FILE *f = fopen(to, "w");
    if (!f) exit(1);
    fputs("name\tfile\ttriangles\n"
          "bunny_res4\tbun_zipper_res4.ply\t948\n"
          "cornell\tcornell_box.obj\t36\n",
          f);
    fclose(f);
    snprintf(to, sizeof to, "%s/views.tsv", dir);
    f = fopen(to, "w");
    if (!f) exit(1);
    fputs("scene\tview\teye\tlook\tup\tfov_deg\tlight\n"
          "bunny_res4\tmain\t-0.0168,0.108,0.28\t-0.0168,0.108,-0.0015\t0,1,0\t40\t"
          "-0.0168,0.18,0.05\n"
          "cornell\tmain\t278,273,-800\t278,273,0\t0,1,0\t39.3\t278,500,279.6\n",
          f);
    fclose(f);
    return dir;
}

static void remove_tree(const char *dir)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
}

#endif
