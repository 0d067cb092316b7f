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

/* A clip in progress: the polygon (cur), the other buffer, and whether
 * a plane has cut it yet (until then it is the triangle, whose bounds are
 * known). */
typedef struct clip_state {
    poly *cur, *next;
    int cut;
} clip_state;

/* Clips the polygon to the slab lo <= x[k] <= hi. Planes the polygon does
 * not cross are skipped (exactly the same polygon, fewer rounding
 * steps). */
static inline void clip_axis(clip_state *s, const double tlo[3], const double thi[3], int k,
                             double lo, double hi)
{
    double plo = tlo[k], phi = thi[k];
    if (s->cut) {
        plo = INFINITY;
        phi = -INFINITY;
        for (int i = 0; i < s->cur->n; i++) {
            plo = dmin(plo, s->cur->v[i][k]);
            phi = dmax(phi, s->cur->v[i][k]);
        }
    }
    if (plo < lo) {
        clip_plane(s->cur, s->next, k, lo, 1);
        poly *t = s->cur;
        s->cur = s->next;
        s->next = t;
        s->cut = 1;
    }
    if (phi > hi) {
        clip_plane(s->cur, s->next, k, hi, 0);
        poly *t = s->cur;
        s->cur = s->next;
        s->next = t;
        s->cut = 1;
    }
}

/* Clips the triangle held in a (whose bounds are tlo, thi and touch the
 * box) to the box, axis by axis from axis k0 on, and returns the polygon
 * (a or b). */
static const poly *clip_from(clip_state *s, const double tlo[3], const double thi[3],
                             const double lo[3], const double hi[3], int k0)
{
    for (int k = k0; k < 3; k++) {
        clip_axis(s, tlo, thi, k, lo[k], hi[k]);
        if (s->cur->n == 0) break;
    }
    return s->cur;
}

static const poly *clip_to_box(poly *a, poly *b, const double tlo[3], const double thi[3],
                               const double lo[3], const double hi[3])
{
    clip_state s = {a, b, 0};
    return clip_from(&s, tlo, thi, lo, hi, 0);
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

enum { PLACE_OUTSIDE, PLACE_INSIDE, PLACE_CROSSES };

static void triangle_bounds(const float *tri, tt_aabb *tb)
{
    for (int k = 0; k < 3; k++) {
        float a = tri[k], b = tri[3 + k], c = tri[6 + k];
        tb->lo[k] = a < b ? (a < c ? a : c) : (b < c ? b : c);
        tb->hi[k] = a > b ? (a > c ? a : c) : (b > c ? b : c);
    }
}

/* Where triangle bounds tb lie against the closed box. */
static int place(const tt_aabb *tb, const tt_aabb *box)
{
    int inside = 1;
    for (int k = 0; k < 3; k++) {
        if (tb->hi[k] < box->lo[k] || tb->lo[k] > box->hi[k]) return PLACE_OUTSIDE;
        if (tb->lo[k] < box->lo[k] || tb->hi[k] > box->hi[k]) inside = 0;
    }
    return inside ? PLACE_INSIDE : PLACE_CROSSES;
}

/* The clipped polygon's bounds, rounded outward to float and clamped to
 * the box; 0 if the polygon is empty. */
static int polygon_bounds(const poly *p, const tt_aabb *box, tt_aabb *out)
{
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

/* The clip works in doubles: the cell's box (lo, hi) and the triangle's
 * bounds (tlo, thi), which clip_axis reads while the polygon is uncut. */
static void boxes_in_double(const tt_aabb *box, const tt_aabb *tb, double lo[3], double hi[3],
                            double tlo[3], double thi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = box->lo[k];
        hi[k] = box->hi[k];
        tlo[k] = tb->lo[k];
        thi[k] = tb->hi[k];
    }
}

int kd_clip_triangle(const float *tri, const tt_aabb *box, tt_aabb *out)
{
    tt_aabb tb;
    triangle_bounds(tri, &tb);
    const int where = place(&tb, box);
    if (where != PLACE_CROSSES) {
        if (where == PLACE_INSIDE) *out = tb;
        return where == PLACE_INSIDE;
    }
    double lo[3], hi[3], tlo[3], thi[3];
    boxes_in_double(box, &tb, lo, hi, tlo, thi);
    poly a, b;
    load_triangle(tri, &a);
    return polygon_bounds(clip_to_box(&a, &b, tlo, thi, lo, hi), box, out);
}

int kd_clip_triangle_split(const float *tri, const tt_aabb *cell, int axis, float pos,
                           tt_aabb *left, tt_aabb *right)
{
    tt_aabb tb, box[2] = {*cell, *cell};
    tt_aabb *out[2] = {left, right};
    box[0].hi[axis] = pos;
    box[1].lo[axis] = pos;
    triangle_bounds(tri, &tb);
    int kept = 0, clip = 0;
    for (int c = 0; c < 2; c++) {
        const int where = place(&tb, &box[c]);
        if (where == PLACE_INSIDE) {
            *out[c] = tb;
            kept |= 1 << c;
        }
        clip |= (where == PLACE_CROSSES) << c;
    }
    if (!clip) return kept;
    /* The children's boxes differ only on the split axis, from which on
     * each child's clip goes its own way: the clip by the axes before it
     * is the same for both and made once. */
    double lo[3], hi[3], tlo[3], thi[3];
    boxes_in_double(cell, &tb, lo, hi, tlo, thi);
    poly a, b;
    load_triangle(tri, &a);
    clip_state shared = {&a, &b, 0};
    for (int k = 0; k < axis && shared.cur->n; k++) clip_axis(&shared, tlo, thi, k, lo[k], hi[k]);
    for (int c = 0; c < 2; c++) {
        if (!(clip >> c & 1)) continue;
        double blo[3] = {lo[0], lo[1], lo[2]}, bhi[3] = {hi[0], hi[1], hi[2]};
        if (c == 0) bhi[axis] = pos;
        else blo[axis] = pos;
        const poly *p = shared.cur;
        if (p->n) {
            /* Each child goes on from a copy of the shared polygon. */
            poly ca, cb;
            ca.n = p->n;
            memcpy(ca.v, p->v, (size_t)p->n * sizeof p->v[0]);
            clip_state own = {&ca, &cb, shared.cut};
            p = clip_from(&own, tlo, thi, blo, bhi, axis);
            kept |= polygon_bounds(p, &box[c], out[c]) << c;
        }
    }
    return kept;
}
