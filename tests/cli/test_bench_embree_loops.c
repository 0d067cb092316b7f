/* The engine table's Embree side (cli/bench/embree/), compiled into this
 * program: Embree's scene of the shared tiny bunny (default flags and
 * robust), its single-ray and 8- / 16-wide packet loops over an image whose
 * size is no multiple of a tile or a packet (so edge lanes are masked), and
 * its occlusion loops over a batch whose size is no multiple of a packet.
 * Every loop must give every ray its own answer: the same triangle as
 * bruteforce for all but a few rays (Embree's test is not watertight), the
 * same occluded flag, and the packet loops the single-ray loop's answers. */
#include "check.h"

#ifndef TT_HAVE_EMBREE
int main(void)
{
    printf("skipped: this build has no Embree\n");
    return 77;
}
#else
#include <math.h>
#include <string.h>

#include "bench/bench_progress.c"
#include "bench/embree/bench_embree_scene.c"
#include "bench/embree/bench_embree_trace.c"

enum { W = 37, H = 29, N = W * H };

int main(void)
{
    tt_context *ctx = NULL;
    CHECK_OK(ctx, tt_context_create(NULL, &ctx));
    tt_scene *s = NULL;
    CHECK_OK(ctx, tt_scene_load(ctx, tt_test_scene_path("bun_zipper_res4.ply"), &s));
    if (!s) return tt_test_finish();
    tt_camera cam = {{-0.0168f, 0.108f, 0.28f}, {-0.0168f, 0.108f, -0.0015f}, {0, 1, 0}, 40.0f,
                     {-0.0168f, 0.18f, 0.05f}, 1};
    static tt_ray rays[N], sh[N];
    static tt_hit truth[N], got[3][N];
    CHECK_OK(ctx, tt_camera_rays(&cam, W, H, rays));
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *bf = NULL;
    CHECK_OK(ctx, tt_accel_build(ctx, s, &bo, &bf));
    CHECK_OK(ctx, tt_intersect(bf, rays, N, truth, NULL, NULL));
    size_t ns = 0;
    for (size_t i = 0; i < N; i++)
        if (truth[i].prim != TT_INVALID_ID && tt_shadow_ray(s, &cam, &rays[i], &truth[i], &sh[ns]))
            ns++;
    CHECK(ns > 100);
    static uint8_t occ_truth[N], occ[3][N];
    CHECK_OK(ctx, tt_occluded(bf, sh, ns, occ_truth, NULL, NULL));

    for (int robust = 0; robust < 2; robust++) {
        double build_s = -1.0;
        size_t mem = 0;
        char err[256] = "";
        bench_embree *e = bench_embree_build(s, robust, 2, &build_s, &mem, err, sizeof err);
        CHECK_MSG(e != NULL, "%s", err);
        if (!e) continue;
        CHECK(build_s >= 0.0 && build_s < 10.0);
        /* at least the mesh (12 bytes a vertex and a triangle) and a BVH */
        CHECK(mem > 12 * (tt_scene_vertex_count(s) + tt_scene_triangle_count(s)));
        const int packets[3] = {1, 8, 16};
        for (int p = 0; p < 3; p++) {
            for (size_t i = 0; i < N; i++) got[p][i] = (tt_hit){-1.0f, -1.0f, -1.0f, 12345};
            memset(occ[p], 7, ns);
            bench_embree_intersect(e, packets[p], rays, W, H, got[p], 2);
            bench_embree_occluded(e, packets[p], sh, ns, occ[p], 2);
            size_t same = 0, flags_ok = 0, written = 0;
            for (size_t i = 0; i < N; i++) {
                same += got[p][i].prim == truth[i].prim;
                written += got[p][i].prim != 12345 &&
                           (got[p][i].prim == TT_INVALID_ID ? isinf(got[p][i].t) : got[p][i].t > 0.0f);
            }
            for (size_t i = 0; i < ns; i++) flags_ok += occ[p][i] == occ_truth[i];
            CHECK_MSG(written == N, "packet %d: %zu of %d rays answered", packets[p], written, N);
            CHECK_MSG(same >= N - 5, "packet %d, robust %d: %zu of %d as bruteforce", packets[p],
                      robust, same, N);
            CHECK_MSG(flags_ok >= ns - 2, "packet %d: %zu of %zu flags as bruteforce", packets[p],
                      flags_ok, ns);
            if (p) {
                size_t as_single = 0;
                for (size_t i = 0; i < N; i++) as_single += got[p][i].prim == got[0][i].prim;
                CHECK_MSG(as_single >= N - 2, "packet %d: %zu of %d as single rays", packets[p],
                          as_single, N);
            }
        }
        bench_embree_destroy(e);
    }
    char version[64];
    bench_embree_version(version, sizeof version);
    CHECK(strncmp(version, "Embree 3.", 9) == 0);
    tt_accel_destroy(bf);
    tt_scene_destroy(s);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
#endif
