/* The batch API against the renderer on the same rays: the primary rays of
 * a view traced by tt_render (primary pass only, its own timing) and by
 * tt_intersect (tt_ray array; in runs of consecutive rays, then in 16 x 16
 * tiles with image_width) and tt_intersect_arrays (one shared origin,
 * stride 0; tiles), alternating for R rounds, the minimum of each
 * reported. The hits are checked equal to the renderer's hit buffer.
 *
 * usage: treetrace_batch_bench SCENE VIEWS SCENE:VIEW [ACCEL [THREADS [ROUNDS [SIZE]]]] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <treetrace/treetrace.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int fail(tt_context *ctx, const char *what)
{
    fprintf(stderr, "%s: %s\n", what, ctx ? tt_context_last_error(ctx) : "");
    return 1;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: %s SCENE VIEWS SCENE:VIEW [ACCEL [THREADS [ROUNDS [SIZE]]]]\n",
                argv[0]);
        return 2;
    }
    const char *accel_name = argc > 4 ? argv[4] : "kdtree";
    int threads = argc > 5 ? atoi(argv[5]) : 2;
    int rounds = argc > 6 ? atoi(argv[6]) : 5;
    uint32_t size = argc > 7 ? (uint32_t)atoi(argv[7]) : 1024;
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = threads;
    tt_context *ctx;
    if (tt_context_create(&co, &ctx) != TT_OK) return 1;
    tt_scene *scene;
    tt_camera cam;
    if (tt_scene_load(ctx, argv[1], &scene) != TT_OK) return fail(ctx, "load");
    if (tt_view_find(ctx, argv[2], argv[3], &cam) != TT_OK) return fail(ctx, "view");
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = accel_name;
    tt_accel *accel;
    if (tt_accel_build(ctx, scene, &bo, &accel) != TT_OK) return fail(ctx, "build");

    const size_t n = (size_t)size * size;
    tt_ray *rays = malloc(n * sizeof *rays);
    tt_hit *hits = malloc(n * sizeof *hits);
    float *t = malloc(n * sizeof *t);
    uint32_t *prim = malloc(n * sizeof *prim);
    if (!rays || !hits || !t || !prim) return 1;
    if (tt_camera_rays(&cam, size, size, rays) != TT_OK) return 1;
    tt_batch_options opt;
    tt_batch_options_default(&opt);
    opt.start_hint = tt_accel_locate(accel, cam.eye); /* what the renderer does */
    tt_batch_options tiled = opt; /* the rays are an image: 16 x 16 tiles */
    tiled.image_width = size;
    tt_ray_arrays ra;
    memset(&ra, 0, sizeof ra);
    for (int k = 0; k < 3; k++) {
        ra.org[k] = &cam.eye[k];
        ra.dir[k] = &rays[0].dir[k];
    }
    ra.dir_stride = sizeof(tt_ray);
    tt_hit_arrays ha = {t, sizeof(float), NULL, 0, NULL, 0, prim, sizeof(uint32_t)};

    tt_render_options ro;
    tt_render_options_default(&ro);
    ro.width = ro.height = size;
    ro.shadows = 0;
    ro.keep_hits = 1;
    double best_render = INFINITY, best_aos = INFINITY, best_tiled = INFINITY, best_soa = INFINITY;
    size_t differ = 0;
    for (int r = 0; r < rounds; r++) {
        tt_render_result *res;
        if (tt_render(ctx, scene, accel, &cam, &ro, &res) != TT_OK) return fail(ctx, "render");
        double rs = tt_render_get_summary(res)->primary_s;
        if (rs < best_render) best_render = rs;
        double t0 = now();
        if (tt_intersect(accel, rays, n, hits, NULL, &opt) != TT_OK) return fail(ctx, "batch");
        double t1 = now();
        if (tt_intersect(accel, rays, n, hits, NULL, &tiled) != TT_OK) return fail(ctx, "tiled");
        double t2 = now();
        if (tt_intersect_arrays(accel, &ra, n, &ha, NULL, &tiled) != TT_OK)
            return fail(ctx, "arrays");
        double t3 = now();
        if (t1 - t0 < best_aos) best_aos = t1 - t0;
        if (t2 - t1 < best_tiled) best_tiled = t2 - t1;
        if (t3 - t2 < best_soa) best_soa = t3 - t2;
        if (r == 0) {
            size_t bytes;
            const uint8_t *buf = tt_render_hits(res, &bytes);
            for (size_t i = 0; i < n; i++) {
                uint32_t p;
                float tr;
                memcpy(&p, buf + 12 * i, 4);
                memcpy(&tr, buf + 12 * i + 4, 4);
                differ += p != hits[i].prim || p != prim[i] || memcmp(&tr, &t[i], 4) != 0 ||
                          (p != TT_INVALID_ID && memcmp(&tr, &hits[i].t, 4) != 0);
            }
        }
        tt_render_result_destroy(res);
    }
    printf("scene: %s\nview: %s\naccel: %s\nthreads: %d\nrays: %zu\nrounds: %d\n", argv[1],
           argv[3], accel_name, threads, n, rounds);
    printf("render_primary_mrays_per_s: %.3f\n", n / best_render * 1e-6);
    printf("batch_mrays_per_s: %.3f\n", n / best_aos * 1e-6);
    printf("batch_tiled_mrays_per_s: %.3f\n", n / best_tiled * 1e-6);
    printf("batch_arrays_tiled_mrays_per_s: %.3f\n", n / best_soa * 1e-6);
    printf("batch_over_render: %.3f\n", best_render / best_aos);
    printf("batch_tiled_over_render: %.3f\n", best_render / best_tiled);
    printf("batch_arrays_tiled_over_render: %.3f\n", best_render / best_soa);
    printf("rays_differing_from_render: %zu\n", differ);
    free(rays);
    free(hits);
    free(t);
    free(prim);
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return differ ? 1 : 0;
}
