/* The O(N log N) builder (Wald & Havran 2006, section 5): the split
 * candidates are sorted once at the root; each split then divides every
 * axis' sorted list in linear time. Triangles entirely on one side keep
 * their events (still sorted, as a subsequence); the few that straddle the
 * plane are clipped again to each child cell, their new events sorted (a
 * short list) and merged in. */
#include <math.h>
#include <omp.h>
#include <string.h>

#include "accel/kdtree/build/kd_build.h"
#include "accel/kdtree/build/kd_build_par.h"
#include "accel/kdtree/build/kd_clip.h"
#include "accel/kdtree/build/kd_memory.h"

/* Most nodes are small and were each paying for several malloc/free
 * pairs. Their event blocks come from reusable buffers instead: the
 * recursion is depth first, so when a node at depth d makes its children's
 * blocks, every earlier node at depth d + 1 is finished and its buffer is
 * free; one buffer per depth for left children and one for right children
 * suffices. Blocks larger than a buffer (the few big nodes near the root)
 * are allocated on their own, which keeps the buffers' memory bounded:
 * 2 (max_depth + 1) buffers of POOL_EVENTS events. */
#define POOL_EVENTS 8192u

typedef struct nl_state {
    tt_context *ctx;
    const float *tri;
    int max_depth;
    uint8_t *side;   /* per triangle: KD_SIDE_* of the split being applied */
    uint32_t *ids;   /* straddlers of a split, or a leaf's triangles        */
    uint64_t **pool; /* [depth][left, right]: buffers of POOL_EVENTS, made
                      * when first needed                                  */
    uint64_t *clip;  /* straddlers' events: 14 per straddler, grown        */
    size_t clip_cap;
} nl_state;

/* Events of one node: the three axes' sorted lists in one block. */
typedef struct nl_lists {
    uint64_t *block;
    size_t n[3];
    int owned;     /* allocated for this node alone (else a pool buffer)  */
    size_t stride; /* axis k's list starts at block + k stride; 0: the
                    * lists follow each other                            */
} nl_lists;

/* A block of n events for a child at this depth (which: 0 left, 1 right);
 * its own allocation if `own` (a block handed to another task). */
static int get_block(nl_state *s, int depth, int which, size_t n, int own, nl_lists *l)
{
    if (n > POOL_EVENTS || own) {
        l->block = tt_alloc_array(s->ctx, n, sizeof *l->block);
        l->owned = 1;
        kd_advise_huge(l->block, n * sizeof *l->block);
        return l->block != NULL;
    }
    uint64_t **slot = &s->pool[2 * depth + which];
    if (!*slot) *slot = tt_alloc_array(s->ctx, POOL_EVENTS, sizeof **slot);
    l->block = *slot;
    l->owned = 0;
    return l->block != NULL;
}

static void put_block(nl_state *s, nl_lists *l)
{
    if (l->owned) tt_free(s->ctx, l->block);
    l->block = NULL;
}

static uint64_t *axis_list(const nl_lists *l, int axis)
{
    if (l->stride) return l->block + (size_t)axis * l->stride;
    size_t off = 0;
    for (int k = 0; k < axis; k++) off += l->n[k];
    return l->block + off;
}

/* The first event at or after index lo whose position key is above
 * `key` (or n): the list is sorted, position first. */
