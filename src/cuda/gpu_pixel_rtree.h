/* The whole per-pixel work of the GPU's R-tree kernels, as TT_HD templates
 * (see accel/stats_variant.h; include once per variant): make the pixel's
 * primary ray (render/camera_hd.h), trace it, and from its hit the shadow
 * ray. A kernel is a thin wrapper that maps a thread to a pixel and calls
 * these; tests/cuda/test_single_source.c compiles this same header as C
 * with TT_NO_SIMD and checks it ray by ray against bruteforce, so the CPU
 * tests run exactly the code the GPU runs. */
#include "accel/rtree/trace/rtree_trace_ordered.h"
#include "accel/rtree/trace/rtree_trace_stackless.h"
#include "accel/rtree/trace/rtc_trace_stackless.h"
#include "render/camera_hd.h"

#ifndef TT_CUDA_GPU_PIXEL_RTREE_ONCE
#define TT_CUDA_GPU_PIXEL_RTREE_ONCE
/* The traversal of a ray from org: the forced one, or for TT_RTREE_AUTO the
 * choice of rt_locate (rtree_vtable.c): stackless when org is in the root box
 * (closed), ordered outside. */
TT_HD int tt_gpu_rt_pick(int traversal, const float *root_box, const float *org)
{
    if (traversal != TT_RTREE_AUTO) return traversal;
    const int inside = org[0] >= root_box[0] && org[0] <= root_box[3] && org[1] >= root_box[1] &&
                       org[1] <= root_box[4] && org[2] >= root_box[2] && org[2] <= root_box[5];
    return inside ? TT_RTREE_STACKLESS : TT_RTREE_ORDERED;
}
#endif

/* The primary ray of pixel (x, y) with traversal `which` (stackless or
 * ordered: the eye's choice, made once per frame); *prim and *dist get the
 * closest hit (TT_INVALID_ID and +inf on a miss). */
TT_HD void TT_VARIANT(tt_gpu_rt_primary)(const tt_rtree_packed *t, int which,
                                         const tt_camera_basis *b, uint32_t x, uint32_t y,
                                         uint32_t *prim, float *dist, tt_ray_stats *stats)
{
    tt_ray r;
    tt_wray w;
    tt_hit h;
    tt_camera_basis_ray(b, x, y, &r);
    tt_wray_init(&w, r.org, r.dir, r.tmin, r.tmax);
    if (which == TT_RTREE_ORDERED) TT_VARIANT(tt_rt_ordered)(t, &w, 0, &h, stats);
    else TT_VARIANT(tt_rt_stackless)(t, &w, 0, &h, stats);
    *prim = h.prim;
    *dist = h.prim == TT_INVALID_ID ? TT_INF : h.t;
}

/* The shadow flag of pixel (x, y) whose primary ray hit triangle prim at
 * dist (the caller has checked there is a light and a hit): the shadow ray
 * of the conventions towards light, traced with `traversal` (TT_RTREE_AUTO:
 * chosen by the shadow ray's origin, as on the CPU). tri: the scene's
 * triangles in load order. */
TT_HD int TT_VARIANT(tt_gpu_rt_shadow)(const tt_rtree_packed *t, int traversal,
                                       const float *root_box, const tt_camera_basis *b,
                                       const float *tri, const float *light, float eps,
                                       uint32_t x, uint32_t y, uint32_t prim, float dist,
                                       tt_ray_stats *stats)
{
    tt_ray r, s;
    tt_wray w;
    tt_camera_basis_ray(b, x, y, &r);
    tt_shadow_ray_from(tri + 9 * (size_t)prim, light, eps, &r, dist, &s);
    tt_wray_init(&w, s.org, s.dir, s.tmin, s.tmax);
    if (tt_gpu_rt_pick(traversal, root_box, s.org) == TT_RTREE_ORDERED)
        return TT_VARIANT(tt_rt_ordered)(t, &w, 1, NULL, stats);
    return TT_VARIANT(tt_rt_stackless)(t, &w, 1, NULL, stats);
}

/* The same two steps on the compact layout (rtc_layout.h), whose GPU
 * traversal is the stackless one (the CPU's stack traversal is its SIMD
 * form). */
TT_HD void TT_VARIANT(tt_gpu_rtc_primary)(const tt_rtc *t, const tt_camera_basis *b, uint32_t x,
                                          uint32_t y, uint32_t *prim, float *dist,
                                          tt_ray_stats *stats)
{
    tt_ray r;
    tt_wray w;
    tt_hit h;
    tt_camera_basis_ray(b, x, y, &r);
    tt_wray_init(&w, r.org, r.dir, r.tmin, r.tmax);
    TT_VARIANT(tt_rtc_stackless)(t, &w, 0, &h, stats);
    *prim = h.prim;
    *dist = h.prim == TT_INVALID_ID ? TT_INF : h.t;
}

TT_HD int TT_VARIANT(tt_gpu_rtc_shadow)(const tt_rtc *t, const tt_camera_basis *b, const float *tri,
                                        const float *light, float eps, uint32_t x, uint32_t y,
                                        uint32_t prim, float dist, tt_ray_stats *stats)
{
    tt_ray r, s;
    tt_wray w;
    tt_camera_basis_ray(b, x, y, &r);
    tt_shadow_ray_from(tri + 9 * (size_t)prim, light, eps, &r, dist, &s);
    tt_wray_init(&w, s.org, s.dir, s.tmin, s.tmax);
    return TT_VARIANT(tt_rtc_stackless)(t, &w, 1, NULL, stats);
}
