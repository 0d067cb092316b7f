/* Triangle-box clipping for the builders (Sutherland-Hodgman in double). */
#include "accel/kdtree/build/kd_clip.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* A triangle clipped by six planes has at most 3 + 6 vertices. */
#define MAX_POLY KD_CLIP_MAX

typedef struct poly {
    /* One slot more: the first vertex is repeated after the last, so that
     * every edge is (v[i], v[i + 1]) with no wrap-around index. */
    double v[MAX_POLY + 1][3];
    int n;
} poly;

/* Keeps the part with x[axis] >= c (keep_above) or x[axis] <= c. Points on
 * the plane stay, so a triangle lying in a face of the box survives. New
 * vertices get the plane coordinate exactly. */
static inline void clip_plane(poly *in, poly *out, int axis, double c, int keep_above)
{
    memcpy(in->v[in->n], in->v[0], sizeof in->v[0]);
    int n = 0;
    int ina = keep_above ? in->v[0][axis] >= c : in->v[0][axis] <= c;
    for (int i = 0; i < in->n; i++) {
        const double *a = in->v[i], *b = in->v[i + 1];
        const int inb = keep_above ? b[axis] >= c : b[axis] <= c;
        if (ina) memcpy(out->v[n++], a, sizeof out->v[0]);
        if (ina != inb) {
            double t = (c - a[axis]) / (b[axis] - a[axis]);
            double *p = out->v[n++];
            for (int k = 0; k < 3; k++) p[k] = a[k] + t * (b[k] - a[k]);
            p[axis] = c;
        }
        ina = inb;
    }
    out->n = n;
}

/* fmin/fmax without NaN handling (none can occur here); the libm calls
 * are a measurable part of the build otherwise. */
static double dmin(double a, double b) { return a < b ? a : b; }
static double dmax(double a, double b) { return a > b ? a : b; }

/* nextafterf(f, +-INFINITY) for a finite f, by stepping the bit pattern:
 * nextafterf is an out-of-line libm call (with scalbn inside) and was a
 * visible part of the build. */
static float step_float(float f, int up)
{
    if (f == 0.0f) return up ? 1.40129846e-45f : -1.40129846e-45f;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    /* Away from zero: magnitude + 1 ulp; towards zero: - 1 ulp. */
    if ((f > 0.0f) == (up != 0)) u++;
    else u--;
    memcpy(&f, &u, sizeof f);
    return f;
}

static float round_down(double d)
{
    float f = (float)d;
    return ((double)f > d) ? step_float(f, 0) : f;
}

static float round_up(double d)
{
    float f = (float)d;
    return ((double)f < d) ? step_float(f, 1) : f;
}

/* Clips the triangle held in a (whose bounds are tlo, thi and touch the
 * box) to the box; returns the resulting polygon, a or b. Planes the
 * polygon does not cross are skipped (exactly the same polygon, fewer
 * rounding steps). Until a plane cuts, the polygon is the triangle and its
 * bounds are known. */
static const poly *clip_to_box(poly *a, poly *b, const double tlo[3], const double thi[3],
                               const double lo[3], const double hi[3])
{
    poly *cur = a, *next = b;
    int cut = 0;
    for (int k = 0; k < 3; k++) {
        double plo = tlo[k], phi = thi[k];
        if (cut) {
            plo = INFINITY;
            phi = -INFINITY;
            for (int i = 0; i < cur->n; i++) {
                plo = dmin(plo, cur->v[i][k]);
                phi = dmax(phi, cur->v[i][k]);
            }
        }
        if (plo < lo[k]) {
            clip_plane(cur, next, k, lo[k], 1);
            poly *t = cur;
            cur = next;
            next = t;
            cut = 1;
        }
        if (phi > hi[k]) {
            clip_plane(cur, next, k, hi[k], 0);
            poly *t = cur;
            cur = next;
            next = t;
            cut = 1;
        }
        if (cur->n == 0) break;
    }
    return cur;
}

static void load_triangle(const float *tri, poly *a)
{
    a->n = 3;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) a->v[i][k] = tri[3 * i + k];
}

int kd_clip_polygon(const float *tri, const double lo[3], const double hi[3],
                    double out[KD_CLIP_MAX][3])
{
    poly a, b;
    load_triangle(tri, &a);
    double tlo[3], thi[3];
    for (int k = 0; k < 3; k++) {
        tlo[k] = dmin(dmin(a.v[0][k], a.v[1][k]), a.v[2][k]);
        thi[k] = dmax(dmax(a.v[0][k], a.v[1][k]), a.v[2][k]);
        if (thi[k] < lo[k] || tlo[k] > hi[k]) return 0;
    }
    const poly *p = clip_to_box(&a, &b, tlo, thi, lo, hi);
    memcpy(out, p->v, (size_t)p->n * sizeof p->v[0]);
    return p->n;
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
    double lo[3], hi[3], tlo[3], thi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = box->lo[k];
        hi[k] = box->hi[k];
        tlo[k] = tb.lo[k];
        thi[k] = tb.hi[k];
    }
    poly a, b;
    load_triangle(tri, &a);
    const poly *p = clip_to_box(&a, &b, tlo, thi, lo, hi);
    if (p->n == 0) return 0;
    double plo[3] = {INFINITY, INFINITY, INFINITY}, phi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < p->n; i++)
        for (int k = 0; k < 3; k++) {
            plo[k] = dmin(plo[k], p->v[i][k]);
            phi[k] = dmax(phi[k], p->v[i][k]);
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
