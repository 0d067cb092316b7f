/* Traversal template pieces shared by the kd-tree traversals (see
 * accel/stats_variant.h: included once per variant, no include guard).
 *
 * Closest hits are kept "closest so far": a leaf tests its triangles on the
 * ray's whole [tmin, best) rather than on the cell's interval, so every hit
 * recorded is a true hit of the ray, wherever the triangle was found. A
 * traversal may stop once the cells still to visit begin at or beyond best.
 * A triangle straddling several cells therefore needs neither mailboxing
 * nor an interval test with a tolerance: it is found in the first of its
 * cells the ray visits and cannot be beaten by a triangle further on. */
#include "accel/kdtree/trace/kd_ray.h"
#include "accel/kdtree/trace/kd_best.h"
#include "geometry/triangle.h"

#ifndef TT_KD_KEY_DEFINED
#define TT_KD_KEY_DEFINED
/* The stackless traversals move from cell to cell by plane crossings
 * compared as keys: the distance t, then, for planes crossed at exactly
 * the same t, the pass's rank of the plane's axis (as if the ray were
 * displaced a tiny bit so that the crossings happen in that order), then,
 * for parallel planes at the same t (rounding), their order along the ray.
 * The keys are a total order, so a traversal never loops, and every pass
 * order together visit every cell around a point where planes meet. Rank
 * -1 marks the ray's start, before any crossing at the same t. */
typedef struct tt_kd_key {
    float t;
    int rank;
    float pos; /* plane position, negated for a ray going down its axis */
    float err; /* rounding band of t (kd_ray.h): the true crossing is within t +- err */
} tt_kd_key;

/* The rounding band of a crossing of plane x_k = p (kd_ray.h's e) from
 * the ray's per-axis factors band |inv_k| and |o_k|: a descent takes them
 * once and then pays one multiply-add a plane. Every band goes through
 * here, so a descent and a re-descent count the same near planes. */
TT_HD float tt_kd_cross_err_of(float band_inv, float abs_org, float p)
{
    return band_inv * (fabsf(p) + abs_org);
}

TT_HD float tt_kd_cross_err(const tt_wray *r, int k, float p)
{
    return tt_kd_cross_err_of(TT_KD_BAND * fabsf(r->inv[k]), fabsf(r->org[k]), p);
}

/* Whether crossing c may, for the true ray, come on the other side of
 * entry point e: their distance is within both rounding bands. */
TT_HD int tt_kd_near(const tt_kd_key *c, const tt_kd_key *e)
{
    return fabsf(c->t - e->t) <= c->err + e->err;
}

#define TT_KD_CORNER_TIE 8u /* in *ties: equal crossings needed the ranks */

/* Whether crossing a comes after crossing b. A comparison of two planes of
 * different axes crossed at exactly the same t is decided by the pass's
 * ranks, which only one of the orders follows: it sets TT_KD_CORNER_TIE in
 * *ties so that the other orders are traced too. */
TT_HD int tt_kd_key_after(const tt_kd_key *a, const tt_kd_key *b, unsigned *ties)
{
    if (a->t != b->t) return a->t > b->t;
    if (a->rank != b->rank) {
        if (a->rank >= 0 && b->rank >= 0) *ties |= TT_KD_CORNER_TIE;
        return a->rank > b->rank;
    }
    return a->pos > b->pos;
}

/* A pass: the side taken in split planes the ray lies in, per axis, and the
 * ranks of the axes for crossings at equal distances. */
typedef struct tt_kd_order {
    unsigned sides;
    int rank[3];
} tt_kd_order;

/* Pass p (0 .. 47): sides p & 7, axis ranks the (p >> 3)-th permutation. */
TT_HD void tt_kd_order_init(tt_kd_order *o, unsigned p)
{
    const unsigned perm = (p >> 3) % 6u;
    const int first = (int)(perm / 2u), second = (first + 1 + (int)(perm % 2u)) % 3;
    o->sides = p & 7u;
    o->rank[first] = 0;
    o->rank[second] = 1;
    o->rank[3 - first - second] = 2;
}

