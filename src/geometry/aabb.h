/* Axis-aligned boxes and the ray-box slab test, shared CPU/GPU. */
#ifndef TT_GEOMETRY_AABB_H
#define TT_GEOMETRY_AABB_H

#include <math.h>

#include "geometry/hd.h"
#include "geometry/ray.h"

typedef struct tt_aabb {
    float lo[3];
    float hi[3];
} tt_aabb;

TT_HD tt_aabb tt_aabb_empty(void)
{
    tt_aabb b = {{TT_INF, TT_INF, TT_INF}, {-TT_INF, -TT_INF, -TT_INF}};
    return b;
}

TT_HD int tt_aabb_is_empty(const tt_aabb *b) { return !(b->lo[0] <= b->hi[0]); }

TT_HD void tt_aabb_grow_point(tt_aabb *b, const float *p)
{
    for (int i = 0; i < 3; i++) {
        b->lo[i] = fminf(b->lo[i], p[i]);
        b->hi[i] = fmaxf(b->hi[i], p[i]);
    }
}

TT_HD void tt_aabb_grow(tt_aabb *b, const tt_aabb *o)
{
    for (int i = 0; i < 3; i++) {
        b->lo[i] = fminf(b->lo[i], o->lo[i]);
        b->hi[i] = fmaxf(b->hi[i], o->hi[i]);
    }
}

TT_HD tt_aabb tt_aabb_union(tt_aabb a, const tt_aabb *b)
{
    tt_aabb_grow(&a, b);
    return a;
}

TT_HD float tt_aabb_extent(const tt_aabb *b, int axis) { return b->hi[axis] - b->lo[axis]; }

TT_HD float tt_aabb_volume(const tt_aabb *b)
{
    if (tt_aabb_is_empty(b)) return 0.0f;
    return tt_aabb_extent(b, 0) * tt_aabb_extent(b, 1) * tt_aabb_extent(b, 2);
}

/* Surface area (the 3D analogue of the R*-tree's margin is in the R-tree). */
TT_HD float tt_aabb_area(const tt_aabb *b)
{
    if (tt_aabb_is_empty(b)) return 0.0f;
    float x = tt_aabb_extent(b, 0), y = tt_aabb_extent(b, 1), z = tt_aabb_extent(b, 2);
    return 2.0f * (x * y + y * z + z * x);
}

/* Volume of the intersection of two boxes (0 if disjoint). */
TT_HD float tt_aabb_overlap(const tt_aabb *a, const tt_aabb *b)
{
    float v = 1.0f;
    for (int i = 0; i < 3; i++) {
        float e = fminf(a->hi[i], b->hi[i]) - fmaxf(a->lo[i], b->lo[i]);
        if (e <= 0.0f) return 0.0f;
        v *= e;
    }
    return v;
}

TT_HD int tt_aabb_contains_point(const tt_aabb *b, const float *p)
{
    return p[0] >= b->lo[0] && p[0] <= b->hi[0] && p[1] >= b->lo[1] && p[1] <= b->hi[1] &&
           p[2] >= b->lo[2] && p[2] <= b->hi[2];
}

/* min / max as plain comparisons: fminf / fmaxf must honour NaN, which keeps
 * them out of line (libm calls) at ISO C flags. */
TT_HD float tt_minf(float a, float b) { return a < b ? a : b; }
TT_HD float tt_maxf(float a, float b) { return a > b ? a : b; }

/* Exact slab test (Williams, Barrus, Morley & Shirley 2005, with NaN-aware
 * accumulation): with the true inverse direction rcp (+-inf for a +-0
 * component), the near plane of each axis is chosen by the direction's sign
 * and (plane - org) * rcp is
 *  - +inf (near) / -inf (far) when the ray runs parallel outside the slab:
 *    the box is missed;
 *  - -inf (near) / +inf (far) when it runs strictly inside: no constraint;
 *  - NaN (0 * inf) only when it lies exactly in that plane, i.e. on the
 *    closed box's face: no constraint either.
 * The accumulations below ignore a NaN candidate (a comparison with NaN is
 * false, so the accumulator stays), which gives exactly the closed-box
 * answer for rays lying in a face plane of either sign of zero. */
TT_HD float tt_slab_near(float t, float acc) { return t > acc ? t : acc; }
TT_HD float tt_slab_far(float t, float acc) { return t < acc ? t : acc; }

/* Conservative slab test on the ray's [tmin, tmax). Returns the entry
 * distance, or +inf if the box is missed. The far distance is widened by a
 * few ulps (Ize 2013) away from t = 0, and the entry lowered by a relative 2^-16 before it is
 * compared with tmax: the triangle test computes t differently, and a
 * triangle lying in a flat box's face can come out a few ulps nearer than the
 * box's rounded entry. A parallel ray outside a slab makes tnear +inf, whose
 * lowered entry inf - inf is NaN and fails `entry < tmax`: a miss. */
TT_HD float tt_ray_box(const tt_wray *r, const float *lo, const float *hi, float tmax)
{
    float tnear = r->tmin, tfar = TT_INF;
    for (int k = 0; k < 3; k++) {
        const int neg = r->rcp[k] < 0.0f;
        const float tn = ((neg ? hi[k] : lo[k]) - r->org[k]) * r->rcp[k];
        const float tf = ((neg ? lo[k] : hi[k]) - r->org[k]) * r->rcp[k];
        tnear = tt_slab_near(tn, tnear);
        tfar = tt_slab_far(tf, tfar);
    }
    /* widened away from the origin by a relative 2^-22 (1 + 2 gamma(3)
     * rounded to float): for tfar >= 0 exactly tfar * 1.00000024f, and a
     * negative tfar (a box behind the origin, found with a negative tmin)
     * is widened too instead of shrunk */
    tfar += fabsf(tfar) * (1.0f / 4194304.0f);
    const float entry = tnear - fabsf(tnear) * (1.0f / 65536.0f);
    return (tnear <= tfar && entry < tmax) ? entry : TT_INF;
}

#endif
