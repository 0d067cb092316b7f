#include "check.h"

#include <string.h>
#include <unistd.h>

int tt_test_passed, tt_test_failed;

int tt_test_finish(void)
{
    printf("%d passed, %d failed\n", tt_test_passed, tt_test_failed);
    return tt_test_failed ? 1 : 0;
}

tt_context *tt_test_context(void)
{
    tt_context *ctx = NULL;
    if (tt_context_create(NULL, &ctx) != TT_OK) {
        fprintf(stderr, "cannot create a context\n");
        exit(1);
    }
    return ctx;
}

const char *tt_test_scene_path(const char *file)
{
    static char path[4][4096];
    static int slot;
    char *p = path[slot++ & 3];
    snprintf(p, sizeof path[0], "%s/%s", TT_SCENES_DIR, file);
    if (access(p, R_OK) != 0) {
        printf("skipped: shared scene %s is not present (set TT_SCENES_DIR)\n", p);
        exit(77);
    }
    return p;
}

tt_scene *tt_test_load_scene(tt_context *ctx, const char *file)
{
    tt_scene *scene = NULL;
    REQUIRE_OK(ctx, tt_scene_load(ctx, tt_test_scene_path(file), &scene));
    return scene;
}

void tt_test_view(tt_context *ctx, const char *name, tt_camera *out)
{
    REQUIRE_OK(ctx, tt_view_find(ctx, tt_test_scene_path("views.tsv"), name, out));
}

int tt_test_has_accel(const char *name)
{
    for (const char *const *n = tt_accel_names(); *n; n++)
        if (strcmp(*n, name) == 0) return 1;
    return 0;
}

tt_accel *tt_test_build_default(tt_context *ctx, const tt_scene *scene, const char *name)
{
    tt_build_options opt;
    tt_build_options_default(&opt);
    opt.accel = name;
    tt_accel *a = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &opt, &a));
    return a;
}

typedef struct stat_lookup {
    const char *name;
    double value;
} stat_lookup;

static void take_stat(void *user, const char *key, double value)
{
    stat_lookup *l = user;
    if (strcmp(key, l->name) == 0) l->value = value;
}

double tt_test_stat(const tt_accel *accel, const char *name)
{
    stat_lookup l = {name, -1.0};
    tt_accel_statistics(accel, take_stat, &l);
    return l.value;
}