/* Where the ray leaves a sparse box, as a key: the earliest face crossing. */
TT_HD tt_kd_key tt_kd_box_exit_key(const tt_kd_aug *a, const tt_wray *r, const tt_kd_order *o,
                                   unsigned *ties)
{
    tt_kd_key best = {TT_INF, 3, 0.0f, 0.0f};
    for (int k = 0; k < 3; k++) {
        if (r->dir[k] == 0.0f) continue;
        const int neg = r->dir[k] < 0.0f;
        const float face = neg ? TT_LDG(&a->lo[k]) : TT_LDG(&a->hi[k]);
        tt_kd_key c = {(face - r->org[k]) * r->inv[k], o->rank[k], neg ? -face : face,
                       tt_kd_cross_err(r, k, face)};
        if (tt_kd_key_after(&best, &c, ties)) best = c;
    }
    return best;
}

/* Whether entry point e lies within the rounding band of a face of box a
 * (d_k == 0 is exact: the ray's coordinate is org_k itself). Cells across
 * such a face lie outside the box, so searching around e must start
 * higher up. */
TT_HD int tt_kd_near_faces(const tt_kd_aug *a, const tt_wray *r, const tt_kd_key *e)
{
    for (int k = 0; k < 3; k++) {
        if (r->dir[k] == 0.0f) continue;
        for (int side = 0; side < 2; side++) {
            const float face = side ? TT_LDG(&a->hi[k]) : TT_LDG(&a->lo[k]);
            tt_kd_key c;
            c.t = (face - r->org[k]) * r->inv[k];
            c.err = tt_kd_cross_err(r, k, face);
            if (tt_kd_near(&c, e)) return 1;
        }
    }
    return 0;
}
#endif

/* Tests a leaf's triangles. Closest hit (any == 0): narrows *best, returns
 * 0. Any hit: returns 1 at the first hit on [tmin, best->t).
 *
 * A per-ISA unit (kd_trace_avx2.c ...) defines TT_KD_LEAF_FAST to its own
 * leaf kernel, with the same results, for the fast variant it compiles; the
 * counting variant always runs this loop, so statistics count one triangle
 * test per triangle whatever the ISA. */
TT_HD int TT_VARIANT(tt_kd_leaf)(const tt_kd_view *T, tt_kd_node leaf, const tt_wray *r, int any,
                                 tt_kd_best *best, tt_ray_stats *stats)
{
#if defined(TT_KD_LEAF_FAST) && !TT_STATS
    (void)stats;
    return TT_KD_LEAF_FAST(T, leaf, r, any, best);
#else
    const uint32_t count = tt_kd_leaf_count(leaf.bits);
    const uint32_t *refs = T->refs + leaf.u.first;
    (void)stats;
    TT_COUNT(stats, leaves, 1);
    TT_COUNT(stats, nodes, 1);
    uint32_t tested;
    const int hit = tt_kd_leaf_refs(T, refs, count, r, any, best, &tested);
    TT_COUNT(stats, triangles, tested);
    return hit;
#endif
}

/* Descends from *node to the leaf the ray enters after *tentry (the "first
 * intersected child" of Algorithm 3; Kaplan's point location done on the
 * ray rather than on a shifted point, so no epsilon is needed): at each
 * split, the child the ray meets first is taken when the ray crosses the
 * plane after tentry. *texit shrinks to the leaf's exit.
 *
 * Crossings are compared as keys (see tt_kd_key): equal distances are
 * ordered by the pass's axis ranks, so a ray through an edge or corner of
 * the tree (an origin on several split planes) moves through the cells
 * around it in a definite order; *ties records that such an order was
 * needed, and the caller runs passes with the other orders.
 *
 * A ray lying in a split plane (dir_k == 0, org_k == split) runs along both
 * children; the pass takes the side its sides mask names for that axis
 * (bit k: 0 left, 1 right) and records the axis in *ties.
 *
 * *last and *tup follow the deepest augmented node passed (Algorithm 3's
 * lastAugmentedNode and t_up).
 *
 * Near-exact ties (see kd_trace_sltr.h): amb->all counts the nodes whose
 * plane the ray crosses within the rounding band of the entry point
 * (tt_kd_near), where the computed choice of child may differ from where
 * the triangle test sees the ray; amb->other those that are not the plane
 * the ray entered through (crossed at exactly the entry key); amb->edge is
 * set when a plane on the path other than the exit plane is crossed within
 * the band of the exit, and amb->box_exit when the exit is the face of the
 * start box (*texit on input), whose other faces the path did not see. */
#ifndef TT_KD_AMB_DEFINED
#define TT_KD_AMB_DEFINED
typedef struct tt_kd_amb {
    unsigned all, other;
    int edge, box_exit;
} tt_kd_amb;

TT_HD int tt_kd_key_same(const tt_kd_key *a, const tt_kd_key *b)
{
    return a->t == b->t && a->rank == b->rank && a->pos == b->pos;
}

