/* The parts both builders share (see kd_build.h). */
#include "accel/kdtree/build/kd_build.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>

#include "accel/kdtree/build/kd_build_par.h"

tt_status kd_fail(kd_builder *b, tt_status st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    /* Tasks of a parallel build may fail at once; the context holds one
     * message. */
#pragma omp critical(tt_kd_error)
    tt_verror(b->ctx, st, fmt, ap);
    va_end(ap);
    return st;
}

tt_status kd_oom(kd_builder *b)
{
    return kd_fail(b, TT_ERR_OUT_OF_MEMORY, "kdtree: out of memory while building (%u nodes)",
                   b->node_count);
}

/* Half the surface area of a box with these extents. */
static double half_area(double x, double y, double z) { return x * y + y * z + z * x; }

void kd_sweep(const kd_builder *b, const uint64_t *ev, size_t n_ev, uint32_t n,
              const tt_aabb *cell, int axis, kd_split *best)
{
    double ext[3];
    for (int k = 0; k < 3; k++) ext[k] = (double)cell->hi[k] - (double)cell->lo[k];
    double area = half_area(ext[0], ext[1], ext[2]);
    if (!(area > 0.0)) return; /* a degenerate cell: probabilities undefined */
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    /* SA(child) = 2 (e_u e_v + e_axis (e_u + e_v)); only e_axis varies. */
    const double cap = ext[u] * ext[v] / area, side = (ext[u] + ext[v]) / area;
    const double lo = cell->lo[axis], hi = cell->hi[axis];
    /* The parameters and the best split so far in locals: stores to *best
     * made the compiler reload them (and b's costs) at every position. */
    const double ct = b->ct, ci = b->ci, ef = b->empty_factor;
    kd_split mine = *best;
    uint32_t nl = 0, nr = n;
    size_t i = 0;
    /* A position's counts in one register: planars in the low half,
     * starts in the high half (a list holds fewer than 2^32 events); the
     * ends are the rest of the position's events. A counter array in
     * memory chained every event through a store and a load. */
    static const uint64_t inc[4] = {0, 1, (uint64_t)1 << 32, 0};
    _Static_assert(KD_END == 0 && KD_PLANAR == 1 && KD_START == 2, "event types");
    while (i < n_ev) {
        /* All events at one position: ends, planars, starts (their order in
         * the sorted list). */
        const uint32_t key = kd_event_poskey(ev[i]);
        const size_t first = i;
        uint64_t acc = 0;
        do acc += inc[kd_event_type(ev[i++])];
        while (i < n_ev && kd_event_poskey(ev[i]) == key);
        const uint32_t planars = (uint32_t)acc, starts = (uint32_t)(acc >> 32);
        const uint32_t ends = (uint32_t)(i - first) - planars - starts;
        nr -= planars + ends;
        const float p = kd_key_float(key);
        /* Only planes strictly inside the cell: a plane on a face would cut
         * off a flat, empty-volume cell. */
        if (p > cell->lo[axis] && p < cell->hi[axis]) {
            const double pl = cap + ((double)p - lo) * side;
            const double pr = cap + (hi - (double)p) * side;
            /* Planar triangles on the right, then on the left (W&H); with
             * none in the plane both costs are the same number. */
            uint32_t l2 = nl, r2 = nr + planars;
            double c = ct + ci * (pl * l2 + pr * r2);
            if (l2 == 0 || r2 == 0) c *= ef;
            int planar_left = 0;
            if (planars) {
                const uint32_t l1 = nl + planars, r1 = nr;
                double c1 = ct + ci * (pl * l1 + pr * r1);
                if (l1 == 0 || r1 == 0) c1 *= ef;
                planar_left = c1 < c;
                if (planar_left) {
                    c = c1;
                    l2 = l1;
                    r2 = r1;
                }
            }
            kd_split_offer(&mine, c, axis, p, planar_left, l2, r2);
        }
        nl += starts + planars;
    }
    *best = mine;
}

/* The SAH prices rays, not memory. Where a split's two children together
 * are no more likely to be visited than the parent (a flat cell: p_l + p_r
 * = 1), duplicating a straddler costs nothing in the model, so on many
 * large overlapping triangles in one plane every split that separates a
 * few of them pays and the greedy recursion runs to the depth limit with
 * the references multiplying at every level (2000 such triangles: 266 M
 * references, minutes of build). The budget bounds that: a split whose
 * children would take the tree past it becomes a leaf. It is far above
 * what real scenes use (the shared ones: 3.1-5.5 references per
 * triangle), so it changes no tree there, and both builders apply it at
 * the same nodes in the same order, so they still build the same tree. */
size_t kd_ref_budget(uint32_t n) { return 64 * (size_t)n + ((size_t)1 << 20); }

int kd_should_split(kd_builder *b, uint32_t n, int depth, const kd_split *best)
{
    if (!(n > 0 && depth < b->max_depth && best->axis >= 0 && best->cost < b->ci * (double)n))
        return 0;
    if (b->par) return kd_par_account(b, n, best);
    if (b->live - n + best->n_left + best->n_right > b->ref_budget) {
        b->budget_hit = 1;
        return 0;
    }
    return 1;
}

