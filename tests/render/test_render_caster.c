/* The kd-tree's shadow-caster hint through tt_render: the renderer must hand
 * each shadow ray its primary ray's end node as start_hint and the node
 * where the tile's last occluded shadow ray ended as end_hint (where the
 * kd-tree takes the caster on input). On a one-tile image traced by one
 * thread (pixels in row order), the render's shadow statistics must equal
 * those of the same protocol replayed through tt_occluded1_ex, and differ
 * from the same replay without the caster (so the caster search is really
 * taken). test_render_hints checks the hit buffers against bruteforce. */
#include <string.h>

#include "check.h"

#define N 16 /* one tile of the renderer */

static int same_stats(const tt_ray_stats *a, const tt_ray_stats *b)
{
    return a->rays == b->rays && a->nodes == b->nodes && a->interior == b->interior &&
           a->leaves == b->leaves && a->boxes == b->boxes && a->triangles == b->triangles;
}

/* The renderer's protocol, replayed: shadow statistics and occluded count. */
static void replay(const tt_scene *scene, const tt_accel *kd, const tt_accel *ref,
                   const tt_camera *cam, int use_caster, tt_ray_stats *primary,
                   tt_ray_stats *shadow, int *occluded_count)
{
    uint32_t eye = tt_accel_locate(kd, cam->eye), caster = TT_INVALID_ID;
    uint32_t ends[N * N];
    tt_hit hits[N * N];
    memset(primary, 0, sizeof *primary);
    memset(shadow, 0, sizeof *shadow);
    *occluded_count = 0;
    for (uint32_t i = 0; i < N * N; i++) {
        tt_ray r;
        CHECK_OK(NULL, tt_camera_ray(cam, N, N, i % N, i / N, &r));
        tt_trace_args a = {eye, TT_INVALID_ID, primary};
        CHECK_OK(NULL, tt_intersect1_ex(kd, &r, &hits[i], &a));
        ends[i] = a.end_hint;
    }
    for (uint32_t i = 0; i < N * N; i++) {
        if (hits[i].prim == TT_INVALID_ID) continue;
        tt_ray r, s;
        CHECK_OK(NULL, tt_camera_ray(cam, N, N, i % N, i / N, &r));
        if (!tt_shadow_ray(scene, cam, &r, &hits[i], &s)) continue;
        tt_trace_args a = {ends[i], use_caster ? caster : TT_INVALID_ID, shadow};
        int o, o_ref;
        CHECK_OK(NULL, tt_occluded1_ex(kd, &s, &o, &a));
        CHECK_OK(NULL, tt_occluded1(ref, &s, &o_ref));
        CHECK_MSG(o == o_ref, "pixel %u: occlusion %d, bruteforce %d", i, o, o_ref);
        if (o) {
            caster = a.end_hint;
            ++*occluded_count;
        }
    }
}

static void check_traversal(tt_context *ctx, const tt_scene *scene, const tt_camera *cam,
                            const tt_accel *ref, tt_kd_traversal traversal)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "kdtree";
    bo.kdtree.traversal = traversal;
    bo.kdtree.dmin = 2; /* many boxes: the caster's box is a small one */
    bo.kdtree.shadow_caster_hint = 1;
    tt_accel *kd;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &kd));
    tt_render_options o;
    tt_render_options_default(&o);
    o.width = o.height = N;
    o.stats = 1;
    tt_render_result *res;
    REQUIRE_OK(ctx, tt_render(ctx, scene, kd, cam, &o, &res));
    const tt_render_summary *sum = tt_render_get_summary(res);

    tt_ray_stats p_with, s_with, p_without, s_without;
    int occ_with, occ_without;
    replay(scene, kd, ref, cam, 1, &p_with, &s_with, &occ_with);
    replay(scene, kd, ref, cam, 0, &p_without, &s_without, &occ_without);
    CHECK_MSG(occ_with > 1, "traversal %d: the view needs occluded pixels (%d)", (int)traversal,
              occ_with);
    CHECK(occ_with == occ_without && (uint64_t)occ_with == sum->shadow_occluded);
    CHECK_MSG(sum->has_stats && same_stats(&sum->primary_stats, &p_with),
              "traversal %d: primary rays differ from the replay", (int)traversal);
    CHECK_MSG(same_stats(&sum->shadow_stats, &s_with),
              "traversal %d: render's shadow statistics (boxes %llu, nodes %llu) are not the "
              "caster protocol's (boxes %llu, nodes %llu)",
              (int)traversal, (unsigned long long)sum->shadow_stats.boxes,
              (unsigned long long)sum->shadow_stats.nodes, (unsigned long long)s_with.boxes,
              (unsigned long long)s_with.nodes);
    CHECK_MSG(!same_stats(&s_with, &s_without),
              "traversal %d: the caster search changed no statistic", (int)traversal);
    tt_render_result_destroy(res);
    tt_accel_destroy(kd);
}

int main(void)
{
    int have_kd = 0;
    for (const char *const *n = tt_accel_names(); *n; n++) have_kd |= strcmp(*n, "kdtree") == 0;
    if (!have_kd) {
        printf("skipped: no kdtree in this build\n");
        return 77;
    }
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = 1;
    tt_context *ctx;
    REQUIRE_OK(NULL, tt_context_create(&co, &ctx));
    tt_scene *scene = tt_test_load_scene(ctx, "cornell_box.obj");
    tt_camera cam;
    tt_test_view(ctx, "cornell:main", &cam);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));
    check_traversal(ctx, scene, &cam, ref, TT_KD_BTR);
    check_traversal(ctx, scene, &cam, ref, TT_KD_SLTR);
    check_traversal(ctx, scene, &cam, ref, TT_KD_SEQ);
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
