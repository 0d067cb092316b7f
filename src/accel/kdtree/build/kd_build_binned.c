/* The binned SAH builder (--kd-build binned): fast by construction.
 *
 * - One flat array of references (kd_bin.h: triangle id and box) used as a
 *   stack: a node's references lie on top of it; the split writes the left
 *   child's after them and packs the right child's in place at the bottom,
 *   then moves the left ones down onto them. The left child, on top, is
 *   built first; the right one waits below. What is on the stack is always
 *   the node being built plus the right children still to build: at most
 *   the references the budget counts as live (kd_should_split), so the
 *   array grows (by doubling, a clean TT error if that fails) to at most
 *   the budget plus one node. No allocation per node.
 * - Split choice by binning all three axes in one pass, all the way down;
 *   the smallest nodes count every box bound exactly instead (kd_bin.h).
 * - A straddler's box is cut at the plane; the triangle is not clipped.
 * - Above kd_par_cutoff references a node's binning pass runs in chunks
 *   on all threads, and its children are tasks, each building its subtree
 *   into arrays of its own; kd_replay (kd_build_par.h) then emits them in
 *   the serial order, so the tree does not depend on the threads. */
#include <math.h>
#include <omp.h>
#include <string.h>

#include "accel/kdtree/build/kd_bin.h"
#include "accel/kdtree/build/kd_build_par.h"

/* The references of one recursion (the whole serial build, or a subtree
 * of a parallel one). */
typedef struct bin_stack {
    kd_bref *ref;
    size_t cap;
    uint32_t *ids; /* a leaf's triangle ids: at most the first node's count */
} bin_stack;

static tt_status reserve(kd_builder *b, bin_stack *s, size_t need)
{
    if (need <= s->cap) return TT_OK;
    size_t cap = 2 * s->cap > need ? 2 * s->cap : need;
    kd_bref *p = tt_realloc_array(b->ctx, s->ref, cap, sizeof *p);
    if (!p) return kd_oom(b);
    s->ref = p;
    s->cap = cap;
    return TT_OK;
}

static void bbox_empty(kd_bbox *x)
{
    for (int k = 0; k < 3; k++) {
        x->lo[k] = INFINITY;
        x->hi[k] = -INFINITY;
    }
}

static void bbox_grow(kd_bbox *x, const kd_bref *r)
{
    for (int k = 0; k < 3; k++) {
        x->lo[k] = r->lo[k] < x->lo[k] ? r->lo[k] : x->lo[k];
        x->hi[k] = r->hi[k] > x->hi[k] ? r->hi[k] : x->hi[k];
    }
}

/* Chunks of a big node's binning pass: a fixed size, so the counts (sums
 * of integers) are the same whatever the threads. */
#define CHUNK 16384u
#define MAX_CHUNKS 64u

static kd_split find_split(const kd_builder *b, const kd_bref *r, uint32_t n, const tt_aabb *cell,
                           const kd_bbox *bounds, int parallel)
{
    if (n <= KD_BIN_SMALL) return kd_bin_exact_small(b, r, n, cell);
    const kd_bin_grid g = kd_bin_grid_of(bounds, n);
    kd_bins bins;
    memset(&bins, 0, sizeof bins);
    uint32_t chunks = parallel ? (n + CHUNK - 1) / CHUNK : 1;
    if (chunks > MAX_CHUNKS) chunks = MAX_CHUNKS;
    if (chunks > 1) {
        kd_bins part[MAX_CHUNKS];
        const uint32_t per = (n + chunks - 1) / chunks;
        for (uint32_t c = 0; c < chunks; c++) {
#pragma omp task shared(part, g) firstprivate(c)
            {
                const uint32_t from = c * per, to = from + per < n ? from + per : n;
                memset(&part[c], 0, sizeof part[c]);
                if (from < to) kd_bin_count(r + from, to - from, &g, &part[c]);
            }
        }
#pragma omp taskwait
        for (uint32_t c = 0; c < chunks; c++)
            for (int k = 0; k < 3; k++)
                for (int j = 0; j < KD_BINS; j++) {
                    bins.start[k][j] += part[c].start[k][j];
                    bins.end[k][j] += part[c].end[k][j];
                }
    } else {
        kd_bin_count(r, n, &g, &bins);
    }
    kd_split s = kd_bin_best(b, &bins, &g, n, bounds, cell);
    /* The binned counts are an estimate; the budget and the comparison
     * with a leaf take the plane's exact ones. A plane beside the boxes
     * (an empty side) has them already: kd_bin_best counts every box on
     * one side there, as kd_classify would. */
    if (s.axis >= 0 && s.n_left != 0 && s.n_right != 0) kd_bin_count_sides(b, r, n, cell, &s);
    return s;
}