void kd_account_split(kd_builder *b, uint32_t n, uint32_t nl, uint32_t nr)
{
    b->live = b->live - n + nl + nr;
}

void kd_split_cell(const tt_aabb *cell, const kd_split *s, tt_aabb *left, tt_aabb *right)
{
    *left = *right = *cell;
    left->hi[s->axis] = s->pos;
    right->lo[s->axis] = s->pos;
}

/* Room for `extra` more node slots. */
static tt_status grow_nodes(kd_builder *b, uint32_t extra)
{
    if (b->node_count + extra <= b->node_cap) return TT_OK;
    if (b->node_count + extra >= TT_KD_MAX_NODES)
        return kd_fail(b, TT_ERR_INVALID_ARGUMENT,
                        "kdtree: the tree needs more than 2^29 nodes; raise cost_traversal or "
                        "lower max_depth");
    uint32_t cap = b->node_cap ? b->node_cap : 1024;
    while (cap < b->node_count + extra) cap *= 2;
    if (cap > TT_KD_MAX_NODES) cap = TT_KD_MAX_NODES;
    tt_kd_node *p = tt_realloc_array(b->ctx, b->nodes, cap, sizeof *p);
    if (!p) return kd_oom(b);
    b->nodes = p;
    b->node_cap = cap;
    return TT_OK;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

tt_status kd_emit_leaf(kd_builder *b, uint32_t *ids, uint32_t n)
{
    tt_status st = grow_nodes(b, 1);
    if (st != TT_OK) return st;
    if (b->ref_count + n > b->ref_cap) {
        size_t cap = b->ref_cap ? b->ref_cap : 4096;
        while (cap < b->ref_count + n) cap *= 2;
        uint32_t *p = tt_realloc_array(b->ctx, b->refs, cap, sizeof *p);
        if (!p) return kd_oom(b);
        b->refs = p;
        b->ref_cap = cap;
    }
    if (b->ref_count + n > UINT32_MAX)
        return kd_fail(b, TT_ERR_OUT_OF_MEMORY, "kdtree: more than 2^32 triangle references");
    /* Most leaves hold a handful of triangles: insertion sort, not qsort's
     * call per comparison. */
    if (n > 32) qsort(ids, n, sizeof *ids, cmp_u32);
    else
        for (uint32_t i = 1; i < n; i++) {
            const uint32_t x = ids[i];
            uint32_t j = i;
            for (; j > 0 && ids[j - 1] > x; j--) ids[j] = ids[j - 1];
            ids[j] = x;
        }
    for (uint32_t i = 0; i < n; i++) b->refs[b->ref_count + i] = ids[i];
    tt_kd_node *node = &b->nodes[b->node_count++];
    node->u.first = (uint32_t)b->ref_count;
    node->bits = (n << 3) | TT_KD_LEAF;
    b->ref_count += n;
    return TT_OK;
}

tt_status kd_emit_interior(kd_builder *b, const kd_split *s, const tt_aabb *cell,
                           const kd_place *here, uint32_t *node, kd_place *child)
{
    /* The root always is augmented (record 0, made before the recursion);
     * below, a node is when it is d_min levels below the last one. */
    int aug = here->depth == 0 || (b->dmin > 0 && here->aug_dist >= b->dmin);
    tt_status st = grow_nodes(b, 1u + (uint32_t)aug);
    if (st != TT_OK) return st;
    uint32_t me = b->node_count;
    uint32_t rec = 0;
    if (aug && here->depth > 0) {
        if (b->aug_count == b->aug_cap) {
            uint32_t cap = b->aug_cap ? 2 * b->aug_cap : 256;
            tt_kd_aug *p = tt_realloc_array(b->ctx, b->aug, cap, sizeof *p);
            if (!p) return kd_oom(b);
            b->aug = p;
            b->aug_cap = cap;
        }
        rec = b->aug_count++;
        tt_kd_aug *a = &b->aug[rec];
        for (int k = 0; k < 3; k++) {
            a->lo[k] = cell->lo[k];
            a->hi[k] = cell->hi[k];
        }
        a->parent = here->parent_aug;
        a->node = me;
    }
    b->nodes[me].u.split = s->pos;
    b->nodes[me].bits = (uint32_t)s->axis | (aug ? TT_KD_AUG_BIT : 0u);
    b->node_count++;
    if (aug) {
        b->nodes[me + 1].u.first = rec;
        b->nodes[me + 1].bits = 0;
        b->node_count++;
    }
    *node = me;
    child->depth = here->depth + 1;
    child->aug_dist = aug ? 1 : here->aug_dist + 1;
    child->parent_aug = aug ? rec : here->parent_aug;
    return TT_OK;
}

void kd_link_right(kd_builder *b, uint32_t node) { b->nodes[node].bits |= b->node_count << 3; }
