/* The O(N log N) and O(N log^2 N) builders build the same tree, node by
 * node, on shared and synthetic scenes and for several d_min; every tree
 * passes tt_accel_check. */
#include "check.h"
#include "kd_scenes.h"
#include "kd_testing.h"

static void same_trees(tt_context *ctx, const tt_scene *scene, const char *what)
{
    const int dmins[] = {1, 3, -1};
    for (size_t i = 0; i < sizeof dmins / sizeof dmins[0]; i++) {
        tt_accel *fast = kd_build_with(ctx, scene, TT_KD_NLOGN, dmins[i], TT_KD_HTR);
        tt_accel *slow = kd_build_with(ctx, scene, TT_KD_NLOG2N, dmins[i], TT_KD_HTR);
        CHECK_MSG(kd_same_tree(tt_kdtree_of(fast), tt_kdtree_of(slow)), "%s, dmin %d", what, dmins[i]);
        CHECK_OK(ctx, tt_accel_check(fast));
        CHECK_OK(ctx, tt_accel_check(slow));
        tt_accel_destroy(fast);
        tt_accel_destroy(slow);
    }
}

static void shared_scene(tt_context *ctx, const char *file)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    same_trees(ctx, scene, file);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    shared_scene(ctx, "bun_zipper_res4.ply");
    shared_scene(ctx, "cornell_box.obj");
    tt_scene *s = kd_scene_blocks(ctx);
    same_trees(ctx, s, "blocks");
    tt_scene_destroy(s);
    s = kd_scene_soup(ctx, 2000, 23);
    same_trees(ctx, s, "soup");
    tt_scene_destroy(s);
    /* A big real scene, one d_min (the split decisions do not depend on it). */
    s = tt_test_load_scene(ctx, "sibenik.obj");
    tt_accel *fast = kd_build_with(ctx, s, TT_KD_NLOGN, 4, TT_KD_HTR);
    tt_accel *slow = kd_build_with(ctx, s, TT_KD_NLOG2N, 4, TT_KD_HTR);
    CHECK_MSG(kd_same_tree(tt_kdtree_of(fast), tt_kdtree_of(slow)), "sibenik");
    CHECK_OK(ctx, tt_accel_check(fast));
    tt_accel_destroy(fast);
    tt_accel_destroy(slow);
    tt_scene_destroy(s);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
