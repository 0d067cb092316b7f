/* Ray by ray against bruteforce on random rays (origins inside and outside
 * the scene box, random, axis-parallel and zero-component directions,
 * finite occlusion intervals): every strategy x traversal, with the (m, M),
 * split and reinsert variants rotating among them, on the
 * small scenes, where rays start both inside (auto: stackless) and outside
 * (auto: ordered) the root box and carry no hint; the default strategy on
 * the full bunny. Also hints: a stale or foreign start hint changes nothing. */
#include <math.h>
#include <string.h>

#include "compare.h"
#include "rtree_test.h"

static void random_matrix(tt_context *ctx, const char *file, uint32_t rays)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    /* every strategy x traversal; (m, M), split and reinsert rotate so
     * that each value meets several strategies and traversals */
    for (int s = 0; s < 5; s++)
        for (int tr = 0; tr < 4; tr++) {
            const int mm = (s + tr) % RT_MM_COUNT;
            tt_build_options o = rt_options(s, tr, rt_mm_list[mm].m, rt_mm_list[mm].M);
            o.rtree.split = (s + mm) % 3 == 2 ? TT_RTREE_SPLIT_QUADRATIC : TT_RTREE_SPLIT_RSTAR;
            o.rtree.reinsert = (s + tr) % 3 != 2;
            tt_accel *a = rt_build_checked(ctx, scene, &o);
            if (!a) continue;
            size_t bad = tt_test_compare_random(scene, a, bf, rays, 1234u + (uint32_t)s);
            CHECK_MSG(bad == 0, "%s random, %s: %zu rays disagree", file, rt_describe(&o), bad);
            tt_accel_destroy(a);
        }
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

/* Whatever the start hint says, the result agrees (the hint only picks a
 * traversal); every hint value, valid or not, is tried on every ray. */
static void hints(tt_context *ctx)
{
    tt_scene *scene = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
    tt_accel *a = rt_build_checked(ctx, scene, &o);
    if (!a) return;
    const uint32_t hint_values[] = {TT_INVALID_ID, 0, TT_RTREE_STACKLESS, TT_RTREE_ORDERED,
                                    TT_RTREE_STACK, 12345};
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    uint32_t x = 99;
    for (int i = 0; i < 500; i++) {
        tt_ray r;
        for (int k = 0; k < 3; k++) {
            x = x * 1664525u + 1013904223u;
            r.org[k] = lo[k] + (hi[k] - lo[k]) * ((float)(x >> 8) / 16777216.0f * 3.0f - 1.0f);
            r.dir[k] = (lo[k] + hi[k]) * 0.5f - r.org[k] + (float)((x >> 4) & 255) * 1e-4f;
        }
        r.tmin = 0.0f;
        r.tmax = INFINITY;
        tt_hit first;
        tt_trace_args args = {TT_INVALID_ID, 0, NULL};
        CHECK_OK(ctx, tt_intersect1_ex(a, &r, &first, &args));
        CHECK(args.end_hint == TT_INVALID_ID);
        for (size_t h = 0; h < sizeof hint_values / sizeof hint_values[0]; h++) {
            tt_hit hit;
            tt_trace_args ha = {hint_values[h], 0, NULL};
            CHECK_OK(ctx, tt_intersect1_ex(a, &r, &hit, &ha));
            CHECK_MSG(tt_test_hits_agree(&hit, &first),
                      "hint %u changed the hit: %u %g vs %u %g", hint_values[h], hit.prim,
                      (double)hit.t, first.prim, (double)first.t);
        }
    }
    tt_accel_destroy(a);
    tt_scene_destroy(scene);
}

static void full_bunny(tt_context *ctx)
{
    tt_scene *scene = tt_test_load_scene(ctx, "bun_zipper.ply");
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    for (int tr = 0; tr < 4; tr++) {
        tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, tr, 2, 4);
        tt_accel *a = rt_build_checked(ctx, scene, &o);
        if (!a) continue;
        size_t bad = tt_test_compare_random(scene, a, bf, 400, 77u);
        CHECK_MSG(bad == 0, "bunny random, %s: %zu rays disagree", rt_describe(&o), bad);
        tt_accel_destroy(a);
    }
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    random_matrix(ctx, "bun_zipper_res4.ply", 2000);
    random_matrix(ctx, "cornell_box.obj", 2000);
    hints(ctx);
    full_bunny(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
