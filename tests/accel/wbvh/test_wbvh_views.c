/* The wide BVH ray by ray against bruteforce: every ISA this CPU runs x M
 * in {4, 5, 8, 16} (5 exercises the padded SoA rows), on the shared views
 * (the big scenes as small images) and on random rays; closest hit and
 * occlusion, fast and counting variants (compare.h, reference.h). */
#include "check.h"
#include "compare.h"
#include "core/isa.h"
#include "reference.h"

static const int widths[] = {4, 5, 8, 16};

static void view(tt_context *ctx, const char *file, const char *view_name, uint32_t size,
                 int random)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view_name, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    tt_test_reference *ref = tt_test_reference_view(scene, bf, &cam, size, size);
    for (int k = 0; k < 4; k++)
        for (int isa = TT_ISA_FIRST; isa <= TT_ISA_LAST; isa++) {
            if (!tt_test_isa_runs((tt_isa)isa)) continue;
            tt_build_options o;
            tt_build_options_default(&o);
            o.accel = "wbvh";
            o.rtree.M = widths[k];
            o.isa = (tt_isa)isa;
            tt_accel *a = NULL;
            tt_status st = tt_accel_build(ctx, scene, &o, &a);
            CHECK_MSG(st == TT_OK, "%s M=%d isa=%s: build: %s", view_name, widths[k],
                      tt_isa_name((tt_isa)isa), tt_context_last_error(ctx));
            if (st != TT_OK) continue;
            CHECK_OK(ctx, tt_accel_check(a));
            CHECK(tt_accel_isa(a) == (tt_isa)isa);
            size_t bad = tt_test_compare_view_reference(a, ref);
            CHECK_MSG(bad == 0, "%s M=%d isa=%s: %zu rays disagree", view_name, widths[k],
                      tt_isa_name((tt_isa)isa), bad);
            if (random) {
                bad = tt_test_compare_random(scene, a, bf, 2000, 91u + (uint32_t)widths[k]);
                CHECK_MSG(bad == 0, "%s M=%d isa=%s: %zu random rays disagree", view_name,
                          widths[k], tt_isa_name((tt_isa)isa), bad);
                bad = tt_test_compare_tiny_dirs(scene, a, bf, 300, 3u + (uint32_t)widths[k]);
                CHECK_MSG(bad == 0, "%s M=%d isa=%s: %zu tiny-direction rays disagree", view_name,
                          widths[k], tt_isa_name((tt_isa)isa), bad);
            }
            tt_accel_destroy(a);
        }
    tt_test_reference_destroy(ref);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    if (!tt_test_has_accel("wbvh")) tt_test_skip("wbvh is not in this build");
    view(ctx, "bun_zipper_res4.ply", "bunny_res4:main", 64, 1);
    view(ctx, "cornell_box.obj", "cornell:main", 48, 1);
    view(ctx, "bun_zipper.ply", "bunny:main", 48, 0);
    view(ctx, "sibenik.obj", "sibenik:main", 32, 0);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
