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

/* Descends from *node to the leaf where the ray continues after tentry
 * (the "first intersected child" of Algorithm 3; Kaplan's point location
 * done on the ray rather than on a shifted point, so no epsilon is needed):
 * a child is taken first when the ray is in it just after tentry. *texit
 * shrinks to the leaf's exit. The first descent of a ray is inclusive (a
 * plane crossed exactly at tentry, e.g. through the origin, still lets the
 * ray visit the near cell, of zero length); later descents start at a
 * previous leaf's exit and must be strict to move on.
 *
 * A ray lying in a split plane (dir_k == 0, org_k == split) runs along both
 * children; a stackless traversal takes the side `rule` names for that axis
 * (bit k: 0 left, 1 right) and records the axis in *ties, and the caller
 * traces the other side in a second pass. *last and *tup follow the deepest
 * augmented node passed (Algorithm 3's lastAugmentedNode and t_up). */
TT_HD tt_kd_node TT_VARIANT(tt_kd_descend)(const tt_kd_view *T, const tt_wray *r, uint32_t *node,
                                           float tentry, float *texit, int inclusive,
                                           unsigned rule, unsigned *ties, uint32_t *last,
                                           float *tup, tt_ray_stats *stats)
{
    uint32_t i = *node;
    tt_kd_node n = T->nodes[i];
    float te = *texit;
    (void)stats;
    while (!tt_kd_is_leaf(n.bits)) {
        TT_COUNT(stats, interior, 1);
        TT_COUNT(stats, nodes, 1);
        const int k = tt_kd_axis(n.bits);
        const uint32_t left = tt_kd_left(i, n.bits), right = tt_kd_right(n.bits);
        if (r->dir[k] == 0.0f) {
            if (r->org[k] < n.u.split) i = left;
            else if (r->org[k] > n.u.split) i = right;
            else {
                *ties |= 1u << k;
                i = ((rule >> k) & 1u) ? right : left;
            }
        } else {
            const float ts = (n.u.split - r->org[k]) * r->inv[k];
            const int neg = r->dir[k] < 0.0f;
            if (ts > tentry || (inclusive && ts == tentry)) {
                i = neg ? right : left;
                te = fminf(te, ts);
            } else {
                i = neg ? left : right;
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
