/* Box measures for the R-tree builder on plain float[6] boxes (lo x, y, z,
 * hi x, y, z), and moving one entry in and out of a node's structure-of-
 * arrays bounds. Build-time only (CPU). */
#ifndef TT_ACCEL_RTREE_BOX_H
#define TT_ACCEL_RTREE_BOX_H

#include <math.h>

#include "geometry/hd.h"

/* Plain comparisons: fminf/fmaxf are library calls unless the compiler may
 * assume no NaNs; boxes here never hold NaN. */
static inline float rt_min(float a, float b) { return a < b ? a : b; }
static inline float rt_max(float a, float b) { return a > b ? a : b; }

static inline void rt_box_empty(float b[6])
{
    b[0] = b[1] = b[2] = TT_INF;
    b[3] = b[4] = b[5] = -TT_INF;
}

static inline void rt_box_grow(float b[6], const float o[6])
{
    for (int i = 0; i < 3; i++) {
        b[i] = rt_min(b[i], o[i]);
        b[i + 3] = rt_max(b[i + 3], o[i + 3]);
    }
}

/* The box of one triangle's nine floats (v0, v1, v2). */
static inline void rt_box_of_triangle(const float v[9], float b[6])
{
    for (int k = 0; k < 3; k++) {
        b[k] = rt_min(rt_min(v[k], v[3 + k]), v[6 + k]);
        b[k + 3] = rt_max(rt_max(v[k], v[3 + k]), v[6 + k]);
    }
}

/* The mark of an empty slot or unused child in both packed layouts: all six
 * bounds +inf (rtree_packed.h, rtc_layout.h). */
static inline int rt_box_is_empty_mark(const float b[6])
{
    for (int k = 0; k < 6; k++)
        if (b[k] != TT_INF) return 0;
    return 1;
}

/* A real box: finite bounds, lo <= hi on every axis. */
static inline int rt_box_is_finite(const float b[6])
{
    for (int k = 0; k < 3; k++)
        if (!(isfinite(b[k]) && isfinite(b[k + 3]) && b[k] <= b[k + 3])) return 0;
    return 1;
}

static inline float rt_box_volume(const float b[6])
{
    return (b[3] - b[0]) * (b[4] - b[1]) * (b[5] - b[2]);
}

static inline float rt_box_area(const float b[6])
{
    float x = b[3] - b[0], y = b[4] - b[1], z = b[5] - b[2];
    return 2.0f * (x * y + y * z + z * x);
}

/* Volume of the intersection; 0 when the boxes are disjoint or only touch. */
static inline float rt_box_overlap(const float a[6], const float b[6])
{
    float v = 1.0f;
    for (int i = 0; i < 3; i++) {
        float e = rt_min(a[i + 3], b[i + 3]) - rt_max(a[i], b[i]);
        if (e <= 0.0f) return 0.0f;
        v *= e;
    }
    return v;
}

static inline int rt_box_equal(const float a[6], const float b[6])
{
    for (int i = 0; i < 6; i++)
        if (a[i] != b[i]) return 0;
    return 1;
}

/* Entry i of a node's SoA bounds (six arrays of cap floats). */
static inline void rt_soa_get(const float *soa, int cap, int i, float out[6])
{
    for (int k = 0; k < 6; k++) out[k] = soa[k * cap + i];
}

static inline void rt_soa_put(float *soa, int cap, int i, const float in[6])
{
    for (int k = 0; k < 6; k++) soa[k * cap + i] = in[k];
}

#endif
