/* The O(N log^2 N) builder (Wald & Havran 2006, section 4.2): every node
 * generates the split candidates of its triangles' clipped bounds and sorts
 * them anew, O(n log n) per node.
 *
 * A node carries each triangle with its clipped bounds. A triangle that
 * goes to one side only keeps its bounds (its clipped part is the same
 * polygon in the child cell); one that straddles the plane is clipped again
 * to each child's cell. The O(N log N) builder does exactly the same with
 * its event lists, so both see identical candidates everywhere. */
#include <math.h>
#include <omp.h>
#include <string.h>

#include "accel/kdtree/build/kd_build.h"
#include "accel/kdtree/build/kd_build_par.h"
#include "accel/kdtree/build/kd_clip.h"

/* A triangle with the bounds of its part inside the node's cell (only
 * this builder keeps them; the binned one has its own reference boxes). */
typedef struct item {
    uint32_t tri;
    tt_aabb box;
} item;

typedef struct n2_state {
    tt_context *ctx;
    uint64_t *ev, *tmp; /* 2 N events of one axis and the sort's scratch  */
    uint32_t *ids;      /* a leaf's triangle ids                           */
} n2_state;

/* One axis' exact candidates: generated, sorted, swept into *best. */
static void sweep_axis(const kd_builder *b, n2_state *s, const item *items, uint32_t n,
                       const tt_aabb *cell, int axis, kd_split *best)
{
    size_t m = 0;
    for (uint32_t i = 0; i < n; i++)
        m += kd_events_of(s->ev + m, items[i].box.lo[axis], items[i].box.hi[axis], items[i].tri);
    /* A comparison sort, as the algorithm's name says: O(n log n) per
     * node, O(N log^2 N) in all. A radix sort here would make this an
     * O(N log N) builder too (with a bigger constant than the one that
     * sorts once), and the two would no longer be the algorithms the
     * issue and W&H compare. */
    kd_sort_events(s->ev, s->tmp, m);
    kd_sweep(b, s->ev, m, n, cell, axis, best);
}

static kd_split find_split(const kd_builder *b, n2_state *s, const item *items, uint32_t n,
                           const tt_aabb *cell)
{
    kd_split best = {-1, 0.0f, 0, INFINITY, 0, 0};
    for (int axis = 0; axis < 3; axis++) sweep_axis(b, s, items, n, cell, axis, &best);
    return best;
}

/* Divides a node's items between its children (clipping the straddlers
 * again to each child's cell). Consumes items. */
static tt_status split_items(kd_builder *b, item *items, uint32_t n, const kd_split *split,
                             const tt_aabb *lcell, const tt_aabb *rcell, item **left, uint32_t *n_left,
                             item **right, uint32_t *n_right)
{
    uint32_t nl = 0, nr = 0;
    for (uint32_t i = 0; i < n; i++) {
        int side = kd_classify(items[i].box.lo[split->axis], items[i].box.hi[split->axis], split);
        nl += (side & KD_SIDE_LEFT) != 0;
        nr += (side & KD_SIDE_RIGHT) != 0;
    }
    item *l = tt_alloc_array(b->ctx, nl, sizeof *l);
    item *r = tt_alloc_array(b->ctx, nr, sizeof *r);
    if (!l || !r) {
        tt_free(b->ctx, l);
        tt_free(b->ctx, r);
        tt_free(b->ctx, items);
        return kd_oom(b);
    }
    nl = nr = 0;
    for (uint32_t i = 0; i < n; i++) {
        int side = kd_classify(items[i].box.lo[split->axis], items[i].box.hi[split->axis], split);
        if (side == KD_SIDE_LEFT) l[nl++] = items[i];
        else if (side == KD_SIDE_RIGHT) r[nr++] = items[i];
        else {
            const float *t = b->tri + 9 * (size_t)items[i].tri;
            item it = {items[i].tri, {{0, 0, 0}, {0, 0, 0}}};
            /* A straddler whose clipped part turns out empty on one side
             * (it only grazed the cell) is dropped there. */
            if (kd_clip_triangle(t, lcell, &it.box)) l[nl++] = it;
            if (kd_clip_triangle(t, rcell, &it.box)) r[nr++] = it;
        }
    }
    tt_free(b->ctx, items);
    kd_account_split(b, n, nl, nr);
    *left = l;
    *right = r;
    *n_left = nl;
    *n_right = nr;
    return TT_OK;
}