/* The float next to finite f towards -infinity (nextafterf without the
 * library call and its special cases). */
static inline float below(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    if (f == 0.0f) u = 0x80000001u; /* the least negative subnormal */
    else u = f > 0.0f ? u - 1 : u + 1;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Rounds a double bound outwards to float (the narrowed bounds are finite:
 * convex combinations of float vertices). */
static inline float down(double x)
{
    const float f = (float)x;
    return (double)f > x ? below(f) : f;
}

static inline float up(double x)
{
    const float f = (float)x;
    return (double)f < x ? -below(-f) : f;
}

/* Narrows box x to [lo, hi] rounded outwards; 0 if nothing is left. */
static inline int narrow_to(kd_bref *x, const double *lo, const double *hi)
{
    for (int k = 0; k < 3; k++) {
        if (!(lo[k] <= hi[k])) return 0;
        const float l = down(lo[k]), h = up(hi[k]);
        x->lo[k] = l > x->lo[k] ? l : x->lo[k];
        x->hi[k] = h < x->hi[k] ? h : x->hi[k];
        if (!(x->lo[k] <= x->hi[k])) return 0;
    }
    return 1;
}

/* Narrows the straddler's boxes l and r (its box already cut at plane p
 * on axis a) to the bounds of the triangle's part in the half-space below
 * and above the plane, computed in double and rounded outwards: still
 * boxes around the triangle's part in each child's cell, much tighter than
 * the cut box for a long thin triangle lying across the cell. The points
 * where edges cross the plane bound both parts: computed once. Returns
 * which sides keep something (KD_SIDE_* bits). */
static int narrow(kd_bref *l, kd_bref *r, const float *v, int a, float p)
{
    double llo[3] = {INFINITY, INFINITY, INFINITY}, lhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double rlo[3] = {INFINITY, INFINITY, INFINITY}, rhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < 3; i++) {
        const float *u = v + 3 * i, *w = v + 3 * ((i + 1) % 3);
        if (u[a] <= p)
            for (int k = 0; k < 3; k++) {
                llo[k] = u[k] < llo[k] ? u[k] : llo[k];
                lhi[k] = u[k] > lhi[k] ? u[k] : lhi[k];
            }
        if (u[a] >= p)
            for (int k = 0; k < 3; k++) {
                rlo[k] = u[k] < rlo[k] ? u[k] : rlo[k];
                rhi[k] = u[k] > rhi[k] ? u[k] : rhi[k];
            }
        /* The edge crosses the plane strictly: its point on it. */
        if ((u[a] < p && w[a] > p) || (u[a] > p && w[a] < p)) {
            const double t = ((double)p - u[a]) / ((double)w[a] - u[a]);
            for (int k = 0; k < 3; k++) {
                const double c = k == a ? (double)p : u[k] + t * ((double)w[k] - u[k]);
                llo[k] = c < llo[k] ? c : llo[k];
                lhi[k] = c > lhi[k] ? c : lhi[k];
                rlo[k] = c < rlo[k] ? c : rlo[k];
                rhi[k] = c > rhi[k] ? c : rhi[k];
            }
        }
    }
    return (narrow_to(l, llo, lhi) ? KD_SIDE_LEFT : 0) | (narrow_to(r, rlo, rhi) ? KD_SIDE_RIGHT : 0);
}

/* Divides r[0, n) by split s (the counts in s an upper bound): the left
 * child's references to l[0, *nl), the right child's to r[0, *nr), in
 * place (never ahead of the reading; l must not overlap r[0, n)). A
 * straddler's box is cut at the plane and narrowed to the triangle's part
 * on each side (dropped where none is left). The children's box unions
 * come out in lb, rb. */
