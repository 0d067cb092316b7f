/* The binned builder (--kd-build binned): its tree passes tt_accel_check
 * (every triangle in every leaf its clipped part overlaps, only in leaves
 * its box touches, the layout and sparse boxes), every traversal in every
 * ISA on it agrees with bruteforce ray by ray on views of the shared
 * scenes, and its SAH cost stays close to the exact builder's (it is an
 * approximation of the same greedy SAH, not another heuristic). */
#include "compare.h"
#include "kd_testing.h"


static void scene_views(tt_context *ctx, const char *file, const char *const *views, size_t n_views,
                        uint32_t w, uint32_t h)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_accel *ref = tt_test_build_default(ctx, scene, "bruteforce");
    const int dmins[] = {1, 4, -1};
    tt_isa isas[TT_ISA_AVX512 + 1];
    const size_t n_isas = kd_isas(isas);
    tt_accel *trees[3], *on[3][TT_ISA_AVX512 + 1], tv[3][TT_ISA_AVX512 + 1][4];
    const tt_accel *tests[3 * (TT_ISA_AVX512 + 1) * 4];
    size_t n = 0;
    for (int d = 0; d < 3; d++) {
        trees[d] = kd_build_with(ctx, scene, TT_KD_BINNED, dmins[d], TT_KD_HTR);
        CHECK_OK(ctx, tt_accel_check(trees[d]));
        for (size_t i = 0; i < n_isas; i++) {
            on[d][i] = kd_isa_view(trees[d], isas[i]);
            kd_traversal_views(on[d][i], tv[d][i]);
            for (int tr = 0; tr < 4; tr++) tests[n++] = &tv[d][i][tr];
        }
    }
    tt_accel *exact = kd_build_with(ctx, scene, TT_KD_NLOGN, 4, TT_KD_HTR);
    const double sah_binned = tt_test_stat(trees[1], "sah_cost"), sah_exact = tt_test_stat(exact, "sah_cost");
    CHECK_MSG(sah_binned > 0.0 && sah_binned < 1.1 * sah_exact, "%s: SAH cost %g binned, %g exact",
              file, sah_binned, sah_exact);
    CHECK(tt_test_stat(trees[1], "ref_budget_reached") == 0.0);
    for (size_t v = 0; v < n_views; v++) {
        tt_camera cam;
        tt_test_view(ctx, views[v], &cam);
        size_t bad = tt_test_compare_view_multi(scene, tests, n, ref, &cam, w, h);
        CHECK_MSG(bad == 0,
                  "%s %ux%u: %zu rays disagree (structure i: d_min 1, 4, none by i / %zu, "
                  "isa by i / 4 %% %zu, traversal htr, btr, sltr, seq by i %% 4)",
                  views[v], w, h, bad, 4 * n_isas, n_isas);
    }
    /* Random rays through the scene box too. */
    for (size_t i = 0; i < n; i++) {
        size_t bad = tt_test_compare_random(scene, tests[i], ref, 300, 11);
        CHECK_MSG(bad == 0, "%s: random rays, structure %zu: %zu differ", file, i, bad);
    }
    for (int d = 0; d < 3; d++) {
        for (size_t i = 0; i < n_isas; i++) kd_isa_view_free(on[d][i]);
        tt_accel_destroy(trees[d]);
    }
    tt_accel_destroy(exact);
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    const char *const res4[] = {"bunny_res4:main"};
    const char *const cornell[] = {"cornell:main"};
    const char *const bunny[] = {"bunny:main", "bunny:side"};
    const char *const sibenik[] = {"sibenik:main", "sibenik:back"};
    scene_views(ctx, "bun_zipper_res4.ply", res4, 1, 48, 48);
    scene_views(ctx, "cornell_box.obj", cornell, 1, 32, 32);
    scene_views(ctx, "bun_zipper.ply", bunny, 2, 32, 32);
    scene_views(ctx, "sibenik.obj", sibenik, 2, 24, 24);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
