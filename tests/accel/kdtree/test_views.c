/* Every traversal (htr, btr, sltr, seq) at several d_min, with the fast
 * kernels of every ISA this CPU runs, agrees with bruteforce ray by ray on views of the shared scenes: primary rays started
 * from tt_accel_locate(eye), shadow rays from the primary ray's end node,
 * fast and counting variants, closest hit and occlusion. */
#include "compare.h"
#include "kd_testing.h"

#define MAX_DMINS 8

typedef struct shot {
    const char *view;
    uint32_t w, h;
} shot;

static void views(tt_context *ctx, const char *file, const shot *shots, size_t n_shots,
                  const int *dmins, size_t n_dmins)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));
    tt_isa isas[TT_ISA_AVX512 + 1];
    const size_t n_isas = kd_isas(isas);
    tt_accel *trees[MAX_DMINS], *per_isa[MAX_DMINS][TT_ISA_AVX512 + 1],
        views[MAX_DMINS][TT_ISA_AVX512 + 1][4];
    const tt_accel *tests[MAX_DMINS * (TT_ISA_AVX512 + 1) * 4];
    size_t n = 0;
    for (size_t d = 0; d < n_dmins && d < MAX_DMINS; d++) {
        trees[d] = kd_build_with(ctx, scene, TT_KD_NLOGN, dmins[d], TT_KD_HTR);
        for (size_t i = 0; i < n_isas; i++) {
            per_isa[d][i] = kd_isa_view(trees[d], isas[i]);
            kd_traversal_views(per_isa[d][i], views[d][i]);
            for (int tr = 0; tr < 4; tr++) tests[n++] = &views[d][i][tr];
        }
    }
    for (size_t v = 0; v < n_shots; v++) {
        tt_camera cam;
        tt_test_view(ctx, shots[v].view, &cam);
        size_t bad = tt_test_compare_view_multi(scene, tests, n, ref, &cam, shots[v].w, shots[v].h);
        CHECK_MSG(bad == 0,
                  "%s %ux%u: %zu rays disagree (structure i is d_min number i / %zu, isa number "
                  "(i / 4) %% %zu of this CPU's, traversal htr, btr, sltr, seq by i %% 4)",
                  shots[v].view, shots[v].w, shots[v].h, bad, 4 * n_isas, n_isas);
    }
    for (size_t d = 0; d < n_dmins && d < MAX_DMINS; d++) {
        for (size_t i = 0; i < n_isas; i++) kd_isa_view_free(per_isa[d][i]);
        tt_accel_destroy(trees[d]);
    }
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    const int dmins[] = {1, 2, 4, 8, -1};
    const shot res4[] = {{"bunny_res4:main", 64, 64}};
    const shot cornell[] = {{"cornell:main", 48, 48}};
    const shot bunny[] = {{"bunny:main", 48, 48}, {"bunny:side", 32, 32}};
    const shot sibenik[] = {{"sibenik:main", 32, 32}, {"sibenik:back", 24, 24}};
    views(ctx, "bun_zipper_res4.ply", res4, 1, dmins, 5);
    views(ctx, "cornell_box.obj", cornell, 1, dmins, 5);
    views(ctx, "bun_zipper.ply", bunny, 2, dmins, 5);
    views(ctx, "sibenik.obj", sibenik, 2, dmins, 5);
    /* The big scene at a small size and two d_min: bruteforce dominates. */
    const int dmins_big[] = {2, -1};
    const shot conference[] = {{"conference:main", 32, 24}};
    views(ctx, "conference.ply", conference, 1, dmins_big, 2);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
