/* The bulk loaders ray by ray against bruteforce on the shared views: every
 * loader (STR, Hilbert, SAH) x (m, M) in {(2,4), (2,8), (4,8), (3,16),
 * (8,16)}, at (2, 4) with every traversal, otherwise one traversal each
 * (cycling); closest hit of every primary ray and occlusion of every shadow
 * ray of a small image (the big scenes' reference traced once and kept). */
#include "compare.h"
#include "reference.h"
#include "rtree_test.h"

static const char *const build_names[] = {"insert", "str", "hilbert", "sah"};
static const rt_mm bulk_mm[] = {{2, 4}, {2, 8}, {4, 8}, {3, 16}, {8, 16}};
#define BULK_MM ((int)(sizeof bulk_mm / sizeof bulk_mm[0]))

static void view(tt_context *ctx, const char *file, const char *name, uint32_t size)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, name, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    tt_test_reference *ref = tt_test_reference_view(scene, bf, &cam, size, size);
    for (int bld = TT_RTREE_BUILD_STR; bld <= TT_RTREE_BUILD_SAH; bld++)
        for (int q = 0; q < BULK_MM; q++)
            for (int tr = 0; tr < 4; tr++) {
                if (q > 0 && tr != (bld + q) % 4) continue;
                tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, tr, bulk_mm[q].m,
                                                bulk_mm[q].M);
                o.rtree.build = (tt_rtree_build)bld;
                tt_accel *a = rt_build_checked(ctx, scene, &o);
                if (!a) continue;
                size_t bad = tt_test_compare_view_reference(a, ref);
                CHECK_MSG(bad == 0, "%s, build %s %s: %zu rays disagree", name, build_names[bld],
                          rt_describe(&o), bad);
                tt_accel_destroy(a);
            }
    tt_test_reference_destroy(ref);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    view(ctx, "bun_zipper_res4.ply", "bunny_res4:main", 64);
    view(ctx, "cornell_box.obj", "cornell:main", 32);
    view(ctx, "bun_zipper.ply", "bunny:main", 40);
    view(ctx, "sibenik.obj", "sibenik:main", 32);
    view(ctx, "conference.ply", "conference:main", 24);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
