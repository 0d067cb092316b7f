#include "common.h"

#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"

static int readable(const char *path) { return access(path, R_OK) == 0; }

int cli_default_scene(const char *cmd, char *buf, size_t size)
{
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    char tried[2][4200];
    int tries = 0;
    if (n > 0) {
        exe[n] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash) *slash = '\0';
        snprintf(tried[tries], sizeof tried[0], "%s/../data/bunny.ply", exe);
        tries++;
    }
#ifdef TT_SOURCE_DIR
    snprintf(tried[tries], sizeof tried[0], "%s/data/bunny.ply", TT_SOURCE_DIR);
    tries++;
#endif
    for (int i = 0; i < tries; i++) {
        if (readable(tried[i]) && strlen(tried[i]) < size) {
            strcpy(buf, tried[i]);
            return 0;
        }
    }
    fprintf(stderr, "treetrace %s: no SCENE given and the default scene data/bunny.ply is not "
                    "found", cmd);
    for (int i = 0; i < tries; i++) fprintf(stderr, "%s %s", i ? "," : " (looked at", tried[i]);
    fprintf(stderr, "%s\n", tries ? ")" : "");
    return -1;
}

void cli_views_beside(const char *scene, char *buf, size_t size)
{
    const char *slash = strrchr(scene, '/');
    if (!slash) {
        snprintf(buf, size, "views.tsv");
        return;
    }
    snprintf(buf, size, "%.*s/views.tsv", (int)(slash - scene), scene);
}

int cli_runtime_error(const char *cmd, const tt_context *ctx)
{
    fprintf(stderr, "treetrace %s: %s\n", cmd, tt_context_last_error(ctx));
    return CLI_RUNTIME;
}

int cli_load_and_build(const char *cmd, tt_context *ctx, const char *path,
                       const tt_build_options *build, tt_scene **scene, double *load_s,
                       tt_accel **accel)
{
    struct timespec t0, t1;
    *scene = NULL;
    *accel = NULL;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (tt_scene_load(ctx, path, scene) != TT_OK) return cli_runtime_error(cmd, ctx);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    *load_s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    if (tt_accel_build(ctx, *scene, build, accel) != TT_OK) {
        int st = cli_runtime_error(cmd, ctx);
        tt_scene_destroy(*scene);
        *scene = NULL;
        return st;
    }
    return CLI_OK;
}

double cli_peak_rss_mb(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
    return (double)ru.ru_maxrss / 1024.0; /* Linux reports KiB */
}
