/* Hard geometry: every registered structure, in every option variant
 * (hard_accel.h), is built on each procedural hard scene (hard_scenes.h),
 * passes tt_accel_check, and agrees ray by ray with bruteforce on targeted
 * rays (hard_rays.h), random rays (compare.h) and a small framed view.
 *
 * Scenes: all triangles identical; all coplanar in an axis-aligned plane (two
 * axes); needles; random soups at 1e-6 and 1e6 scale and 1e5 away from the
 * origin; many triangles sharing one vertex; a heavily overlapping soup;
 * zero-area triangles among ordinary ones; a single triangle; and the empty
 * scene. */
#include "core/context.h" /* tt_now */
#include "hard_rays.h"

#define PER_FAMILY 60
#define RANDOM_RAYS 200

static int verbose;

static void run_scene(tt_context *ctx, hard_mesh *m)
{
    double t0 = tt_now();
    tt_scene *scene = hard_scene(ctx, m);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));

    hard_rays rays = {0};
    hard_rays_targeted(&rays, scene, PER_FAMILY, 777u);
    hard_rays_reference(&rays, ref);
    hard_rays intervals = {0};
    hard_geom g;
    hard_geom_init(&g, scene);
    hard_rays_intervals(&intervals, &rays, g.diag, PER_FAMILY);
    hard_rays_reference(&intervals, ref);
    /* one set: the targeted rays, then their interval variants */
    for (size_t i = 0; i < intervals.n; i++)
        hard_rays_add(&rays, intervals.kind[i], intervals.ray[i].org, intervals.ray[i].dir,
                      intervals.ray[i].tmin, intervals.ray[i].tmax);
    hard_rays_reference(&rays, ref);
    size_t hits = 0;
    for (size_t i = 0; i < rays.n; i++) hits += rays.hit[i].prim != TT_INVALID_ID;

    size_t built = hard_each_structure(ctx, m->name, scene, &rays, RANDOM_RAYS);
    CHECK(built > 0);
    printf("%-14s %6zu triangles, %5zu targeted rays (%zu hit), %3zu structure variants, %.2fs\n",
           m->name, m->nt, rays.n, hits, built, tt_now() - t0);
    if (verbose) fflush(stdout);
    hard_rays_free(&rays);
    hard_rays_free(&intervals);
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
    hard_mesh_free(m);
}

int main(int argc, char **argv)
{
    verbose = argc > 1 && argv[1][0] == '-';
    tt_context *ctx = tt_test_context();
    printf("structures:");
    for (const char *const *n = tt_accel_names(); *n; n++) printf(" %s", *n);
    printf("\n");

    hard_mesh m = {0};
    hard_gen_identical(&m, 300);
    run_scene(ctx, &m);

    hard_gen_coplanar(&m, 2, 16, 200, 11u);
    run_scene(ctx, &m);
    hard_gen_coplanar(&m, 0, 10, 300, 12u);
    run_scene(ctx, &m);

    hard_gen_needles(&m, 800, 1e-5f, 13u);
    run_scene(ctx, &m);

    static const float zero[3] = {0, 0, 0};
    hard_gen_soup(&m, "tiny (1e-6)", 800, 0.05f, 14u);
    hard_mesh_transform(&m, 1e-6f, zero);
    run_scene(ctx, &m);
    hard_gen_soup(&m, "huge (1e6)", 800, 0.05f, 15u);
    hard_mesh_transform(&m, 1e6f, zero);
    run_scene(ctx, &m);
    static const float far[3] = {1e5f, -1e5f, 1e5f};
    hard_gen_soup(&m, "far (1e5 off)", 800, 0.05f, 16u);
    hard_mesh_transform(&m, 1.0f, far);
    run_scene(ctx, &m);

    hard_gen_fan(&m, 1000, 17u);
    run_scene(ctx, &m);

    hard_gen_soup(&m, "overlap", 1000, 0.6f, 18u);
    run_scene(ctx, &m);

    hard_gen_degenerate(&m, 600, 19u);
    run_scene(ctx, &m);

    static const float a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    m.name = "single";
    hard_triangle(&m, a, b, c);
    run_scene(ctx, &m);

    m.name = "empty";
    run_scene(ctx, &m);

    tt_context_destroy(ctx);
    return tt_test_finish();
}
