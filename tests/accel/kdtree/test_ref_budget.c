/* The reference budget (kd_build.c, kd_should_split): 2000 large random
 * triangles in one plane drive the greedy SAH to its depth limit with the
 * references multiplying at every level (266 M references without the
 * budget). With it the build stays within the budget, both builders still
 * build the same tree, every traversal still equals bruteforce ray by ray,
 * and a real scene's tree is not touched by it. */
#include "check.h"
#include "compare.h"
#include "kd_scenes.h"
#include "kd_testing.h"

#include "accel/kdtree/build/kd_build.h"


/* Rays straight down onto the plane and slanted ones through it. */
static size_t down_rays(const tt_accel *test, const tt_accel *ref)
{
    enum { N = 600 };
    static tt_ray rays[N];
    uint32_t seed = 99;
    for (int i = 0; i < N; i++) {
        tt_ray *r = &rays[i];
        r->org[0] = kd_unit(&seed) * 4.4f - 0.2f;
        r->org[1] = kd_unit(&seed) * 4.4f - 0.2f;
        r->org[2] = 1.0f;
        r->dir[0] = (i % 3 == 0) ? 0.0f : kd_unit(&seed) - 0.5f;
        r->dir[1] = (i % 3 == 0) ? 0.0f : kd_unit(&seed) - 0.5f;
        r->dir[2] = -1.0f;
        r->tmin = 0.0f;
        r->tmax = TT_INF;
    }
    return tt_test_compare_rays(test, ref, rays, N);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *flat = kd_scene_coplanar(ctx, 2000, 5);
    tt_accel *ref = tt_test_build_default(ctx, flat, "bruteforce");
    tt_accel *fast = kd_build_with(ctx, flat, TT_KD_NLOGN, 4, TT_KD_HTR);
    tt_accel *slow = kd_build_with(ctx, flat, TT_KD_NLOG2N, 4, TT_KD_HTR);
    const tt_kdtree *t = tt_kdtree_of(fast);
    CHECK_MSG(t->ref_count <= kd_ref_budget(2000), "%zu references, budget %zu",
              (size_t)t->ref_count, kd_ref_budget(2000));
    CHECK(t->ref_budget_hit == 1);
    CHECK(tt_test_stat(fast, "ref_budget_reached") == 1.0);
    CHECK(kd_same_tree(t, tt_kdtree_of(slow)));
    CHECK_OK(ctx, tt_accel_check(fast));
    tt_accel views[4];
    kd_traversal_views(fast, views);
    for (int tr = 0; tr < 4; tr++) {
        size_t bad = down_rays(&views[tr], ref) + tt_test_compare_random(flat, &views[tr], ref, 400, 7);
        CHECK_MSG(bad == 0, "flat scene, %s: %zu rays differ from bruteforce", kd_traversal_names[tr],
                  bad);
    }
    tt_accel_destroy(fast);
    tt_accel_destroy(slow);
    tt_accel_destroy(ref);
    tt_scene_destroy(flat);

    /* A real scene stays far below the budget. */
    tt_scene *bunny = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    tt_accel *b = kd_build_with(ctx, bunny, TT_KD_NLOGN, 4, TT_KD_HTR);
    CHECK(tt_kdtree_of(b)->ref_budget_hit == 0);
    CHECK(tt_test_stat(b, "ref_budget_reached") == 0.0);
    tt_accel_destroy(b);
    tt_scene_destroy(bunny);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
