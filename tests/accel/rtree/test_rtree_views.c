/* Ray by ray against bruteforce on the shared views: every strategy x every
 * traversal (auto, stackless, ordered, stack) returns the bruteforce closest
 * hit of every primary ray and the same occlusion of every shadow ray, on
 * the bunny (eye outside the root box: auto = ordered), Sibenik (eye inside:
 * auto = stackless) and the small scenes; plus the other construction
 * options on the small bunny. The big scenes' reference is traced once and
 * kept (tests/support/reference.h). */
#include "compare.h"
#include "reference.h"
#include "rtree_test.h"

static void strategies_by_traversals(tt_context *ctx, const tt_scene *scene,
                                     const tt_test_reference *ref, const char *view)
{
    for (int s = 0; s < 5; s++)
        for (int tr = 0; tr < 4; tr++) {
            tt_build_options o = rt_options(s, tr, 2, 4);
            tt_accel *a = rt_build_checked(ctx, scene, &o);
            if (!a) continue;
            size_t bad = tt_test_compare_view_reference(a, ref);
            CHECK_MSG(bad == 0, "%s, %s: %zu rays disagree", view, rt_describe(&o), bad);
            tt_accel_destroy(a);
        }
}

static void view_cached(tt_context *ctx, const char *file, const char *view, uint32_t size,
                        uint32_t expect_hint)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    tt_test_reference *ref = tt_test_reference_view(scene, bf, &cam, size, size);
    strategies_by_traversals(ctx, scene, ref, view);
    /* the auto traversal picks by the eye: the hint names the choice */
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
    tt_accel *a = rt_build_checked(ctx, scene, &o);
    if (a) {
        uint32_t hint = tt_accel_locate(a, cam.eye);
        CHECK_MSG(hint == expect_hint, "%s: auto picks %u for the eye, expected %u", view, hint,
                  expect_hint);
        tt_accel_destroy(a);
    }
    tt_test_reference_destroy(ref);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

/* Every strategy x traversal x construction variant against one kept
 * reference of the view. */
static void view_options(tt_context *ctx, const char *file, const char *view, uint32_t size)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    tt_test_reference *ref = tt_test_reference_view(scene, bf, &cam, size, size);
    for (int s = 0; s < 5; s++)
        for (int tr = 0; tr < 4; tr++)
            for (int variant = 0; variant < 1 + RT_MM_COUNT + 2; variant++) {
                /* variant 0: defaults; then each (m, M); then no reinsert
                 * with the quadratic split; then close reinsert */
                tt_build_options o = rt_options(s, tr, 2, 4);
                if (variant >= 1 && variant <= RT_MM_COUNT) {
                    o.rtree.m = rt_mm_list[variant - 1].m;
                    o.rtree.M = rt_mm_list[variant - 1].M;
                } else if (variant == RT_MM_COUNT + 1) {
                    o.rtree.reinsert = 0;
                    o.rtree.split = TT_RTREE_SPLIT_QUADRATIC;
                } else if (variant == RT_MM_COUNT + 2) {
                    o.rtree.reinsert_far = 0;
                }
                tt_accel *a = rt_build_checked(ctx, scene, &o);
                if (!a) continue;
                size_t bad = tt_test_compare_view_reference(a, ref);
                CHECK_MSG(bad == 0, "%s, %s: %zu rays disagree", view, rt_describe(&o), bad);
                tt_accel_destroy(a);
            }
    /* one uncached run through the shared helper, as every structure does */
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
    tt_accel *a = rt_build_checked(ctx, scene, &o);
    if (a) {
        size_t bad = tt_test_compare_view(scene, a, bf, &cam, size, size);
        CHECK_MSG(bad == 0, "%s, %s: %zu rays disagree", view, rt_describe(&o), bad);
        tt_accel_destroy(a);
    }
    tt_test_reference_destroy(ref);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    view_options(ctx, "bun_zipper_res4.ply", "bunny_res4:main", 64);
    view_options(ctx, "cornell_box.obj", "cornell:main", 32);
    view_cached(ctx, "bun_zipper.ply", "bunny:main", 48, TT_RTREE_ORDERED);
    view_cached(ctx, "sibenik.obj", "sibenik:main", 32, TT_RTREE_STACKLESS);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