static size_t first_above(const uint64_t *ev, size_t lo, size_t n, uint32_t key)
{
    size_t hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (kd_event_poskey(ev[mid]) > key) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

/* Marks every triangle of the node with its side of the split, from the
 * split axis' events alone (the rule of kd_classify, in event form): a
 * triangle's START comes before its END in the sorted list. Counts the
 * one-sided triangles and lists the straddlers in s->ids (marked 0).
 *
 * The list falls in three parts, found by binary search: events below the
 * plane, in it, and above it. Below, an END or PLANAR makes its triangle
 * LEFT and a START makes it BOTH for now; above, a START or PLANAR makes
 * it RIGHT and an END finds a triangle still BOTH: a straddler. Those two
 * parts need no test of the position and are written without branches
 * (the types come in no predictable order); only the events in the plane
 * take the general rule. */
static uint32_t classify(nl_state *s, const uint64_t *ev, size_t n_ev, const kd_split *sp,
                         uint32_t *n_left, uint32_t *n_right, size_t plane[2])
{
    const uint32_t pkey = kd_float_key(sp->pos);
    const uint8_t planar_side = sp->planar_left ? KD_SIDE_LEFT : KD_SIDE_RIGHT;
    /* In locals: a byte store may alias anything, so through s the
     * compiler reloaded both pointers after every one. */
    uint8_t *side = s->side;
    uint32_t *ids = s->ids;
    const float *tri = s->tri;
    _Static_assert(KD_END == 0 && KD_PLANAR == 1 && KD_START == 2, "event types");
    _Static_assert(KD_SIDE_LEFT == 1 && KD_SIDE_RIGHT == 2 && KD_SIDE_BOTH == 3, "side bits");
    /* [0, lo): below the plane; [lo, hi): in it; [hi, n_ev): above. */
    const size_t lo = pkey ? first_above(ev, 0, n_ev, pkey - 1) : 0;
    const size_t hi = first_above(ev, lo, n_ev, pkey);
    plane[0] = lo;
    plane[1] = hi;
    size_t nl = 0, nr = 0, nb = 0;
    for (size_t i = 0; i < lo; i++) {
        const uint32_t type = kd_event_type(ev[i]);
        /* START (2): BOTH (3); END (0) or PLANAR (1): LEFT (1). */
        side[kd_event_tri(ev[i])] = (uint8_t)(KD_SIDE_LEFT | (type & 2u));
        nl += (type >> 1) ^ 1u;
    }
    for (size_t i = lo; i < hi; i++) {
        const uint32_t type = kd_event_type(ev[i]), t = kd_event_tri(ev[i]);
        if (type == KD_START) {
            side[t] = KD_SIDE_RIGHT;
            nr++;
        } else if (type == KD_END) {
            side[t] = KD_SIDE_LEFT;
            nl++;
        } else {
            side[t] = planar_side;
            nl += planar_side & KD_SIDE_LEFT;
            nr += planar_side >> 1; /* KD_SIDE_RIGHT */
        }
    }
    for (size_t i = hi; i < n_ev; i++) {
        const uint32_t type = kd_event_type(ev[i]), t = kd_event_tri(ev[i]);
        const uint32_t was = side[t];
        const uint32_t is_end = type == KD_END;
        /* An END's triangle keeps its side (RIGHT, or BOTH: listed). */
        ids[nb] = t;
        nb += is_end & (was == KD_SIDE_BOTH);
        side[t] = (uint8_t)(is_end ? was : KD_SIDE_RIGHT);
        nr += is_end ^ 1u;
    }
    /* The straddlers' events are not copied to either child (their new
     * ones are merged in): side 0, so that the copy can add the side's two
     * bits as the children's counts. reclip reads their triangles next:
     * the scene's triangles are far larger than the caches. */
    for (size_t i = 0; i < nb; i++) {
        side[ids[i]] = 0;
        __builtin_prefetch(tri + 9 * (size_t)ids[i]);
        __builtin_prefetch(tri + 9 * (size_t)ids[i] + 8);
    }
    *n_left = (uint32_t)nl;
    *n_right = (uint32_t)nr;
    return (uint32_t)nb;
}

/* Sorts each of the 3 runs (2 nb apart, lengths len) of re-clipped
 * straddlers' events. */
static void sort_runs(uint64_t *out, uint64_t *tmp, uint32_t nb, const size_t len[3])
{
    /* Order among events of equal position and type does not matter: the
     * sweep and classification look only at position and type, and leaves
     * sort their ids. One triangle's events are in order already (its
     * START before its END, at a higher position). Most nodes re-clip a
     * straddler or two: short runs are sorted here, not through calls. */
    for (int k = 0; k < 3; k++) {
        uint64_t *run = out + 2 * (size_t)nb * k;
        if (len[k] > 16) {
            kd_radix_sort_events(run, tmp, len[k]);
            continue;
        }
        for (size_t i = 1; i < len[k]; i++) {
            const uint64_t x = run[i];
            size_t j = i;
            for (; j > 0 && run[j - 1] > x; j--) run[j] = run[j - 1];
            run[j] = x;
        }
    }
}

/* Clips the straddlers to both child cells (kd_clip_triangle_split):
 * each child's sorted events per axis in lout / rout (3 runs of at most
 * 2 nb each, starting at out + 2 nb * axis), the run lengths in llen /
 * rlen, and how many survived the clip on each side. */
static void reclip(nl_state *s, uint32_t nb, const tt_aabb *cell, const kd_split *sp, uint64_t *lout,
                   uint64_t *rout, uint64_t *tmp, size_t llen[3], size_t rlen[3], uint32_t *lkept,
                   uint32_t *rkept)
{
    uint32_t kl = 0, kr = 0;
    for (int k = 0; k < 3; k++) llen[k] = rlen[k] = 0;
    for (uint32_t i = 0; i < nb; i++) {
        tt_aabb lbox, rbox;
        const uint32_t t = s->ids[i];
        const int kept = kd_clip_triangle_split(s->tri + 9 * (size_t)t, cell, sp->axis, sp->pos, &lbox, &rbox);
        if (kept & 1) {
            kl++;
            for (int k = 0; k < 3; k++)
                llen[k] += kd_events_of(lout + 2 * (size_t)nb * k + llen[k], lbox.lo[k], lbox.hi[k], t);
        }
        if (kept & 2) {
            kr++;
            for (int k = 0; k < 3; k++)
                rlen[k] += kd_events_of(rout + 2 * (size_t)nb * k + rlen[k], rbox.lo[k], rbox.hi[k], t);
        }
    }
    if (kl > 1) sort_runs(lout, tmp, nb, llen);
    if (kr > 1) sort_runs(rout, tmp, nb, rlen);
    *lkept = kl;
    *rkept = kr;
}

/* One axis of a split: the parent's events of one-sided triangles (their
 * order kept) go to the children's lists ldst and rdst, merged with the
 * re-clipped straddlers' sorted events lc[0, llen) and rc[0, rlen) as they
 * go. Each destination has room for one event more than it receives. */
static void split_axis(const uint8_t *side_of, const uint64_t *ev, size_t n_ev, const uint64_t *lc,
                       size_t llen, const uint64_t *rc, size_t rlen, uint64_t *ldst, uint64_t *rdst,
                       size_t *n_left, size_t *n_right)
{
    /* The value after a run's last is above every event (type 3 does not
     * exist). */
    const uint64_t *lc_end = lc + llen, *rc_end = rc + rlen;
    uint64_t lnext = lc < lc_end ? *lc : UINT64_MAX, rnext = rc < rc_end ? *rc : UINT64_MAX;
    /* The lower of the two: one test an event instead of two. */
    uint64_t next = lnext < rnext ? lnext : rnext;
    size_t nl = 0, nr = 0;
    for (size_t i = 0; i < n_ev; i++) {
        const uint64_t e = ev[i];
        /* Few straddlers against many one-sided triangles: these loops
         * rarely run, and merging here spares a second pass over the
         * children's lists. A child's key equals a parent's event only
         * where a straddler's re-clipped event kept its old position: the
         * parent's event is then that straddler's own, which goes to
         * neither side, so the order is the sorted one. */
        if (next < e) {
            while (lnext < e) {
                ldst[nl++] = lnext;
                lnext = ++lc < lc_end ? *lc : UINT64_MAX;
            }
            while (rnext < e) {
                rdst[nr++] = rnext;
                rnext = ++rc < rc_end ? *rc : UINT64_MAX;
            }
            next = lnext < rnext ? lnext : rnext;
        }
        /* (widened to the counts' type at once: a byte's shift cost a
         * mask and a move more) */
        const size_t side = side_of[kd_event_tri(e)];
        /* Branch-free: the sides come in no predictable order. A store past
         * a run's end lands in the room behind it (the next axis' space,
         * overwritten later, or a spare slot). */
        ldst[nl] = e;
        rdst[nr] = e;
        _Static_assert(KD_SIDE_LEFT == 1 && KD_SIDE_RIGHT == 2, "side bits");
        nl += side & KD_SIDE_LEFT;
        nr += side >> 1; /* KD_SIDE_RIGHT */
    }
    while (lc < lc_end) ldst[nl++] = *lc++;
    while (rc < rc_end) rdst[nr++] = *rc++;
    *n_left = nl;
    *n_right = nr;
}

/* split_axis for the split axis of a split no triangle straddles, whose
 * list falls in three parts (classify): below the plane [0, plane[0]),
 * every event its triangle's on the left; in it; above it [plane[1],
 * n_ev), every event on the right. The outer parts are copied whole. */
static void split_plane_axis(const uint8_t *side_of, const uint64_t *ev, size_t n_ev,
                             const size_t plane[2], uint64_t *ldst, uint64_t *rdst, size_t *n_left,
                             size_t *n_right)
{
    const size_t lo = plane[0], hi = plane[1];
    size_t ml, mr;
    memcpy(ldst, ev, lo * sizeof *ev);
    /* (no straddlers' runs: empty ones, at a valid address) */
    split_axis(side_of, ev + lo, hi - lo, ev, 0, ev, 0, ldst + lo, rdst, &ml, &mr);
    memcpy(rdst + mr, ev + hi, (n_ev - hi) * sizeof *ev);
    *n_left = lo + ml;
    *n_right = mr + (n_ev - hi);
}

/* Builds both children's lists in one pass over the parent's (split_axis
 * for each axis). Each child's run for an axis is sized for the worst
 * case, two events per triangle, so the split needs no counting pass.
 *
 * A big node of a parallel build (own) splits its three axes in tasks:
 * each axis then writes its own part of the blocks (a stride apart, a
 * spare slot each, so no task's stray store reaches another's list). The
 * lists are the same either way. */
static int child_lists(nl_state *s, const nl_lists *parent, int depth, int own, uint32_t n_left,
                       uint32_t n_right, const uint64_t *lclip, const size_t llen[3],
                       const uint64_t *rclip, const size_t rlen[3], uint32_t nb, int axis,
                       const size_t plane[2], nl_lists *left, nl_lists *right)
{
    const size_t lcap = 2 * (size_t)n_left, rcap = 2 * (size_t)n_right;
    const int tasks = own && parent->n[0] + parent->n[1] + parent->n[2] >= 6 * (size_t)kd_par_cutoff;
    /* One slot more than the runs need (one an axis with tasks): the
     * filter writes every event to both children and advances only the
     * side it belongs to. */
    const size_t extra = tasks ? 3 : 1;
    if (!get_block(s, depth, 0, 3 * lcap + extra, own, left) ||
        !get_block(s, depth, 1, 3 * rcap + extra, own, right))
        return 0;
    if (tasks) {
        left->stride = lcap + 1;
        right->stride = rcap + 1;
        const uint8_t *side_of = s->side;
        for (int k = 0; k < 3; k++) {
#pragma omp task firstprivate(k) shared(left, right)
            if (k == axis && nb == 0)
                split_plane_axis(side_of, axis_list(parent, k), parent->n[k], plane, axis_list(left, k),
                                 axis_list(right, k), &left->n[k], &right->n[k]);
            else
                split_axis(side_of, axis_list(parent, k), parent->n[k], lclip + 2 * (size_t)nb * k,
                           llen[k], rclip + 2 * (size_t)nb * k, rlen[k], axis_list(left, k),
                           axis_list(right, k), &left->n[k], &right->n[k]);
        }
#pragma omp taskwait
        return 1;
    }
    uint64_t *ldst = left->block, *rdst = right->block;
    for (int k = 0; k < 3; k++) {
        if (k == axis && nb == 0)
            split_plane_axis(s->side, axis_list(parent, k), parent->n[k], plane, ldst, rdst, &left->n[k],
                             &right->n[k]);
        else
            split_axis(s->side, axis_list(parent, k), parent->n[k], lclip + 2 * (size_t)nb * k, llen[k],
                       rclip + 2 * (size_t)nb * k, rlen[k], ldst, rdst, &left->n[k], &right->n[k]);
        ldst += left->n[k];
        rdst += right->n[k];
    }
    return 1;
}

/* Room for the straddlers' events: for each of nb straddlers, 6 (2 per
 * axis) for each child and 2 of sort scratch. */
static int clip_room(nl_state *s, uint32_t nb)
{
    const size_t need = 14 * (size_t)nb;
    /* Allocated even when no triangle straddles (need 0): the run pointers
     * are computed from it, and an offset on a null pointer is undefined. */
    if (s->clip && need <= s->clip_cap) return 1;
    size_t cap = s->clip_cap ? s->clip_cap : 1024;
    while (cap < need) cap *= 2;
    uint64_t *p = tt_realloc_array(s->ctx, s->clip, cap, sizeof *p);
    if (!p) return 0;
    s->clip = p;
    s->clip_cap = cap;
    return 1;
}

/* The leaf of a node's triangles (each has one START or PLANAR event). */
static tt_status emit_leaf(kd_builder *b, nl_state *s, nl_lists *lists)
{
    uint32_t m = 0;
    /* An empty child of a split has no block (split_node). */
    const uint64_t *ev = lists->n[0] ? axis_list(lists, 0) : NULL;
    for (size_t i = 0; i < lists->n[0]; i++)
        if (kd_event_type(ev[i]) != KD_END) s->ids[m++] = kd_event_tri(ev[i]);
    put_block(s, lists);
    return kd_emit_leaf(b, s->ids, m);
}

/* Applies a split: the children's cells, triangle counts and event lists
 * (their own allocations if own). Consumes lists->block. */
static tt_status split_node(kd_builder *b, nl_state *s, nl_lists *lists, uint32_t n,
                            const tt_aabb *cell, const kd_split *split, int depth, int own,
                            tt_aabb *lcell, tt_aabb *rcell, uint32_t *n_left, uint32_t *n_right,
                            nl_lists *left, nl_lists *right)
{
    if (split->n_left == 0 || split->n_right == 0) {
        /* A split that cuts off empty space (the sweep's counts are exact
         * but for straddlers, and there are none: every triangle lies on
         * one side). That side's lists are the parent's, event for event:
         * they are handed over, not filtered; the other child is an empty
         * leaf with no lists. The block stays valid: a pool buffer of a
         * depth that only a node above this subtree reuses, or one of the
         * node's own. */
        const int left_full = split->n_left != 0;
        kd_split_cell(cell, split, lcell, rcell);
        kd_account_split(b, n, left_full ? n : 0, left_full ? 0 : n);
        nl_lists *full = left_full ? left : right, *empty = left_full ? right : left;
        *full = *lists;
        empty->block = NULL;
        empty->n[0] = empty->n[1] = empty->n[2] = 0;
        empty->owned = 0;
        empty->stride = 0;
        lists->block = NULL;
        *n_left = left_full ? n : 0;
        *n_right = left_full ? 0 : n;
        return TT_OK;
    }
    const uint64_t *ev = axis_list(lists, split->axis);
    const size_t n_ev = lists->n[split->axis];
    uint32_t nl, nr;
    size_t plane[2];
    const uint32_t nb = classify(s, ev, n_ev, split, &nl, &nr, plane);
    kd_split_cell(cell, split, lcell, rcell);
    tt_status st = TT_OK;
    if (!clip_room(s, nb)) {
        st = kd_oom(b);
    } else {
        /* Straddlers' events: left runs, right runs, sort scratch. */
        uint64_t *lclip = s->clip, *rclip = s->clip + 6 * (size_t)nb, *tmp = s->clip + 12 * (size_t)nb;
        size_t llen[3], rlen[3];
        uint32_t kl, kr;
        reclip(s, nb, cell, split, lclip, rclip, tmp, llen, rlen, &kl, &kr);
        nl += kl;
        nr += kr;
        kd_account_split(b, n, nl, nr);
        if (!child_lists(s, lists, depth + 1, own, nl, nr, lclip, llen, rclip, rlen, nb, split->axis,
                         plane, left, right))
            st = kd_oom(b);
    }
    put_block(s, lists);
    *n_left = nl;
    *n_right = nr;
    return st;
}

/* Consumes (releases) lists->block. */
static tt_status build(kd_builder *b, nl_state *s, nl_lists *lists, uint32_t n, const tt_aabb *cell,
                       const kd_place *here)
{
    if (kd_par_aborted(b)) {
        put_block(s, lists);
        return KD_ABORTED;
    }
    kd_split split = {-1, 0.0f, 0, INFINITY, 0, 0};
    if (n > 0 && here->depth < b->max_depth)
        for (int k = 0; k < 3; k++) kd_sweep(b, axis_list(lists, k), lists->n[k], n, cell, k, &split);
    if (!kd_should_split(b, n, here->depth, &split)) return emit_leaf(b, s, lists);
    tt_aabb lcell, rcell;
    uint32_t nl, nr;
    nl_lists left = {NULL, {0, 0, 0}, 0, 0}, right = {NULL, {0, 0, 0}, 0, 0};
    tt_status st = split_node(b, s, lists, n, cell, &split, here->depth, 0, &lcell, &rcell, &nl, &nr,
                              &left, &right);
    uint32_t node = 0;
    kd_place child;
    if (st == TT_OK) st = kd_emit_interior(b, &split, cell, here, &node, &child);
    if (st != TT_OK) {
        put_block(s, &left);
        put_block(s, &right);
        return st;
    }
    st = build(b, s, &left, nl, &lcell, &child);
    if (st != TT_OK) {
        put_block(s, &right);
        return st;
    }
    kd_link_right(b, node);
    return build(b, s, &right, nr, &rcell, &child);
}

static void state_init(nl_state *s, const kd_builder *b)
{
    memset(s, 0, sizeof *s);
    s->ctx = b->ctx;
    s->tri = b->tri;
    s->max_depth = b->max_depth;
}

/* The scratch of a build (or of one thread of it): 0 when out of memory. */
static int state_alloc(nl_state *s, uint32_t n)
{
    s->side = tt_alloc_array(s->ctx, n, sizeof *s->side);
    /* One more than the triangles: classify stores a candidate past the
     * straddlers it has listed. */
    s->ids = tt_alloc_array(s->ctx, (size_t)n + 1, sizeof *s->ids);
    s->pool = tt_calloc(s->ctx, 2 * ((size_t)s->max_depth + 1), sizeof *s->pool);
    return s->side && s->ids && s->pool;
}

static void state_free(nl_state *s)
{
    tt_free(s->ctx, s->side);
    tt_free(s->ctx, s->ids);
    tt_free(s->ctx, s->clip);
    if (s->pool)
        for (size_t i = 0; i < 2 * ((size_t)s->max_depth + 1); i++) tt_free(s->ctx, s->pool[i]);
    tt_free(s->ctx, s->pool);
    memset(s, 0, sizeof *s);
}

/* The events of triangles [first, last) of the scene, in triangle order:
 * axis k's at run_k + 2 first (run_k = block + 2 n k, room for 2 events a
 * triangle), their counts in count[k]. Returns how many triangles touch
 * the root cell. */
static uint32_t root_events(const kd_builder *b, const tt_aabb *root, uint64_t *block, uint32_t first,
                            uint32_t last, size_t count[3])
{
    const size_t n = b->tri_count;
    uint32_t m = 0;
    count[0] = count[1] = count[2] = 0;
    for (uint32_t i = first; i < last; i++) {
        tt_aabb box;
        if (!kd_clip_triangle(b->tri + 9 * (size_t)i, root, &box)) continue;
        m++;
        for (int k = 0; k < 3; k++)
            count[k] += kd_events_of(block + 2 * n * k + 2 * (size_t)first + count[k], box.lo[k],
                                     box.hi[k], i);
    }
    return m;
}

/* Root triangles a chunk of the events' generation takes at least, and
 * the most chunks. */
#define ROOT_CHUNK_MIN 16384u
#define ROOT_CHUNKS_MAX 32

/* Axis k's run of the root's events: the chunks' parts (2 n events apart
 * at first) moved together, down in chunk order, then sorted with t as
 * the radix sort's scratch. */
static void sort_axis(uint64_t *run, uint64_t *t, size_t count[][3], int chunks, uint32_t n, int k)
{
    size_t len = count[0][k];
    for (int c = 1; c < chunks; c++) {
        const size_t first = (size_t)((uint64_t)n * (uint64_t)c / (uint64_t)chunks);
        memmove(run + len, run + 2 * first, count[c][k] * sizeof *run);
        len += count[c][k];
    }
    kd_radix_sort_events(run, t, len);
}

/* The root's event lists: each axis' run sorted, axis k's at block +
 * 2 n k. With `tasks` (inside a parallel region) the events are generated
 * by a task per chunk of triangles and each axis is sorted by a task of
 * its own; tmp then holds 6 n keys, else 2 n. Either way a run lists its
 * events in triangle order before the (stable) sort, so the lists are the
 * same. With ax (a parallel build's root, else NULL) also the root's
 * sweeps, into ax[0..2], when *swept says so. Returns the number of
 * triangles that touch the root cell. */
static uint32_t root_lists(const kd_builder *b, const tt_aabb *root, nl_lists *lists, uint64_t *tmp,
                           int tasks, kd_split ax[3], int *swept)
{
    const uint32_t n = b->tri_count;
    int chunks = 1;
    if (tasks) {
        chunks = omp_get_num_threads();
        if (chunks > ROOT_CHUNKS_MAX) chunks = ROOT_CHUNKS_MAX;
        if ((uint32_t)chunks > n / ROOT_CHUNK_MIN) chunks = (int)(n / ROOT_CHUNK_MIN);
        if (chunks < 1) chunks = 1;
    }
    size_t count[ROOT_CHUNKS_MAX][3];
    uint32_t kept[ROOT_CHUNKS_MAX];
    uint64_t *block = lists->block;
    for (int c = 0; c < chunks; c++) {
        const uint32_t first = (uint32_t)((uint64_t)n * (uint64_t)c / (uint64_t)chunks);
        const uint32_t last = (uint32_t)((uint64_t)n * (uint64_t)(c + 1) / (uint64_t)chunks);
#pragma omp task firstprivate(c, first, last) shared(count, kept) if (chunks > 1)
        kept[c] = root_events(b, root, block, first, last, count[c]);
    }
#pragma omp taskwait
    uint32_t m = 0;
    for (int c = 0; c < chunks; c++) m += kept[c];
    /* With ax (a parallel build), the root's sweeps too: each axis' sweep
     * is a task that starts as soon as that axis is sorted, so that on two
     * threads the third sort runs beside the first sweeps instead of
     * alone. par_build's rule for sweeping a node, decided here for the
     * root (nothing can have aborted yet). */
    *swept = ax && m >= kd_par_cutoff && b->max_depth > 0;
    for (int k = 0; k < 3; k++) {
        lists->n[k] = 0;
        for (int c = 0; c < chunks; c++) lists->n[k] += count[c][k];
    }
    if (!tasks) {
        /* The serial build: no task constructs at all. An undeferred task
         * with a depend clause (if (0)) makes libomp wait on dependences
         * outside any parallel region, where LLVM 14's archer (the
         * ThreadSanitizer OpenMP tool) dereferences a null task and
         * crashes. */
        for (int k = 0; k < 3; k++) sort_axis(block + 2 * (size_t)n * k, tmp, count, chunks, n, k);
    } else {
        char sorted[3]; /* what the depend clauses name (only its addresses) */
        (void)sorted;
        for (int k = 0; k < 3; k++) {
            uint64_t *run = block + 2 * (size_t)n * k, *t = tmp + 2 * (size_t)n * k;
#pragma omp task firstprivate(run, t, k) shared(count) depend(out : sorted[k])
            sort_axis(run, t, count, chunks, n, k);
        }
        if (*swept)
            for (int k = 0; k < 3; k++) {
                const uint64_t *run = block + 2 * (size_t)n * k;
                const size_t len = lists->n[k];
                const kd_split none = {-1, 0.0f, 0, INFINITY, 0, 0};
                ax[k] = none;
#pragma omp task firstprivate(run, len, k) shared(ax) depend(in : sorted[k])
                kd_sweep(b, run, len, m, root, k, &ax[k]);
            }
    }
#pragma omp taskwait
    /* The runs stay where they are, 2 n apart: moving them together was
     * a serial copy of the whole root's events. */
    lists->stride = 2 * (size_t)n;
    return m;
}

/* ------------------------------------------------------------ parallel */

typedef struct nl_par {
    const kd_builder *proto;
    nl_state *scratch; /* one per thread, allocated by its thread */
} nl_par;

static nl_state *my_state(nl_par *p)
{
    nl_state *s = &p->scratch[omp_get_thread_num()];
    if (s->side) return s;
    state_init(s, p->proto);
    if (state_alloc(s, p->proto->tri_count)) return s;
    state_free(s);
    return NULL;
}

/* A node built by tasks into sub (see kd_build_par.h). Consumes lists. */
static tt_status par_build(nl_par *p, kd_sub *sub, nl_lists *lists, uint32_t n, const tt_aabb *cell,
                           kd_place here, const kd_split *swept)
{
    kd_builder *b = &sub->out;
    kd_split split = {-1, 0.0f, 0, INFINITY, 0, 0};
    if (swept) {
        /* the root's, swept by root_lists */
        for (int k = 0; k < 3; k++)
            if (swept[k].cost < split.cost) split = swept[k];
    } else if (n >= kd_par_cutoff && here.depth < b->max_depth && !kd_par_aborted(b)) {
        /* The three axes' sweeps at once; the lowest cost wins, the lower
         * axis on a tie, as in the serial loop. */
        kd_split ax[3];
        for (int k = 0; k < 3; k++) {
            ax[k] = split;
#pragma omp task shared(ax) firstprivate(k)
            kd_sweep(b, axis_list(lists, k), lists->n[k], n, cell, k, &ax[k]);
        }
#pragma omp taskwait
        for (int k = 0; k < 3; k++)
            if (ax[k].cost < split.cost) split = ax[k];
    }
    nl_state *s = my_state(p);
    if (!s) {
        tt_free(b->ctx, lists->block); /* a parallel node's lists are its own */
        return kd_oom(b);
    }
    if (split.axis < 0 || !kd_should_split(b, n, here.depth, &split))
        return build(b, s, lists, n, cell, &here);
    tt_aabb lcell, rcell;
    uint32_t nl, nr;
    nl_lists left = {NULL, {0, 0, 0}, 1, 0}, right = {NULL, {0, 0, 0}, 1, 0};
    tt_status st = split_node(b, s, lists, n, cell, &split, here.depth, 1, &lcell, &rcell, &nl, &nr,
                              &left, &right);
    if (st == TT_OK) {
        sub->kid[0] = kd_sub_new(b);
        sub->kid[1] = kd_sub_new(b);
        if (!sub->kid[0] || !sub->kid[1]) st = kd_oom(b);
    }
    if (st != TT_OK) {
        put_block(s, &left);
        put_block(s, &right);
        return st;
    }
    sub->split = split;
    const kd_place child = kd_child_place(b, &here);
    kd_sub *l = sub->kid[0], *r = sub->kid[1];
#pragma omp task firstprivate(l, left, nl, lcell)
    l->st = par_build(p, l, &left, nl, &lcell, child, NULL);
#pragma omp task firstprivate(r, right, nr, rcell)
    r->st = par_build(p, r, &right, nr, &rcell, child, NULL);
#pragma omp taskwait
    return l->st != TT_OK ? l->st : r->st;
}

/* The parallel build; KD_ABORTED when the budget bound was passed. */
static tt_status build_parallel(kd_builder *b, const tt_aabb *root, int threads)
{
    const uint32_t n = b->tri_count;
    kd_par par = {0, 0, 0};
    nl_par p = {b, NULL};
    nl_lists lists = {NULL, {0, 0, 0}, 1, 0};
    p.scratch = tt_calloc(b->ctx, (size_t)threads, sizeof *p.scratch);
    lists.block = tt_alloc_array(b->ctx, 6 * (size_t)n, sizeof *lists.block);
    uint64_t *tmp = tt_alloc_array(b->ctx, 6 * (size_t)n, sizeof *tmp);
    kd_advise_huge(lists.block, 6 * (size_t)n * sizeof *lists.block);
    kd_advise_huge(tmp, 6 * (size_t)n * sizeof *tmp);
    kd_sub *top = kd_sub_new(b);
    tt_status st = TT_OK;
    if (!p.scratch || !lists.block || !tmp || !top) {
        tt_free(b->ctx, lists.block);
        st = kd_oom(b);
    } else {
        top->out.par = &par;
#pragma omp parallel num_threads(threads)
#pragma omp single
        {
            kd_split ax[3];
            int swept = 0;
            par.m = root_lists(b, root, &lists, tmp, 1, ax, &swept);
            tt_free(b->ctx, tmp);
            tmp = NULL;
            kd_place here = {0, 0, TT_KD_NO_PARENT};
            st = par_build(&p, top, &lists, (uint32_t)par.m, root, here, swept ? ax : NULL);
        }
        if (par.abort) st = KD_ABORTED;
        if (st == TT_OK) st = kd_replay(b, top, root);
    }
    tt_free(b->ctx, tmp);
    if (p.scratch)
        for (int t = 0; t < threads; t++) state_free(&p.scratch[t]);
    tt_free(b->ctx, p.scratch);
    kd_sub_free(b->ctx, top);
    return st;
}

tt_status kd_build_nlogn(kd_builder *b, const tt_aabb *root)
{
    const uint32_t n = b->tri_count;
    const int threads = kd_par_threads(b->ctx);
    if (threads > 1 && n >= kd_par_cutoff) {
        tt_status st = build_parallel(b, root, threads);
        if (st != KD_ABORTED) return st;
    }
    nl_state s;
    state_init(&s, b);
    nl_lists lists = {NULL, {0, 0, 0}, 1, 0};
    lists.block = tt_alloc_array(b->ctx, 6 * (size_t)n, sizeof *lists.block);
    uint64_t *tmp = tt_alloc_array(b->ctx, 2 * (size_t)n, sizeof *tmp);
    kd_advise_huge(lists.block, 6 * (size_t)n * sizeof *lists.block);
    kd_advise_huge(tmp, 2 * (size_t)n * sizeof *tmp);
    tt_status st;
    if (!state_alloc(&s, n) || !lists.block || !tmp) {
        tt_free(b->ctx, lists.block);
        st = kd_oom(b);
    } else {
        int swept;
        const uint32_t m = root_lists(b, root, &lists, tmp, 0, NULL, &swept);
        tt_free(b->ctx, tmp);
        tmp = NULL;
        kd_place here = {0, 0, TT_KD_NO_PARENT};
        b->live = m;
        st = build(b, &s, &lists, m, root, &here);
    }
    tt_free(b->ctx, tmp);
    state_free(&s);
    return st;
}