/* Consumes (frees) items. */
static tt_status build(kd_builder *b, n2_state *s, item *items, uint32_t n, const tt_aabb *cell,
                       const kd_place *here)
{
    if (kd_par_aborted(b)) {
        tt_free(b->ctx, items);
        return KD_ABORTED;
    }
    kd_split split = {-1, 0.0f, 0, INFINITY, 0, 0};
    if (n > 0 && here->depth < b->max_depth) split = find_split(b, s, items, n, cell);
    if (!kd_should_split(b, n, here->depth, &split)) {
        for (uint32_t i = 0; i < n; i++) s->ids[i] = items[i].tri;
        tt_free(b->ctx, items);
        return kd_emit_leaf(b, s->ids, n);
    }
    tt_aabb lcell, rcell;
    kd_split_cell(cell, &split, &lcell, &rcell);
    item *left, *right;
    uint32_t nl, nr;
    tt_status st = split_items(b, items, n, &split, &lcell, &rcell, &left, &nl, &right, &nr);
    if (st != TT_OK) return st;
    uint32_t node;
    kd_place child;
    st = kd_emit_interior(b, &split, cell, here, &node, &child);
    if (st != TT_OK) {
        tt_free(b->ctx, left);
        tt_free(b->ctx, right);
        return st;
    }
    st = build(b, s, left, nl, &lcell, &child);
    if (st != TT_OK) {
        tt_free(b->ctx, right);
        return st;
    }
    kd_link_right(b, node);
    return build(b, s, right, nr, &rcell, &child);
}

/* The scratch of a build (or of one thread of it): 0 when out of memory. */
static int state_alloc(n2_state *s, tt_context *ctx, uint32_t n)
{
    s->ctx = ctx;
    s->ev = tt_alloc_array(ctx, 2 * (size_t)n, sizeof *s->ev);
    s->tmp = tt_alloc_array(ctx, 2 * (size_t)n, sizeof *s->tmp);
    s->ids = tt_alloc_array(ctx, n, sizeof *s->ids);
    return s->ev && s->tmp && s->ids;
}

static void state_free(n2_state *s)
{
    if (!s->ctx) return;
    tt_free(s->ctx, s->ev);
    tt_free(s->ctx, s->tmp);
    tt_free(s->ctx, s->ids);
    memset(s, 0, sizeof *s);
}

/* The root's items: the triangles that touch the root cell. */
static uint32_t root_items(const kd_builder *b, const tt_aabb *root, item *items)
{
    uint32_t m = 0;
    for (uint32_t i = 0; i < b->tri_count; i++) {
        items[m].tri = i;
        if (kd_clip_triangle(b->tri + 9 * (size_t)i, root, &items[m].box)) m++;
    }
    return m;
}

/* ------------------------------------------------------------ parallel */

typedef struct n2_par {
    const kd_builder *proto;
    n2_state *scratch; /* one per thread, allocated by its thread */
} n2_par;

static n2_state *my_state(n2_par *p)
{
    n2_state *s = &p->scratch[omp_get_thread_num()];
    if (s->ctx) return s;
    if (state_alloc(s, p->proto->ctx, p->proto->tri_count)) return s;
    state_free(s);
    s->ctx = NULL;
    return NULL;
}

