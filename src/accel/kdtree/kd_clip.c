/* Triangle-box clipping for the builders (Sutherland-Hodgman in double). */
#include "accel/kdtree/kd_clip.h"

#include <math.h>
#include <string.h>

/* A triangle clipped by six planes has at most 3 + 6 vertices. */
#define MAX_POLY KD_CLIP_MAX

typedef struct poly {
    double v[MAX_POLY][3];
    int n;
} poly;

/* Keeps the part with sign * (x[axis] - c) >= 0. Points on the plane stay,
 * so a triangle lying in a face of the box survives. New vertices get the
 * plane coordinate exactly. */
static void clip_plane(const poly *in, poly *out, int axis, double c, double sign)
{
    out->n = 0;
    for (int i = 0; i < in->n; i++) {
        const double *a = in->v[i], *b = in->v[(i + 1) % in->n];
        int ina = sign * (a[axis] - c) >= 0.0, inb = sign * (b[axis] - c) >= 0.0;
        if (ina) memcpy(out->v[out->n++], a, sizeof out->v[0]);
        if (ina != inb) {
            double t = (c - a[axis]) / (b[axis] - a[axis]);
            double *p = out->v[out->n++];
            for (int k = 0; k < 3; k++) p[k] = a[k] + t * (b[k] - a[k]);
            p[axis] = c;
        }
    }
}

/* fmin/fmax without NaN handling (none can occur here); the libm calls
 * are a measurable part of the build otherwise. */
static double dmin(double a, double b) { return a < b ? a : b; }
static double dmax(double a, double b) { return a > b ? a : b; }

static float round_down(double d)
{
    float f = (float)d;
    return ((double)f > d) ? nextafterf(f, -INFINITY) : f;
}

static float round_up(double d)
{
    float f = (float)d;
    return ((double)f < d) ? nextafterf(f, INFINITY) : f;
}

int kd_clip_polygon(const float *tri, const double lo[3], const double hi[3],
                    double out[KD_CLIP_MAX][3])
{
    poly a, b;
    a.n = 3;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) a.v[i][k] = tri[3 * i + k];
    for (int k = 0; k < 3; k++) {
        double tlo = dmin(dmin(a.v[0][k], a.v[1][k]), a.v[2][k]);
        double thi = dmax(dmax(a.v[0][k], a.v[1][k]), a.v[2][k]);
        if (thi < lo[k] || tlo > hi[k]) return 0;
    }
    /* Planes the triangle does not cross are skipped (exactly the same
     * polygon, fewer rounding steps). The two polygons take turns. */
    poly *cur = &a, *next = &b;
    for (int k = 0; k < 3; k++) {
        double tlo = INFINITY, thi = -INFINITY;
        for (int i = 0; i < cur->n; i++) {
            tlo = dmin(tlo, cur->v[i][k]);
            thi = dmax(thi, cur->v[i][k]);
        }
        if (tlo < lo[k]) {
            clip_plane(cur, next, k, lo[k], 1.0);
            poly *t = cur;
            cur = next;
            next = t;
        }
        if (thi > hi[k]) {
            clip_plane(cur, next, k, hi[k], -1.0);
            poly *t = cur;
            cur = next;
            next = t;
        }
        if (cur->n == 0) return 0;
    }
    memcpy(out, cur->v, (size_t)cur->n * sizeof cur->v[0]);
    return cur->n;
}

int kd_clip_triangle(const float *tri, const tt_aabb *box, tt_aabb *out)
{
    tt_aabb tb;
    for (int k = 0; k < 3; k++) {
        float a = tri[k], b = tri[3 + k], c = tri[6 + k];
        tb.lo[k] = a < b ? (a < c ? a : c) : (b < c ? b : c);
        tb.hi[k] = a > b ? (a > c ? a : c) : (b > c ? b : c);
    }
    int inside = 1;
    for (int k = 0; k < 3; k++) {
        if (tb.hi[k] < box->lo[k] || tb.lo[k] > box->hi[k]) return 0;
        if (tb.lo[k] < box->lo[k] || tb.hi[k] > box->hi[k]) inside = 0;
    }
    if (inside) {
        *out = tb;
        return 1;
    }
    double lo[3], hi[3], v[KD_CLIP_MAX][3];
    for (int k = 0; k < 3; k++) {
        lo[k] = box->lo[k];
        hi[k] = box->hi[k];
    }
    int n = kd_clip_polygon(tri, lo, hi, v);
    if (n == 0) return 0;
    double plo[3] = {INFINITY, INFINITY, INFINITY}, phi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            plo[k] = dmin(plo[k], v[i][k]);
            phi[k] = dmax(phi[k], v[i][k]);
        }
    for (int k = 0; k < 3; k++) {
        /* Interpolated coordinates may stray a rounding error outside the
         * box; the clamp keeps every candidate inside the cell. */
        float l = round_down(plo[k]), h = round_up(phi[k]);
        l = l > box->lo[k] ? l : box->lo[k];
        h = h < box->hi[k] ? h : box->hi[k];
        if (l > h) l = h = (l > box->hi[k]) ? box->hi[k] : box->lo[k];
        out->lo[k] = l;
        out->hi[k] = h;
    }
    return 1;
}
