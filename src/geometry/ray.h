/* A ray prepared once for traversal: inverse direction for slab tests and the
 * shear constants of the watertight triangle test. Shared CPU/GPU. */
#ifndef TT_GEOMETRY_RAY_H
#define TT_GEOMETRY_RAY_H

#include <math.h>

#include "geometry/hd.h"

typedef struct tt_wray {
    float org[3];
    float dir[3];
    float inv[3]; /* finite: +-1e30 stands in for 1/0 (kd-tree plane tests)   */
    float rcp[3]; /* exact IEEE 1/dir: +-inf for a +-0 component (box tests)   */
    float tmin, tmax;
    int kx, ky, kz;   /* kz: the dominant axis of dir                          */
    float sx, sy, sz; /* shear constants (Woop, Benthin & Wald 2013)           */
} tt_wray;

TT_HD float tt_safe_inv(float d)
{
    /* A huge finite value instead of inf: (plane - org) * inv stays 0 for a
     * ray lying in the plane instead of NaN. The kd-tree's plane tests rely
     * on it being finite. The slab test of boxes must not use it: a ray in a
     * box's upper face plane would get the slab [-1e30, 0] and be culled
     * (see rcp and tt_ray_box). */
    return fabsf(d) < 1e-30f ? copysignf(1e30f, d) : 1.0f / d;
}

TT_HD void tt_wray_init(tt_wray *r, const float *org, const float *dir, float tmin, float tmax)
{
    for (int i = 0; i < 3; i++) {
        r->org[i] = org[i];
        r->dir[i] = dir[i];
        r->inv[i] = tt_safe_inv(dir[i]);
        r->rcp[i] = 1.0f / dir[i];
    }
    r->tmin = tmin;
    r->tmax = tmax;
    float ax = fabsf(dir[0]), ay = fabsf(dir[1]), az = fabsf(dir[2]);
    int kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    /* Swapping keeps the triangle's winding, so the sign tests below stay
     * valid for both facings. */
    if (dir[kz] < 0.0f) {
        int t = kx;
        kx = ky;
        ky = t;
    }
    r->kx = kx;
    r->ky = ky;
    r->kz = kz;
    r->sx = dir[kx] / dir[kz];
    r->sy = dir[ky] / dir[kz];
    r->sz = 1.0f / dir[kz];
}

#endif
