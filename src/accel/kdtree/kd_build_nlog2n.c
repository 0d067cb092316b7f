/* The O(N log^2 N) builder (Wald & Havran 2006, section 4.2): every node
 * generates the split candidates of its triangles' clipped bounds and sorts
 * them anew, O(n log n) per node.
 *
 * A node carries each triangle with its clipped bounds. A triangle that
 * goes to one side only keeps its bounds (its clipped part is the same
 * polygon in the child cell); one that straddles the plane is clipped again
 * to each child's cell. The O(N log N) builder does exactly the same with
 * its event lists, so both see identical candidates everywhere. */
#include "accel/kdtree/kd_build.h"
#include "accel/kdtree/kd_clip.h"

typedef struct item {
    uint32_t tri;
    tt_aabb box;
} item;

typedef struct n2_state {
    kd_builder *b;
    uint64_t *ev, *tmp; /* 2 N events of one axis and the sort's scratch  */
    uint32_t *ids;      /* a leaf's triangle ids                           */
} n2_state;

static kd_split find_split(n2_state *s, const item *items, uint32_t n, const tt_aabb *cell)
{
    kd_split best = {-1, 0.0f, 0, INFINITY, 0, 0};
    for (int axis = 0; axis < 3; axis++) {
        size_t m = 0;
        for (uint32_t i = 0; i < n; i++)
            m += kd_events_of(s->ev + m, items[i].box.lo[axis], items[i].box.hi[axis], items[i].tri);
        /* A comparison sort, as the algorithm's name says: O(n log n) per
         * node, O(N log^2 N) in all. A radix sort here would make this an
         * O(N log N) builder too (with a bigger constant than the one that
         * sorts once), and the two would no longer be the algorithms the
         * issue and W&H compare. */
        kd_sort_events(s->ev, s->tmp, m);
        kd_sweep(s->b, s->ev, m, n, cell, axis, &best);
    }
    return best;
}

/* Consumes (frees) items. */
static tt_status build(n2_state *s, item *items, uint32_t n, const tt_aabb *cell,
                       const kd_place *here)
{
    kd_builder *b = s->b;
    kd_split split = {-1, 0.0f, 0, INFINITY, 0, 0};
    if (n > 0 && here->depth < b->max_depth) split = find_split(s, items, n, cell);
    if (!kd_should_split(b, n, here->depth, &split)) {
        for (uint32_t i = 0; i < n; i++) s->ids[i] = items[i].tri;
        tt_free(b->ctx, items);
        return kd_emit_leaf(b, s->ids, n);
    }
    tt_aabb lcell, rcell;
    kd_split_cell(cell, &split, &lcell, &rcell);
    uint32_t nl = 0, nr = 0;
    for (uint32_t i = 0; i < n; i++) {
        int side = kd_classify(items[i].box.lo[split.axis], items[i].box.hi[split.axis], &split);
        nl += (side & KD_SIDE_LEFT) != 0;
        nr += (side & KD_SIDE_RIGHT) != 0;
    }
    item *left = tt_alloc_array(b->ctx, nl, sizeof *left);
    item *right = tt_alloc_array(b->ctx, nr, sizeof *right);
    if (!left || !right) {
        tt_free(b->ctx, left);
        tt_free(b->ctx, right);
        tt_free(b->ctx, items);
        return kd_oom(b);
    }
    nl = nr = 0;
    for (uint32_t i = 0; i < n; i++) {
        int side = kd_classify(items[i].box.lo[split.axis], items[i].box.hi[split.axis], &split);
        if (side == KD_SIDE_LEFT) left[nl++] = items[i];
        else if (side == KD_SIDE_RIGHT) right[nr++] = items[i];
        else {
            const float *t = b->tri + 9 * (size_t)items[i].tri;
            item it = {items[i].tri, {{0, 0, 0}, {0, 0, 0}}};
            /* A straddler whose clipped part turns out empty on one side
             * (it only grazed the cell) is dropped there. */
            if (kd_clip_triangle(t, &lcell, &it.box)) left[nl++] = it;
            if (kd_clip_triangle(t, &rcell, &it.box)) right[nr++] = it;
        }
    }
    tt_free(b->ctx, items);
    kd_account_split(b, n, nl, nr);
    uint32_t node;
    kd_place child;
    tt_status st = kd_emit_interior(b, &split, cell, here, &node, &child);
    if (st != TT_OK) {
        tt_free(b->ctx, left);
        tt_free(b->ctx, right);
        return st;
    }
    st = build(s, left, nl, &lcell, &child);
    if (st != TT_OK) {
        tt_free(b->ctx, right);
        return st;
    }
    kd_link_right(b, node);
    return build(s, right, nr, &rcell, &child);
}

tt_status kd_build_nlog2n(kd_builder *b, const tt_aabb *root)
{
    uint32_t n = b->tri_count;
    n2_state s = {b, NULL, NULL, NULL};
    item *items = tt_alloc_array(b->ctx, n, sizeof *items);
    s.ev = tt_alloc_array(b->ctx, 2 * (size_t)n, sizeof *s.ev);
    s.tmp = tt_alloc_array(b->ctx, 2 * (size_t)n, sizeof *s.tmp);
    s.ids = tt_alloc_array(b->ctx, n, sizeof *s.ids);
    tt_status st;
    if (!items || !s.ev || !s.tmp || !s.ids) {
        tt_free(b->ctx, items);
        st = kd_oom(b);
    } else {
        uint32_t m = 0;
        for (uint32_t i = 0; i < n; i++) {
            items[m].tri = i;
            if (kd_clip_triangle(b->tri + 9 * (size_t)i, root, &items[m].box)) m++;
        }
        kd_place here = {0, 0, TT_KD_NO_PARENT};
        b->live = m;
        st = build(&s, items, m, root, &here);
    }
    tt_free(b->ctx, s.ev);
    tt_free(b->ctx, s.tmp);
    tt_free(b->ctx, s.ids);
    return st;
}
