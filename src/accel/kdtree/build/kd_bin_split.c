/* The binned builder's split choice (see kd_bin.h): binned SAH (after Wald
 * 2007 and Shevtsov et al. 2007) over the references' boxes, all three axes
 * counted in one pass; the smallest nodes count every box bound exactly
 * instead, without sorting. The cost model is kd_sweep's. */
#include "accel/kdtree/build/kd_bin.h"

#include <math.h>
#include <string.h>

/* The parts of the SAH that depend on the cell only: the area terms of a
 * split plane on each axis. */
typedef struct cell_terms {
    double cap[3], side[3];
    int ok; /* the cell has area: probabilities are defined */
} cell_terms;

static cell_terms terms_of(const tt_aabb *cell)
{
    cell_terms t;
    double ext[3];
    for (int k = 0; k < 3; k++) ext[k] = (double)cell->hi[k] - (double)cell->lo[k];
    const double area = ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0];
    t.ok = area > 0.0;
    for (int k = 0; k < 3; k++) {
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        t.cap[k] = t.ok ? ext[u] * ext[v] / area : 0.0;
        t.side[k] = t.ok ? (ext[u] + ext[v]) / area : 0.0;
    }
    return t;
}

static double cost_at(const kd_builder *b, const cell_terms *t, const tt_aabb *cell, int axis,
                      float pos, uint32_t nl, uint32_t nr)
{
    const double pl = t->cap[axis] + ((double)pos - cell->lo[axis]) * t->side[axis];
    const double pr = t->cap[axis] + ((double)cell->hi[axis] - pos) * t->side[axis];
    double c = b->ct + b->ci * (pl * nl + pr * nr);
    if (nl == 0 || nr == 0) c *= b->empty_factor;
    return c;
}

double kd_bin_cost(const kd_builder *b, const tt_aabb *cell, const kd_split *s)
{
    const cell_terms t = terms_of(cell);
    return cost_at(b, &t, cell, s->axis, s->pos, s->n_left, s->n_right);
}

kd_bin_grid kd_bin_grid_of(const kd_bbox *bounds, uint32_t n)
{
    kd_bin_grid g;
    /* One bin per two references, 4 to KD_BINS: on conference as good a
     * tree as KD_BINS everywhere (SAH cost +1 %) for a tenth less time. */
    const uint32_t nb = n / 2;
    g.bins = nb >= KD_BINS ? KD_BINS : nb < 4 ? 4 : (int)nb;
    for (int k = 0; k < 3; k++) {
        const double ext = (double)bounds->hi[k] - (double)bounds->lo[k];
        g.lo[k] = bounds->lo[k];
        /* A flat axis gets scale 0: every box lands in bin 0 (and an
         * infinite difference times 0, NaN, is clamped to 0 below). */
        g.scale[k] = ext > 0.0 ? (float)(g.bins / ext) : 0.0f;
    }
    return g;
}

/* Four floats and four lanes of comparison masks (GCC/Clang vector
 * extensions: plain SSE2 or NEON, no ISA-specific unit needed). */
typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

void kd_bin_count(const kd_bref *refs, uint32_t n, const kd_bin_grid *g, kd_bins *bins)
{
    /* A reference's lo and hi read 16 bytes at a time (lane 3, the next
     * field, has origin and scale 0 and is never used). Clamped in float
     * before the conversion (NaN compares false and becomes 0): boxes on
     * the union's upper faces land in the last bin. */
    const float top = (float)(g->bins - 1);
    const v4f org = {g->lo[0], g->lo[1], g->lo[2], 0.0f};
    const v4f sc = {g->scale[0], g->scale[1], g->scale[2], 0.0f};
    const v4f zero = {0.0f, 0.0f, 0.0f, 0.0f}, tops = {top, top, top, top};
    for (uint32_t i = 0; i < n; i++) {
        v4f f, h;
        memcpy(&f, refs[i].lo, sizeof f);
        memcpy(&h, refs[i].hi, sizeof h);
        f = (f - org) * sc;
        h = (h - org) * sc;
        f = (v4f)((v4i)f & (f > zero));
        h = (v4f)((v4i)h & (h > zero));
        v4i t = f < tops;
        f = (v4f)(((v4i)f & t) | ((v4i)tops & ~t));
        t = h < tops;
        h = (v4f)(((v4i)h & t) | ((v4i)tops & ~t));
        const v4i fi = __builtin_convertvector(f, v4i), hi = __builtin_convertvector(h, v4i);
        for (int k = 0; k < 3; k++) {
            bins->start[k][fi[k]]++;
            bins->end[k][hi[k]]++;
        }
    }
}

static inline void consider(const kd_builder *b, const cell_terms *t, const tt_aabb *cell, int axis,
                     float pos, int planar_left, uint32_t nl, uint32_t nr, kd_split *best)
{
    /* Only planes strictly inside the cell (kd_sweep's rule). */
    if (!(pos > cell->lo[axis] && pos < cell->hi[axis])) return;
    kd_split_offer(best, cost_at(b, t, cell, axis, pos, nl, nr), axis, pos, planar_left, nl, nr);
}

