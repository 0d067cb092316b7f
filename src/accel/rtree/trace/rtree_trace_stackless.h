/* Stackless traversal (Feldmann 2015, Listing 1), a template compiled once
 * per statistics variant (see accel/stats_variant.h) and shared with the
 * CUDA backend: depth first over the packed tree using only the index
 * arithmetic (n_e, n_p, chi); no stack, constant memory per ray. A box
 * farther than the closest hit so far is skipped; with `any` set (shadow
 * rays) the first hit ends the traversal.
 *
 * One refinement of the listing that changes no result: a node's entries
 * are its first child slots, so an empty slot means its later siblings are
 * empty too and the walk goes straight up instead of stepping over them. */
#include "accel/rtree/trace/rtree_trace_leaf.h"

TT_RT_INLINE int TT_VARIANT(tt_rt_stackless_m)(const tt_rtree_packed *TT_RESTRICT t, const uint32_t Mc,
        const tt_wray *r, int any, tt_hit *hit, tt_ray_stats *stats)
{
    const uint32_t M = Mc, L = t->L; /* M == t->M, a constant when specialised */
    float best = r->tmax, bu = 0.0f, bv = 0.0f;
    uint32_t found = TT_INVALID_ID;
    /* n: the slot (paper's numbering) on level l; g, pos: its group and
     * position chi(n) there, kept along so that no step divides n */
    uint32_t n = 0, l = L, pos = M - 1; /* the root: group 0, last position */
    const float *g = t->box;
    tt_rt_planes planes; /* the ray's near/far bound arrays, once per ray */
    tt_rt_planes_init(&planes, r, M);
    (void)stats;
    TT_COUNT(stats, rays, 1);
    for (;;) {
        const int empty = TT_LDG(g + pos) == TT_INF;
        if (!empty) {
            TT_COUNT(stats, boxes, 1);
            if (tt_rt_box_test_at(r, &planes, g + pos, best) < best) {
                TT_COUNT(stats, nodes, 1);
                if (l > 0) { /* n = n_e(n), one level down */
                    TT_COUNT(stats, interior, 1);
                    g = tt_rt_child_group_m(t, M, n, l);
                    n = tt_rt_first_child_m(t, M, n, l);
                    l--;
                    pos = 0;
                    continue;
                }
                if (TT_VARIANT(tt_rt_leaf)(t, n, r, any, &best, &bu, &bv, &found, stats)) return 1;
            }
        }
        /* the next sibling (chi(n) < M - 1), or the next sibling of the
         * nearest ancestor that has one (n = n_p(n)); done at the root */
        int last = empty;
        for (;;) {
            if (l == L) goto done;
            if (!last && pos < M - 1) {
                n++;
                pos++;
                break;
            }
            const uint32_t kp = tt_rt_div_m(t, M, n - t->delta[l]); /* n_p(n) - Delta_L(l+1) */
            n = kp + t->delta[l + 1];
            l++;
            if (l == L) goto done;
            pos = tt_rt_mod_m(t, M, kp); /* chi(n_p(n)) */
            g = t->box + (size_t)(t->gfirst[l] + tt_rt_div_m(t, M, kp)) * 6 * M;
            last = 0;
        }
    }
done:
    return tt_rt_finish(t, any, found, best, bu, bv, hit);
}

/* Not specialised for M = 4 like the other traversals: with one box test
 * per step there is little index arithmetic to fold, and the specialised
 * code measured about 5% more instructions per shadow ray. */
TT_HD int TT_VARIANT(tt_rt_stackless)(const tt_rtree_packed *TT_RESTRICT t, const tt_wray *r, int any,
                                tt_hit *hit, tt_ray_stats *stats)
{
    return TT_VARIANT(tt_rt_stackless_m)(t, t->M, r, any, hit, stats);
}
