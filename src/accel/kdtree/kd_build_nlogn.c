/* The O(N log N) builder (Wald & Havran 2006, section 5): the split
 * candidates are sorted once at the root; each split then divides every
 * axis' sorted list in linear time. Triangles entirely on one side keep
 * their events (still sorted, as a subsequence); the few that straddle the
 * plane are clipped again to each child cell, their new events sorted (a
 * short list) and merged in. */
#include "accel/kdtree/kd_build.h"
#include "accel/kdtree/kd_clip.h"

typedef struct nl_state {
    kd_builder *b;
    uint8_t *side; /* per triangle: KD_SIDE_* of the split being applied */
    uint32_t *ids; /* straddlers of a split, or a leaf's triangles        */
} nl_state;

/* Events of one node: the three axes' sorted lists in one block. */
typedef struct nl_lists {
    uint64_t *block;
    size_t n[3];
} nl_lists;

static uint64_t *axis_list(const nl_lists *l, int axis)
{
    size_t off = 0;
    for (int k = 0; k < axis; k++) off += l->n[k];
    return l->block + off;
}

/* Marks every triangle of the node with its side of the split, from the
 * split axis' events alone (the rule of kd_classify, in event form), in one
 * pass: a triangle's START comes before its END in the sorted list. Counts
 * the one-sided triangles and lists the straddlers in s->ids. */
static uint32_t classify(nl_state *s, const uint64_t *ev, size_t n_ev, const kd_split *sp,
                         uint32_t *n_left, uint32_t *n_right)
{
    const uint32_t pkey = kd_float_key(sp->pos);
    const uint8_t planar_side = sp->planar_left ? KD_SIDE_LEFT : KD_SIDE_RIGHT;
    uint32_t nl = 0, nr = 0, nb = 0;
    for (size_t i = 0; i < n_ev; i++) {
        const uint32_t key = kd_event_poskey(ev[i]), type = kd_event_type(ev[i]), t = kd_event_tri(ev[i]);
        if (type == KD_START) {
            s->side[t] = key >= pkey ? KD_SIDE_RIGHT : KD_SIDE_BOTH;
            nr += key >= pkey;
        } else if (type == KD_END) {
            if (key <= pkey) {
                s->side[t] = KD_SIDE_LEFT;
                nl++;
            } else if (s->side[t] == KD_SIDE_BOTH) {
                s->ids[nb++] = t;
            }
        } else {
            uint8_t side = key < pkey ? KD_SIDE_LEFT : key > pkey ? KD_SIDE_RIGHT : planar_side;
            s->side[t] = side;
            nl += side == KD_SIDE_LEFT;
            nr += side == KD_SIDE_RIGHT;
        }
    }
    *n_left = nl;
    *n_right = nr;
    return nb;
}

/* Clips the straddlers to one child cell: their sorted events per axis in
 * out (3 runs of at most 2 nb each, starting at out + 2 nb * axis), the
 * run lengths in len, and how many survived the clip. */
static uint32_t reclip(nl_state *s, uint32_t nb, const tt_aabb *cell, uint64_t *out, uint64_t *tmp,
                       size_t len[3])
{
    uint32_t kept = 0;
    len[0] = len[1] = len[2] = 0;
    for (uint32_t i = 0; i < nb; i++) {
        tt_aabb box;
        if (!kd_clip_triangle(s->b->tri + 9 * (size_t)s->ids[i], cell, &box)) continue;
        kept++;
        for (int k = 0; k < 3; k++)
            len[k] += kd_events_of(out + 2 * (size_t)nb * k + len[k], box.lo[k], box.hi[k], s->ids[i]);
    }
    /* Order among events of equal position and type does not matter: the
     * sweep and classification look only at position and type, and leaves
     * sort their ids. */
    for (int k = 0; k < 3; k++) kd_radix_sort_events(out + 2 * (size_t)nb * k, tmp, len[k]);
    return kept;
}

/* Builds both children's lists in one pass over the parent's: the events
 * of one-sided triangles (their order kept) merged with the re-clipped
 * straddlers' events. Each child's run for an axis is sized for the worst
 * case, two events per triangle, so the split needs no counting pass. */
static int child_lists(nl_state *s, const nl_lists *parent, uint32_t n_left, uint32_t n_right,
                       const uint64_t *lclip, const size_t llen[3], const uint64_t *rclip,
                       const size_t rlen[3], uint32_t nb, nl_lists *left, nl_lists *right)
{
    const size_t lcap = 2 * (size_t)n_left, rcap = 2 * (size_t)n_right;
    /* One slot more than the runs need: the filter below writes every
     * event to both children and advances only the side it belongs to. */
    left->block = tt_alloc_array(s->b->ctx, 3 * lcap + 1, sizeof *left->block);
    right->block = tt_alloc_array(s->b->ctx, 3 * rcap + 1, sizeof *right->block);
    if (!left->block || !right->block) return 0;
    uint64_t *ldst = left->block, *rdst = right->block;
    for (int k = 0; k < 3; k++) {
        const uint64_t *ev = axis_list(parent, k);
        size_t nl = 0, nr = 0;
        /* Branch-free: the sides come in no predictable order. A store past
         * a run's end lands in the next axis' space (overwritten later) or
         * in the spare slot. */
        for (size_t i = 0; i < parent->n[k]; i++) {
            const uint64_t e = ev[i];
            const uint8_t side = s->side[kd_event_tri(e)];
            ldst[nl] = e;
            rdst[nr] = e;
            nl += side == KD_SIDE_LEFT;
            nr += side == KD_SIDE_RIGHT;
        }
        kd_merge_in_place(ldst, nl, lclip + 2 * (size_t)nb * k, llen[k]);
        kd_merge_in_place(rdst, nr, rclip + 2 * (size_t)nb * k, rlen[k]);
        left->n[k] = nl + llen[k];
        right->n[k] = nr + rlen[k];
        ldst += left->n[k];
        rdst += right->n[k];
    }
    return 1;
}