/* Whether a face of box a the ray leaves through, other than the exit
 * crossing itself, is crossed within the band of that exit. */
TT_HD int tt_kd_box_exit_near_edge(const tt_kd_aug *a, const tt_wray *r, const tt_kd_key *exit)
{
    for (int k = 0; k < 3; k++) {
        if (r->dir[k] == 0.0f) continue;
        const int neg = r->dir[k] < 0.0f;
        const float face = neg ? TT_LDG(&a->lo[k]) : TT_LDG(&a->hi[k]);
        tt_kd_key c;
        c.t = (face - r->org[k]) * r->inv[k];
        c.pos = neg ? -face : face;
        c.err = tt_kd_cross_err(r, k, face);
        if (!(c.t == exit->t && c.pos == exit->pos) && tt_kd_near(&c, exit)) return 1;
    }
    return 0;
}
#endif

TT_HD tt_kd_node TT_VARIANT(tt_kd_descend)(const tt_kd_view *T, const tt_wray *r,
                                           const tt_kd_order *ord, uint32_t *node,
                                           const tt_kd_key *tentry, tt_kd_key *texit,
                                           unsigned *ties, uint32_t *last, tt_kd_key *tup,
                                           tt_kd_amb *amb, tt_ray_stats *stats)
{
    uint32_t i = *node;
    tt_kd_node n = T->nodes[i];
    tt_kd_key te = *texit, te2 = {TT_INF, 3, 0.0f, 0.0f};
    int box_exit = 1;
    /* tt_kd_cross_err's per-axis factors, taken once per descent. */
    float bi[3], ao[3];
    for (int k = 0; k < 3; k++) {
        bi[k] = TT_KD_BAND * fabsf(r->inv[k]);
        ao[k] = fabsf(r->org[k]);
    }
    const float e_t = tentry->t;
    (void)stats;
    while (!tt_kd_is_leaf(n.bits)) {
        TT_COUNT(stats, interior, 1);
        TT_COUNT(stats, nodes, 1);
        const int k = tt_kd_axis(n.bits);
        const uint32_t left = tt_kd_left(i, n.bits), right = tt_kd_right(n.bits);
        const float d = r->dir[k], split = n.u.split;
        if (d == 0.0f) {
            if (r->org[k] < split) i = left;
            else if (r->org[k] > split) i = right;
            else {
                *ties |= 1u << k;
                i = ((ord->sides >> k) & 1u) ? right : left;
            }
        } else {
            const float ct = (split - r->org[k]) * r->inv[k];
            tt_kd_key c;
            c.t = ct;
            c.rank = ord->rank[k];
            c.pos = d < 0.0f ? -split : split;
            c.err = tt_kd_cross_err_of(bi[k], ao[k], split);
            if (tt_kd_near(&c, tentry)) {
                amb->all++;
                amb->other += (unsigned)!tt_kd_key_same(&c, tentry);
            }
            /* tt_kd_key_after's order, its common case (distinct
             * distances decide alone) written out: keys are whole only
             * for ties. */
            if (ct != e_t ? ct > e_t : tt_kd_key_after(&c, tentry, ties)) {
                i = d < 0.0f ? right : left;
                if (ct < te.t || (ct == te.t && tt_kd_key_after(&te, &c, ties))) {
                    te2 = te;
                    te = c;
                    box_exit = 0;
                } else if (ct < te2.t || (ct == te2.t && tt_kd_key_after(&te2, &c, ties))) {
                    te2 = c;
                }
            } else {
                i = d < 0.0f ? left : right;
            }
        }
        n = T->nodes[i];
        if (!tt_kd_is_leaf(n.bits) && tt_kd_is_aug(n.bits)) {
            *last = tt_kd_aug_index(T->nodes, i);
            *tup = te;
        }
    }
    amb->edge = tt_kd_near(&te2, &te);
    amb->box_exit = box_exit;
    *node = i;
    *texit = te;
    return n;
}

/* A descent like tt_kd_descend's from augmented node `from` at entry point
 * *tentry, taking the other child at the i-th near-ambiguous node (see
 * tt_kd_descend's *amb) where bit i of mask is set. *amb: how many such
 * nodes the path met. */
