/* The whole per-pixel work of the GPU's kd-tree kernels, as TT_HD templates
 * (see accel/stats_variant.h; include once per variant), like
 * gpu_pixel_rtree.h: the pixel's primary ray started from the eye's node,
 * and the shadow ray from its hit started from the node the primary ray
 * ended in, exactly as the CPU renderer starts them. Compiled as C by
 * tests/cuda/test_single_source.c too. */
#include "accel/kdtree/trace/kd_trace.h"
#include "render/camera_hd.h"

/* The primary ray of pixel (x, y) with `traversal` (TT_KD_SLTR or
 * TT_KD_HTR) from start node `hint`; *prim and *dist get the closest hit,
 * *end the augmented node the ray ended in (the shadow ray's start). */
TT_HD void TT_VARIANT(tt_gpu_kd_primary)(const tt_kd_view *T, int traversal, uint32_t hint,
                                         const tt_camera_basis *b, uint32_t x, uint32_t y,
                                         uint32_t *prim, float *dist, uint32_t *end,
                                         tt_ray_stats *stats)
{
    tt_ray r;
    tt_wray w;
    tt_hit h;
    tt_camera_basis_ray(b, x, y, &r);
    tt_wray_init(&w, r.org, r.dir, r.tmin, r.tmax);
    TT_VARIANT(tt_kd_intersect)(T, traversal, &w, hint, &h, end, stats);
    *prim = h.prim;
    *dist = h.prim == TT_INVALID_ID ? TT_INF : h.t;
}

/* The shadow flag of pixel (x, y) whose primary ray hit triangle prim at
 * dist and ended in node `hint` (the caller has checked there is a light
 * and a hit). The kd-tree's view holds the scene's triangles in load order. */
TT_HD int TT_VARIANT(tt_gpu_kd_shadow)(const tt_kd_view *T, int traversal, uint32_t hint,
                                       const tt_camera_basis *b, const float *light, float eps,
                                       uint32_t x, uint32_t y, uint32_t prim, float dist,
                                       tt_ray_stats *stats)
{
    tt_ray r, s;
    tt_wray w;
    uint32_t end;
    tt_camera_basis_ray(b, x, y, &r);
    tt_shadow_ray_from(T->tri + 9 * (size_t)prim, light, eps, &r, dist, &s);
    tt_wray_init(&w, s.org, s.dir, s.tmin, s.tmax);
    return TT_VARIANT(tt_kd_occluded)(T, traversal, &w, hint, TT_INVALID_ID, &end, stats);
}