kd_split kd_bin_best(const kd_builder *b, const kd_bins *bins, const kd_bin_grid *g, uint32_t n,
                     const kd_bbox *bounds, const tt_aabb *cell)
{
    kd_split best = {-1, 0.0f, 0, INFINITY, 0, 0};
    const cell_terms t = terms_of(cell);
    if (!t.ok) return best;
    for (int k = 0; k < 3; k++) {
        /* The empty space beside the boxes: every box on one side (boxes
         * lying in the upper plane are put left with it). */
        consider(b, &t, cell, k, bounds->lo[k], 0, 0, n, &best);
        consider(b, &t, cell, k, bounds->hi[k], 1, n, 0, &best);
        const double lo = bounds->lo[k], ext = (double)bounds->hi[k] - lo;
        if (!(ext > 0.0)) continue;
        const double step = ext / g->bins;
        /* Boundary j lies between bins j - 1 and j: a box starting below
         * it counts left, one ending in bin j or above counts right. */
        uint32_t nl = 0, nr = n;
        for (int j = 1; j < g->bins; j++) {
            nl += bins->start[k][j - 1];
            nr -= bins->end[k][j - 1];
            consider(b, &t, cell, k, (float)(lo + step * j), 0, nl, nr, &best);
        }
    }
    return best;
}

static inline uint32_t lanes(v4i m) { return (uint32_t)-(m[0] + m[1] + m[2] + m[3]); }

/* One axis of kd_bin_exact_small over W vectors of bounds (W constant in
 * each inlined copy: the count loops unroll). */
static inline void exact_axis(const kd_builder *b, const cell_terms *t, const kd_bref *refs, uint32_t n,
                              const tt_aabb *cell, int k, int W, kd_split *best)
{
    /* The boxes' bounds on this axis; unused slots count nowhere. */
    float fl[KD_BIN_SMALL], fh[KD_BIN_SMALL];
    for (int i = 0; i < 4 * W; i++) {
        fl[i] = (uint32_t)i < n ? refs[i].lo[k] : INFINITY;
        fh[i] = (uint32_t)i < n ? refs[i].hi[k] : -INFINITY;
    }
    v4f lo[KD_BIN_SMALL / 4], hi[KD_BIN_SMALL / 4];
    memcpy(lo, fl, sizeof lo);
    memcpy(hi, fh, sizeof hi);
    for (uint32_t c = 0; c < 2 * n; c++) {
        const float p = c < n ? fl[c] : fh[c - n];
        /* A flat box's upper bound is its lower one: tried already. */
        if (c >= n && p == fl[c - n]) continue;
        if (!(p > cell->lo[k] && p < cell->hi[k])) continue;
        /* kd_classify's sides: a box starting below p is left (or
         * both), one ending above p right (or both), one lying in p on
         * the planar side. */
        const v4f pv = {p, p, p, p};
        v4i l = {0, 0, 0, 0}, r = l, in = l;
        for (int j = 0; j < W; j++) {
            l += lo[j] < pv;
            r += hi[j] > pv;
            in += (lo[j] == pv) & (hi[j] == pv);
        }
        const uint32_t nl = lanes(l), nr = lanes(r), planar = lanes(in);
        /* Planar boxes right, then left (the sweep's order of trial). */
        consider(b, t, cell, k, p, 0, nl, nr + planar, best);
        if (planar) consider(b, t, cell, k, p, 1, nl + planar, nr, best);
    }
}

kd_split kd_bin_exact_small(const kd_builder *b, const kd_bref *refs, uint32_t n, const tt_aabb *cell)
{
    kd_split best = {-1, 0.0f, 0, INFINITY, 0, 0};
    const cell_terms t = terms_of(cell);
    if (!t.ok) return best;
    for (int k = 0; k < 3; k++) {
        if (n <= 4) exact_axis(b, &t, refs, n, cell, k, 1, &best);
        else if (n <= 8) exact_axis(b, &t, refs, n, cell, k, 2, &best);
        else if (n <= 12) exact_axis(b, &t, refs, n, cell, k, 3, &best);
        else exact_axis(b, &t, refs, n, cell, k, 4, &best);
    }
    return best;
}

void kd_bin_count_sides(const kd_builder *b, const kd_bref *refs, uint32_t n, const tt_aabb *cell,
                        kd_split *s)
{
    uint32_t nl = 0, nr = 0;
    const int a = s->axis;
    for (uint32_t i = 0; i < n; i++) {
        const int side = kd_classify(refs[i].lo[a], refs[i].hi[a], s);
        nl += (side & KD_SIDE_LEFT) != 0;
        nr += (side & KD_SIDE_RIGHT) != 0;
    }
    s->n_left = nl;
    s->n_right = nr;
    s->cost = kd_bin_cost(b, cell, s);
}
