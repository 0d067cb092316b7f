/* The parallel builders (kd_build_par.h) build the tree the serial ones
 * build, node by node (references, sparse boxes), at every thread count,
 * for both exact builders and the binned one (which is not the exact tree
 * but must not depend on the threads either). The task cutoff is lowered
 * so that small scenes are split by many tasks too; the flat scene that
 * reaches the reference budget takes the parallel build's fallback to the
 * serial order. */
#include "check.h"
#include "kd_scenes.h"
#include "kd_testing.h"

#include "accel/kdtree/build/kd_build_par.h"

static tt_context *context_with(int threads)
{
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = threads;
    tt_context *ctx = NULL;
    REQUIRE_OK(ctx, tt_context_create(&co, &ctx));
    return ctx;
}

static const char *const builder_names[] = {"nlogn", "nlog2n", "binned"};

/* Builds scene with every builder at 1 thread, then at each thread count
 * and task cutoff, and asserts the trees are equal. */
static void same_at_all_threads(const tt_scene *scene, const char *what, const int *threads,
                                size_t n_threads, const uint32_t *cutoffs, size_t n_cutoffs,
                                int expect_budget)
{
    const uint32_t saved = kd_par_cutoff;
    tt_context *serial = context_with(1);
    for (int b = TT_KD_NLOGN; b <= TT_KD_BINNED; b++) {
        tt_accel *ref = kd_build_with(serial, scene, (tt_kd_builder)b, 3, TT_KD_HTR);
        CHECK_OK(serial, tt_accel_check(ref));
        if (expect_budget >= 0)
            CHECK_MSG(tt_kdtree_of(ref)->ref_budget_hit == expect_budget, "%s %s: budget %d", what,
                      builder_names[b], tt_kdtree_of(ref)->ref_budget_hit);
        for (size_t c = 0; c < n_cutoffs; c++) {
            kd_par_cutoff = cutoffs[c];
            for (size_t t = 0; t < n_threads; t++) {
                tt_context *ctx = context_with(threads[t]);
                tt_accel *par = kd_build_with(ctx, scene, (tt_kd_builder)b, 3, TT_KD_HTR);
                CHECK_MSG(kd_same_tree(tt_kdtree_of(ref), tt_kdtree_of(par)),
                          "%s %s: %d threads, cutoff %u", what, builder_names[b], threads[t],
                          cutoffs[c]);
                CHECK(tt_kdtree_of(par)->ref_budget_hit == tt_kdtree_of(ref)->ref_budget_hit);
                tt_accel_destroy(par);
                tt_context_destroy(ctx);
            }
            kd_par_cutoff = saved;
        }
        /* The exact builders agree with each other in parallel too. */
        if (b == TT_KD_NLOG2N) {
            tt_context *ctx = context_with(2);
            kd_par_cutoff = cutoffs[n_cutoffs - 1];
            tt_accel *fast = kd_build_with(ctx, scene, TT_KD_NLOGN, 3, TT_KD_HTR);
            CHECK_MSG(kd_same_tree(tt_kdtree_of(ref), tt_kdtree_of(fast)), "%s: nlogn vs nlog2n", what);
            kd_par_cutoff = saved;
            tt_accel_destroy(fast);
            tt_context_destroy(ctx);
        }
        tt_accel_destroy(ref);
    }
    tt_context_destroy(serial);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    /* Largest team first: LLVM's libomp leaks its thread records when a
     * later parallel region grows the team (LeakSanitizer reports it). */
    const int all[] = {8, 4, 3, 2}, few[] = {3, 2};
    const uint32_t small_cutoffs[] = {2, 64};
    const uint32_t big_cutoffs[] = {256, 4096};

    tt_scene *s = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    same_at_all_threads(s, "bunny_res4", all, 4, small_cutoffs, 2, 0);
    tt_scene_destroy(s);
    s = tt_test_load_scene(ctx, "cornell_box.obj");
    same_at_all_threads(s, "cornell", few, 2, small_cutoffs, 2, 0);
    tt_scene_destroy(s);
    s = kd_scene_blocks(ctx);
    same_at_all_threads(s, "blocks", few, 2, small_cutoffs, 2, 0);
    tt_scene_destroy(s);
    /* Degenerate triangles (collinear, points) among all sizes. */
    s = kd_scene_soup(ctx, 3000, 41);
    same_at_all_threads(s, "soup", few, 2, small_cutoffs, 2, 0);
    tt_scene_destroy(s);
    /* Many copies of one triangle: no split pays. */
    s = kd_scene_identical(ctx, 500);
    same_at_all_threads(s, "identical", few, 2, small_cutoffs, 2, 0);
    tt_scene_destroy(s);
    /* Overlapping triangles in one plane: planar events everywhere, and
     * the reference budget is reached (the parallel build's bound passes
     * it and the serial order decides). */
    s = kd_scene_coplanar(ctx, 2000, 5);
    same_at_all_threads(s, "coplanar", few, 2, small_cutoffs, 2, 1);
    tt_scene_destroy(s);
    /* Fewer, flat triangles: planar but within the budget. */
    s = kd_scene_coplanar(ctx, 60, 9);
    same_at_all_threads(s, "coplanar 60", few, 2, small_cutoffs, 2, -1);
    tt_scene_destroy(s);
    /* A big real scene with the default cutoff (and a lower one). */
    s = tt_test_load_scene(ctx, "sibenik.obj");
    same_at_all_threads(s, "sibenik", few, 2, big_cutoffs, 2, 0);
    tt_scene_destroy(s);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
