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
#include "accel/kdtree/kd_ray.h"
#include "geometry/triangle.h"

/* The running result of one ray. */
#ifndef TT_KD_BEST_DEFINED
#define TT_KD_BEST_DEFINED
typedef struct tt_kd_best {
    float t, u, v;
    uint32_t prim;
} tt_kd_best;

TT_HD void tt_kd_best_init(tt_kd_best *b, const tt_wray *r)
{
    b->t = r->tmax;
    b->u = b->v = 0.0f;
    b->prim = TT_INVALID_ID;
}

TT_HD void tt_kd_best_store(const tt_kd_best *b, tt_hit *hit)
{
    hit->t = b->prim == TT_INVALID_ID ? TT_INF : b->t;
    hit->u = b->u;
    hit->v = b->v;
    hit->prim = b->prim;
}

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
} tt_kd_key;

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
    tt_kd_key best = {TT_INF, 3, 0.0f};
    for (int k = 0; k < 3; k++) {
        if (r->dir[k] == 0.0f) continue;
        const int neg = r->dir[k] < 0.0f;
        const float face = neg ? TT_LDG(&a->lo[k]) : TT_LDG(&a->hi[k]);
        tt_kd_key c = {(face - r->org[k]) * r->inv[k], o->rank[k], neg ? -face : face};
        if (tt_kd_key_after(&best, &c, ties)) best = c;
    }
    return best;
}
#endif

/* Tests a leaf's triangles. Closest hit (any == 0): narrows *best, returns
 * 0. Any hit: returns 1 at the first hit on [tmin, best->t). */
TT_HD int TT_VARIANT(tt_kd_leaf)(const tt_kd_view *T, tt_kd_node leaf, const tt_wray *r, int any,
                                 tt_kd_best *best, tt_ray_stats *stats)
{
    const uint32_t count = tt_kd_leaf_count(leaf.bits);
    const uint32_t *refs = T->refs + leaf.u.first;
    (void)stats;
    TT_COUNT(stats, leaves, 1);
    TT_COUNT(stats, nodes, 1);
    for (uint32_t i = 0; i < count; i++) {
        const uint32_t id = TT_LDG(&refs[i]);
        const float *p = T->tri + 9 * (size_t)id;
        float t, u, v;
        TT_COUNT(stats, triangles, 1);
        if (tt_intersect_triangle(r, p, p + 3, p + 6, best->t, &t, &u, &v)) {
            best->t = t;
            best->u = u;
            best->v = v;
            best->prim = id;
            if (any) return 1;
        }
    }
    return 0;
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
 * lastAugmentedNode and t_up). */
TT_HD tt_kd_node TT_VARIANT(tt_kd_descend)(const tt_kd_view *T, const tt_wray *r,
                                           const tt_kd_order *ord, uint32_t *node,
                                           const tt_kd_key *tentry, tt_kd_key *texit,
                                           unsigned *ties, uint32_t *last, tt_kd_key *tup,
                                           tt_ray_stats *stats)
{
    uint32_t i = *node;
    tt_kd_node n = T->nodes[i];
    tt_kd_key te = *texit;
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
            else {
                *ties |= 1u << k;
                i = ((ord->sides >> k) & 1u) ? right : left;
            }
        } else {
            tt_kd_key c;
            c.t = (n.u.split - r->org[k]) * r->inv[k];
            c.rank = ord->rank[k];
            c.pos = d < 0.0f ? -n.u.split : n.u.split;
            if (tt_kd_key_after(&c, tentry, ties)) {
                i = d < 0.0f ? right : left;
                if (tt_kd_key_after(&te, &c, ties)) te = c;
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
    *node = i;
    *texit = te;
    return n;
}