/* Consumes (frees) lists->block. */
static tt_status build(nl_state *s, nl_lists *lists, uint32_t n, const tt_aabb *cell,
                       const kd_place *here)
{
    kd_builder *b = s->b;
    kd_split split = {-1, 0.0f, 0, INFINITY};
    if (n > 0 && here->depth < b->max_depth)
        for (int k = 0; k < 3; k++) kd_sweep(b, axis_list(lists, k), lists->n[k], n, cell, k, &split);
    if (!kd_should_split(b, n, here->depth, &split)) {
        uint32_t m = 0;
        const uint64_t *ev = axis_list(lists, 0);
        for (size_t i = 0; i < lists->n[0]; i++)
            if (kd_event_type(ev[i]) != KD_END) s->ids[m++] = kd_event_tri(ev[i]);
        tt_free(b->ctx, lists->block);
        return kd_emit_leaf(b, s->ids, m);
    }
    const uint64_t *ev = axis_list(lists, split.axis);
    const size_t n_ev = lists->n[split.axis];
    uint32_t nl, nr;
    const uint32_t nb = classify(s, ev, n_ev, &split, &nl, &nr);
    tt_aabb lcell, rcell;
    kd_split_cell(cell, &split, &lcell, &rcell);
    /* Straddlers' events: left runs, right runs, sort scratch. */
    uint64_t *clip = tt_alloc_array(b->ctx, 14 * (size_t)nb, sizeof *clip);
    nl_lists left = {NULL, {0, 0, 0}}, right = {NULL, {0, 0, 0}};
    tt_status st = TT_OK;
    if (!clip) {
        st = kd_oom(b);
    } else {
        uint64_t *lclip = clip, *rclip = clip + 6 * (size_t)nb, *tmp = clip + 12 * (size_t)nb;
        size_t llen[3], rlen[3];
        nl += reclip(s, nb, &lcell, lclip, tmp, llen);
        nr += reclip(s, nb, &rcell, rclip, tmp, rlen);
        if (!child_lists(s, lists, nl, nr, lclip, llen, rclip, rlen, nb, &left, &right))
            st = kd_oom(b);
    }
    tt_free(b->ctx, clip);
    tt_free(b->ctx, lists->block);
    uint32_t node = 0;
    kd_place child;
    if (st == TT_OK) st = kd_emit_interior(b, &split, cell, here, &node, &child);
    if (st != TT_OK) {
        tt_free(b->ctx, left.block);
        tt_free(b->ctx, right.block);
        return st;
    }
    st = build(s, &left, nl, &lcell, &child);
    if (st != TT_OK) {
        tt_free(b->ctx, right.block);
        return st;
    }
    kd_link_right(b, node);
    return build(s, &right, nr, &rcell, &child);
}

tt_status kd_build_nlogn(kd_builder *b, const tt_aabb *root)
{
    const uint32_t n = b->tri_count;
    nl_state s = {b, NULL, NULL};
    nl_lists lists = {NULL, {0, 0, 0}};
    s.side = tt_alloc_array(b->ctx, n, sizeof *s.side);
    s.ids = tt_alloc_array(b->ctx, n, sizeof *s.ids);
    lists.block = tt_alloc_array(b->ctx, 6 * (size_t)n, sizeof *lists.block);
    uint64_t *tmp = tt_alloc_array(b->ctx, 2 * (size_t)n, sizeof *tmp);
    tt_status st;
    if (!s.side || !s.ids || !lists.block || !tmp) {
        tt_free(b->ctx, lists.block);
        st = kd_oom(b);
    } else {
        /* Axis runs of 2 n events each at first, compacted below. */
        uint32_t m = 0;
        for (uint32_t i = 0; i < n; i++) {
            tt_aabb box;
            if (!kd_clip_triangle(b->tri + 9 * (size_t)i, root, &box)) continue;
            m++;
            for (int k = 0; k < 3; k++)
                lists.n[k] += kd_events_of(lists.block + 2 * (size_t)n * k + lists.n[k], box.lo[k],
                                           box.hi[k], i);
        }
        size_t at = 0;
        for (int k = 0; k < 3; k++) {
            memmove(lists.block + at, lists.block + 2 * (size_t)n * k, lists.n[k] * sizeof(uint64_t));
            kd_radix_sort_events(lists.block + at, tmp, lists.n[k]);
            at += lists.n[k];
        }
        tt_free(b->ctx, tmp);
        tmp = NULL;
        kd_place here = {0, 0, TT_KD_NO_PARENT};
        st = build(&s, &lists, m, root, &here);
    }
    tt_free(b->ctx, tmp);
    tt_free(b->ctx, s.side);
    tt_free(b->ctx, s.ids);
    return st;
}