static void partition(const kd_builder *b, kd_bref *r, uint32_t n, const kd_split *s, kd_bref *l,
                      kd_bbox *lb, kd_bbox *rb, uint32_t *nl, uint32_t *nr)
{
    const int a = s->axis;
    uint32_t w = 0, m = 0;
    bbox_empty(lb);
    bbox_empty(rb);
    for (uint32_t i = 0; i < n; i++) {
        kd_bref x = r[i];
        const int side = kd_classify(x.lo[a], x.hi[a], s);
        if (side == KD_SIDE_BOTH) {
            kd_bref y = x;
            y.hi[a] = s->pos;
            x.lo[a] = s->pos;
            const int keep = narrow(&y, &x, b->tri + 9 * (size_t)x.tri, a, s->pos);
            if (keep & KD_SIDE_LEFT) {
                l[m++] = y;
                bbox_grow(lb, &y);
            }
            if (keep & KD_SIDE_RIGHT) {
                r[w++] = x; /* w <= i: the slot written was read already */
                bbox_grow(rb, &x);
            }
        } else if (side == KD_SIDE_LEFT) {
            l[m++] = x;
            bbox_grow(lb, &x);
        } else {
            r[w++] = x;
            bbox_grow(rb, &x);
        }
    }
    *nl = m;
    *nr = w;
}

static tt_status emit_leaf(kd_builder *b, bin_stack *st, size_t base, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++) st->ids[i] = st->ref[base + i].tri;
    return kd_emit_leaf(b, st->ids, n);
}

/* The serial recursion: the node's references are st->ref[base, base+n),
 * the top of the stack. */
static tt_status build(kd_builder *b, bin_stack *st, size_t base, uint32_t n, const tt_aabb *cell,
                       const kd_bbox *bounds, const kd_place *here)
{
    if (kd_par_aborted(b)) return KD_ABORTED;
    kd_split s = {-1, 0.0f, 0, INFINITY, 0, 0};
    if (n > 0 && here->depth < b->max_depth) s = find_split(b, st->ref + base, n, cell, bounds, 0);
    if (!kd_should_split(b, n, here->depth, &s)) return emit_leaf(b, st, base, n);
    uint32_t nl = s.n_left, nr = s.n_right;
    tt_status e = reserve(b, st, base + n + (nr ? nl : 0));
    if (e != TT_OK) return e;
    kd_bbox lb, rb;
    kd_bref *r = st->ref + base;
    if (nl == 0 || nr == 0) {
        /* A plane beside the boxes (the counts are exact): no box
         * straddles it, so the one child's references are the node's as
         * they are, in place (what the partition would make of them, for
         * nothing; a third of the splits on conference). */
        lb = *bounds;
        rb = *bounds;
    } else {
        /* The left child's references above the node's, then moved down
         * onto the right child's. */
        partition(b, r, n, &s, r + n, &lb, &rb, &nl, &nr);
        memmove(r + nr, r + n, (size_t)nl * sizeof *r);
    }
    kd_account_split(b, n, nl, nr);
    tt_aabb lcell, rcell;
    kd_split_cell(cell, &s, &lcell, &rcell);
    uint32_t node;
    kd_place child;
    e = kd_emit_interior(b, &s, cell, here, &node, &child);
    if (e != TT_OK) return e;
    e = build(b, st, base + nr, nl, &lcell, &lb, &child);
    if (e != TT_OK) return e;
    kd_link_right(b, node);
    return build(b, st, base, nr, &rcell, &rb, &child);
}

/* Builds a subtree from refs[0, n) (an array of cap entries, consumed). */
static tt_status build_from(kd_builder *b, kd_bref *refs, size_t cap, uint32_t n, const tt_aabb *cell,
                            const kd_bbox *bounds, const kd_place *here)
{
    bin_stack st = {refs, cap, NULL};
    tt_status e;
    if (n > 0 && !(st.ids = tt_alloc_array(b->ctx, n, sizeof *st.ids))) e = kd_oom(b);
    else e = build(b, &st, 0, n, cell, bounds, here);
    tt_free(b->ctx, st.ref);
    tt_free(b->ctx, st.ids);
    return e;
}

/* The root's references: every triangle with its bounds (inside the scene
 * box, the root cell, by construction; clamped all the same). */
static void root_refs(const kd_builder *b, const tt_aabb *root, kd_bref *r, kd_bbox *bounds)
{
    bbox_empty(bounds);
    for (uint32_t i = 0; i < b->tri_count; i++) {
        const float *t = b->tri + 9 * (size_t)i;
        for (int k = 0; k < 3; k++) {
            float lo = t[k], hi = t[k];
            for (int v = 1; v < 3; v++) {
                lo = t[3 * v + k] < lo ? t[3 * v + k] : lo;
                hi = t[3 * v + k] > hi ? t[3 * v + k] : hi;
            }
            r[i].lo[k] = lo > root->lo[k] ? lo : root->lo[k];
            r[i].hi[k] = hi < root->hi[k] ? hi : root->hi[k];
        }
        r[i].tri = i;
        r[i].pad = 0;
        bbox_grow(bounds, &r[i]);
    }
}

