/* The one ray-triangle intersection of the project: watertight (Woop, Benthin
 * & Wald 2013, "Watertight Ray/Triangle Intersection"). Edge functions are
 * evaluated in a sheared space where the ray is the +z axis; a ray through a
 * shared edge or vertex gets the same edge-function value from both triangles,
 * so it can never slip between them. Values of exactly zero are recomputed in
 * double precision, as the paper prescribes. Every structure calls this
 * function, so equal triangles give equal t across all of them. */
#ifndef TT_GEOMETRY_TRIANGLE_H
#define TT_GEOMETRY_TRIANGLE_H

#include "geometry/hd.h"
#include "geometry/ray.h"

/* Tests triangle (a, b, c) against r on [r->tmin, tmax). On a hit returns 1
 * and writes t and the barycentrics u (of b) and v (of c). Degenerate
 * (zero-area) triangles, and rays in a triangle's plane, never hit. */
TT_HD int tt_intersect_triangle(const tt_wray *r, const float *a, const float *b, const float *c,
                                float tmax, float *t_out, float *u_out, float *v_out)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const float ax = a[kx] - r->org[kx], ay = a[ky] - r->org[ky], az = a[kz] - r->org[kz];
    const float bx = b[kx] - r->org[kx], by = b[ky] - r->org[ky], bz = b[kz] - r->org[kz];
    const float cx = c[kx] - r->org[kx], cy = c[ky] - r->org[ky], cz = c[kz] - r->org[kz];
    const float Ax = ax - r->sx * az, Ay = ay - r->sy * az;
    const float Bx = bx - r->sx * bz, By = by - r->sy * bz;
    const float Cx = cx - r->sx * cz, Cy = cy - r->sy * cz;
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        U = (float)((double)Cx * (double)By - (double)Cy * (double)Bx);
        V = (float)((double)Ax * (double)Cy - (double)Ay * (double)Cx);
        W = (float)((double)Bx * (double)Ay - (double)By * (double)Ax);
    }
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return 0;
    const float det = U + V + W;
    if (det == 0.0f) return 0;
    const float T = U * (r->sz * az) + V * (r->sz * bz) + W * (r->sz * cz);
    const float inv_det = 1.0f / det;
    const float t = T * inv_det;
    if (!(t >= r->tmin && t < tmax)) return 0;
    /* A zero-area triangle (coincident or collinear vertices) is no longer
     * exactly degenerate once translated and sheared in float: a ray through
     * one of its vertices gets two zero edge functions and a tiny nonzero
     * third one, and would count as a hit. Its unsheared normal is exactly
     * zero, so it is refused here, only for the few candidates that got this
     * far. Neighbouring triangles cover the segment it lies on. */
    const float e1x = b[0] - a[0], e1y = b[1] - a[1], e1z = b[2] - a[2];
    const float e2x = c[0] - a[0], e2y = c[1] - a[1], e2z = c[2] - a[2];
    if (e1y * e2z - e1z * e2y == 0.0f && e1z * e2x - e1x * e2z == 0.0f &&
        e1x * e2y - e1y * e2x == 0.0f)
        return 0;
    *t_out = t;
    *u_out = V * inv_det;
    *v_out = W * inv_det;
    return 1;
}

#endif