TT_HD tt_kd_node TT_VARIANT(tt_kd_descend_mask)(const tt_kd_view *T, const tt_wray *r,
                                                const tt_kd_order *ord, uint32_t from,
                                                const tt_kd_key *tentry, uint32_t mask,
                                                unsigned *amb, tt_ray_stats *stats)
{
    uint32_t i = T->aug[from].node;
    tt_kd_node n = T->nodes[i];
    unsigned ties = 0, count = 0;
    (void)stats;
    while (!tt_kd_is_leaf(n.bits)) {
        TT_COUNT(stats, interior, 1);
        TT_COUNT(stats, nodes, 1);
        const int k = tt_kd_axis(n.bits);
        const uint32_t left = tt_kd_left(i, n.bits), right = tt_kd_right(n.bits);
        const float d = r->dir[k];
        if (d == 0.0f) {
            if (r->org[k] < n.u.split) i = left;
            else if (r->org[k] > n.u.split) i = right;
            else i = ((ord->sides >> k) & 1u) ? right : left;
        } else {
            tt_kd_key c;
            c.t = (n.u.split - r->org[k]) * r->inv[k];
            c.rank = ord->rank[k];
            c.pos = d < 0.0f ? -n.u.split : n.u.split;
            c.err = tt_kd_cross_err(r, k, n.u.split);
            int near_first = tt_kd_key_after(&c, tentry, &ties);
            if (tt_kd_near(&c, tentry)) {
                if (count < 32u && ((mask >> count) & 1u)) near_first = !near_first;
                count++;
            }
            i = (near_first == (d < 0.0f)) ? right : left;
        }
        n = T->nodes[i];
    }
    *amb = count;
    return n;
}

#ifndef TT_KD_BUDGET_DEFINED
#define TT_KD_BUDGET_DEFINED
/* What the near-tie search may still spend on one ray, in descents: the
 * re-descents of tt_kd_around and every descent of a pass after the first
 * (main: what a main descent costs in the current pass, 0 in the first).
 * The search is exact but exponential in the near-ambiguous planes on one
 * path (2^n descents), which real trees keep at a handful and a scene far
 * from the origin, whose planes all lie within one rounding band, makes
 * dozens. When the budget would be exceeded the search gives up (over) and
 * the caller finishes the ray with a traversal that needs no search (see
 * kd_trace_sltr.h), so the bound costs no exactness. */
typedef struct tt_kd_budget {
    unsigned spare, main;
    int over;
} tt_kd_budget;

/* Takes n descents from the budget; 0 (and over set) if they do not fit. */
TT_HD int tt_kd_budget_take(tt_kd_budget *b, unsigned n)
{
    if (b->over || n > b->spare) {
        b->over = 1;
        return 0;
    }
    b->spare -= n;
    return 1;
}
#endif

/* The leaves around entry point *tentry that a near-ambiguous choice may
 * hide: every combination of choices at the near-ambiguous nodes below
 * augmented node `from`, one stackless descent each (mask bit i flips the
 * i-th such node of the path). The combination 0 (the computed path) is
 * skipped when the caller has already visited it and passes its count in
 * amb. Leaves are tested on the ray's whole [tmin, best) like any other,
 * so extra leaves cost only time. 1 on an any-hit, and when the descents
 * do not fit the budget (budget->over; a path with more than 31
 * near-ambiguous nodes never fits). */
TT_HD int TT_VARIANT(tt_kd_around)(const tt_kd_view *T, const tt_wray *r, int any,
                                   const tt_kd_order *ord, uint32_t from, const tt_kd_key *tentry,
                                   int skip_computed, unsigned amb, tt_kd_budget *budget,
                                   tt_kd_best *best, tt_ray_stats *stats)
{
    unsigned most = amb;
    /* All the combinations known to be needed must fit, or none is tried. */
    if (most > 31u || !tt_kd_budget_take(budget, 0u) ||
        (1u << most) - (unsigned)skip_computed > budget->spare) {
        budget->over = 1;
        return 1;
    }
    for (uint32_t m = skip_computed ? 1u : 0u; m < (1u << most); m++) {
        unsigned count;
        if (!tt_kd_budget_take(budget, 1u)) return 1;
        tt_kd_node leaf = TT_VARIANT(tt_kd_descend_mask)(T, r, ord, from, tentry, m, &count, stats);
        if (count > most) {
            /* This path meets more near planes: their combinations too. */
            if (count > 31u || (1u << count) - m - 1u > budget->spare) {
                budget->over = 1;
                return 1;
            }
            most = count;
        }
        if ((m >> count) != 0u) continue; /* same path as a smaller mask */
        if (TT_VARIANT(tt_kd_leaf)(T, leaf, r, any, best, stats)) return 1;
    }
    return 0;
}