/* ------------------------------------------------------------ parallel */

/* A node built by tasks into sub (see kd_build_par.h). Consumes refs (an
 * array of cap entries). */
static tt_status par_build(kd_sub *sub, kd_bref *refs, size_t cap, uint32_t n, const tt_aabb *cell,
                           kd_bbox bounds, kd_place here)
{
    kd_builder *b = &sub->out;
    kd_split s = {-1, 0.0f, 0, INFINITY, 0, 0};
    if (n >= kd_par_cutoff && here.depth < b->max_depth && !kd_par_aborted(b))
        s = find_split(b, refs, n, cell, &bounds, 1);
    /* Not split here: the serial recursion decides again, the same way. */
    if (s.axis < 0 || !kd_should_split(b, n, here.depth, &s))
        return build_from(b, refs, cap, n, cell, &bounds, &here);
    uint32_t nl = s.n_left, nr = s.n_right;
    /* The left child's references to an array of their own (with room
     * for its children: a subtree built serially uses it as its stack),
     * the right child's in place. */
    const size_t lcap = 2 * (size_t)nl + 64;
    kd_bref *left = tt_alloc_array(b->ctx, lcap, sizeof *left);
    sub->kid[0] = kd_sub_new(b);
    sub->kid[1] = kd_sub_new(b);
    if (!left || !sub->kid[0] || !sub->kid[1]) {
        tt_free(b->ctx, refs);
        tt_free(b->ctx, left);
        return kd_oom(b);
    }
    kd_bbox lb, rb;
    partition(b, refs, n, &s, left, &lb, &rb, &nl, &nr);
    kd_account_split(b, n, nl, nr);
    sub->split = s;
    tt_aabb lcell, rcell;
    kd_split_cell(cell, &s, &lcell, &rcell);
    const kd_place child = kd_child_place(b, &here);
    kd_sub *l = sub->kid[0], *r = sub->kid[1];
#pragma omp task firstprivate(l, left, lcap, nl, lcell, lb, child)
    l->st = par_build(l, left, lcap, nl, &lcell, lb, child);
#pragma omp task firstprivate(r, refs, cap, nr, rcell, rb, child)
    r->st = par_build(r, refs, cap, nr, &rcell, rb, child);
#pragma omp taskwait
    return l->st != TT_OK ? l->st : r->st;
}

/* The parallel build; KD_ABORTED when the budget bound was passed. */
static tt_status build_parallel(kd_builder *b, const tt_aabb *root, int threads)
{
    kd_par par = {0, 0, 0};
    const size_t cap = 2 * (size_t)b->tri_count + 1024;
    kd_bref *refs = tt_alloc_array(b->ctx, cap, sizeof *refs);
    kd_sub *top = kd_sub_new(b);
    tt_status st = TT_OK;
    if (!refs || !top) {
        tt_free(b->ctx, refs);
        st = kd_oom(b);
    } else {
        top->out.par = &par;
        kd_bbox bounds;
        root_refs(b, root, refs, &bounds);
        par.m = b->tri_count;
#pragma omp parallel num_threads(threads)
#pragma omp single
        {
            kd_place here = {0, 0, TT_KD_NO_PARENT};
            st = par_build(top, refs, cap, b->tri_count, root, bounds, here);
        }
        if (par.abort) st = KD_ABORTED;
        if (st == TT_OK) st = kd_replay(b, top, root);
    }
    kd_sub_free(b->ctx, top);
    return st;
}

tt_status kd_build_binned(kd_builder *b, const tt_aabb *root)
{
    const int threads = kd_par_threads(b->ctx);
    if (threads > 1 && b->tri_count >= kd_par_cutoff) {
        tt_status st = build_parallel(b, root, threads);
        if (st != KD_ABORTED) return st;
    }
    /* Room for the root and its left child at once, and a little more:
     * the stack rarely needs to grow. */
    const size_t cap = 2 * (size_t)b->tri_count + 1024;
    kd_bref *refs = tt_alloc_array(b->ctx, cap, sizeof *refs);
    if (!refs) return kd_oom(b);
    kd_bbox bounds;
    root_refs(b, root, refs, &bounds);
    b->live = b->tri_count;
    kd_place here = {0, 0, TT_KD_NO_PARENT};
    return build_from(b, refs, cap, b->tri_count, root, &bounds, &here);
}
