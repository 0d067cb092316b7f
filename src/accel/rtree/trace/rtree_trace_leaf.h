/* The leaf step every R-tree traversal shares: test the triangles of leaf
 * slot n (stored contiguously, in leaf order) on the ray's [tmin, *best).
 * A template per statistics variant (see accel/stats_variant.h); the
 * traversal headers each include it, so the guard below makes it appear
 * once per variant. Always inlined, so the running closest hit stays in
 * registers as it was when each traversal spelled this loop out. */
#include "accel/rtree/layout/rtree_packed.h"
#include "geometry/triangle.h"

#if TT_STATS ? !defined(TT_RT_LEAF_STATS_ONCE) : !defined(TT_RT_LEAF_FAST_ONCE)
#if TT_STATS
#define TT_RT_LEAF_STATS_ONCE
#else
#define TT_RT_LEAF_FAST_ONCE
#endif

/* Narrows *best (with its barycentrics and packed index *found) to every
 * closer hit; with `any` set, returns 1 at the first hit instead. */
TT_RT_INLINE int TT_VARIANT(tt_rt_leaf)(const tt_rtree_packed *TT_RESTRICT t, uint32_t n,
                                        const tt_wray *r, int any, float *best, float *bu,
                                        float *bv, uint32_t *found, tt_ray_stats *stats)
{
    (void)stats;
    TT_COUNT(stats, leaves, 1);
    const uint32_t j = n - t->delta[0];
    const uint32_t a = TT_LDG(t->leaf_start + j), e = TT_LDG(t->leaf_start + j + 1);
    TT_COUNT(stats, triangles, e - a);
    for (uint32_t k = a; k < e; k++) {
        const float *p = t->tri + 9 * (size_t)k;
        float tt, u, v;
        if (tt_intersect_triangle(r, p, p + 3, p + 6, *best, &tt, &u, &v)) {
            if (any) return 1;
            *best = tt;
            *bu = u;
            *bv = v;
            *found = k;
        }
    }
    return 0;
}
#endif
