/* Bruteforce traversal template (see accel/stats_variant.h): every triangle
 * is tested. The reference every other structure is checked against. */
#include <stdint.h>

#include "geometry/triangle.h"

TT_HD void TT_VARIANT(tt_bf_intersect)(const float *tri, uint32_t count, const tt_wray *r,
                                        tt_hit *hit, tt_ray_stats *stats)
{
    float best = r->tmax, u, v, t;
    uint32_t prim = TT_INVALID_ID;
    float bu = 0.0f, bv = 0.0f;
    (void)stats;
    for (uint32_t i = 0; i < count; i++) {
        const float *p = tri + 9 * (size_t)i;
        if (tt_intersect_triangle(r, p, p + 3, p + 6, best, &t, &u, &v)) {
            best = t;
            prim = i;
            bu = u;
            bv = v;
        }
    }
    TT_COUNT(stats, triangles, count);
    TT_COUNT(stats, rays, 1);
    hit->t = prim == TT_INVALID_ID ? TT_INF : best;
    hit->u = bu;
    hit->v = bv;
    hit->prim = prim;
}

TT_HD int TT_VARIANT(tt_bf_occluded)(const float *tri, uint32_t count, const tt_wray *r,
                                      tt_ray_stats *stats)
{
    float u, v, t;
    (void)stats;
    TT_COUNT(stats, rays, 1);
    for (uint32_t i = 0; i < count; i++) {
        const float *p = tri + 9 * (size_t)i;
        TT_COUNT(stats, triangles, 1);
        if (tt_intersect_triangle(r, p, p + 3, p + 6, r->tmax, &t, &u, &v)) return 1;
    }
    return 0;
}