/* A node built by tasks into sub (see kd_build_par.h). Consumes items. */
static tt_status par_build(n2_par *p, kd_sub *sub, item *items, uint32_t n, const tt_aabb *cell,
                           kd_place here)
{
    kd_builder *b = &sub->out;
    kd_split split = {-1, 0.0f, 0, INFINITY, 0, 0};
    int oom = 0;
    if (n >= kd_par_cutoff && here.depth < b->max_depth && !kd_par_aborted(b)) {
        /* The three axes at once, each with its thread's scratch; the
         * lowest cost wins, the lower axis on a tie, as in the serial
         * loop. */
        kd_split ax[3];
        for (int k = 0; k < 3; k++) {
            ax[k] = split;
#pragma omp task shared(ax, oom) firstprivate(k)
            {
                n2_state *s = my_state(p);
                if (s) sweep_axis(b, s, items, n, cell, k, &ax[k]);
                else {
#pragma omp atomic write
                    oom = 1;
                }
            }
        }
#pragma omp taskwait
        for (int k = 0; k < 3; k++)
            if (ax[k].cost < split.cost) split = ax[k];
    }
    n2_state *s = my_state(p);
    if (!s || oom) {
        tt_free(b->ctx, items);
        return kd_oom(b);
    }
    /* Not split here (small, or no split pays): the serial recursion
     * decides again, the same way. */
    if (split.axis < 0 || !kd_should_split(b, n, here.depth, &split))
        return build(b, s, items, n, cell, &here);
    tt_aabb lcell, rcell;
    kd_split_cell(cell, &split, &lcell, &rcell);
    item *left, *right;
    uint32_t nl, nr;
    tt_status st = split_items(b, items, n, &split, &lcell, &rcell, &left, &nl, &right, &nr);
    if (st != TT_OK) return st;
    sub->kid[0] = kd_sub_new(b);
    sub->kid[1] = kd_sub_new(b);
    if (!sub->kid[0] || !sub->kid[1]) {
        tt_free(b->ctx, left);
        tt_free(b->ctx, right);
        return kd_oom(b);
    }
    sub->split = split;
    const kd_place child = kd_child_place(b, &here);
    kd_sub *l = sub->kid[0], *r = sub->kid[1];
#pragma omp task firstprivate(l, left, nl, lcell)
    l->st = par_build(p, l, left, nl, &lcell, child);
#pragma omp task firstprivate(r, right, nr, rcell)
    r->st = par_build(p, r, right, nr, &rcell, child);
#pragma omp taskwait
    return l->st != TT_OK ? l->st : r->st;
}

/* The parallel build; KD_ABORTED when the budget bound was passed. */
static tt_status build_parallel(kd_builder *b, const tt_aabb *root, int threads)
{
    kd_par par = {0, 0, 0};
    n2_par p = {b, NULL};
    p.scratch = tt_calloc(b->ctx, (size_t)threads, sizeof *p.scratch);
    item *items = tt_alloc_array(b->ctx, b->tri_count, sizeof *items);
    kd_sub *top = kd_sub_new(b);
    tt_status st = TT_OK;
    if (!p.scratch || !items || !top) {
        tt_free(b->ctx, items);
        st = kd_oom(b);
    } else {
        top->out.par = &par;
        par.m = root_items(b, root, items);
#pragma omp parallel num_threads(threads)
#pragma omp single
        {
            kd_place here = {0, 0, TT_KD_NO_PARENT};
            st = par_build(&p, top, items, (uint32_t)par.m, root, here);
        }
        if (par.abort) st = KD_ABORTED;
        if (st == TT_OK) st = kd_replay(b, top, root);
    }
    if (p.scratch)
        for (int t = 0; t < threads; t++) state_free(&p.scratch[t]);
    tt_free(b->ctx, p.scratch);
    kd_sub_free(b->ctx, top);
    return st;
}

tt_status kd_build_nlog2n(kd_builder *b, const tt_aabb *root)
{
    const int threads = kd_par_threads(b->ctx);
    if (threads > 1 && b->tri_count >= kd_par_cutoff) {
        tt_status st = build_parallel(b, root, threads);
        if (st != KD_ABORTED) return st;
    }
    n2_state s;
    memset(&s, 0, sizeof s);
    item *items = tt_alloc_array(b->ctx, b->tri_count, sizeof *items);
    tt_status st;
    if (!state_alloc(&s, b->ctx, b->tri_count) || !items) {
        tt_free(b->ctx, items);
        st = kd_oom(b);
    } else {
        kd_place here = {0, 0, TT_KD_NO_PARENT};
        const uint32_t m = root_items(b, root, items);
        b->live = m;
        st = build(b, &s, items, m, root, &here);
    }
    state_free(&s);
    return st;
}
