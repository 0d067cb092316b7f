/* HTR: the traditional stack-based hierarchical traversal (Havran & Bittner,
 * Algorithm 1), front to back from the root. A template (see
 * accel/stats_variant.h); include kd_trace_common.h first.
 *
 * At a node with the ray on [ta, tb] and the plane crossed at ts +- e (e:
 * the rounding band of kd_ray.h), the child the ray meets first is visited
 * on [ta, min(tb, ts + e)] if that is not empty, the other on
 * [max(ta, ts - e), tb]: both inclusive, so a ray crossing a plane exactly
 * or nearly at a cell boundary (an origin on a split plane, a ray through an
 * edge or a vertex of the tree) also visits the thin cell there. A ray
 * lying in the split plane visits both children over its whole interval.
 * Stack entries whose interval begins at or beyond the closest hit so far
 * are dropped; with front-to-back order that ends the traversal right after
 * the hit's cell. */

#ifndef TT_KD_HTR_ENTRY_DEFINED
#define TT_KD_HTR_ENTRY_DEFINED
/* A deferred far child and the ray's interval in it. */
typedef struct tt_kd_htr_entry {
    uint32_t node;
    float ta, tb;
} tt_kd_htr_entry;

/* Pops the next deferred child that begins before the closest hit so far
 * (t_best) into *node, *ta, *tb; 0 when none is left (the traversal ends). */
TT_HD int tt_kd_htr_pop(const tt_kd_htr_entry *stack, int *sp, float t_best, uint32_t *node,
                        float *ta, float *tb)
{
    do {
        if (*sp == 0) return 0;
        (*sp)--;
    } while (stack[*sp].ta >= t_best);
    *node = stack[*sp].node;
    *ta = stack[*sp].ta;
    *tb = stack[*sp].tb;
    return 1;
}
#endif

/* The general loop, for rays with a zero direction component (they may
 * lie in a split plane, which takes both children). */
TT_HD int TT_VARIANT(tt_kd_htr_general)(const tt_kd_view *T, const tt_wray *r, int any,
                                        tt_kd_best *best, tt_ray_stats *stats)
{
    tt_kd_htr_entry stack[TT_KD_STACK];
    float ta, tb;
    (void)stats;
    tt_kd_band band;
    tt_kd_band_init(&band, r);
    if (!tt_kd_root_interval(T, r, &band, &ta, &tb)) return 0;
    tb = tt_kd_min(tb, r->tmax);
    int sp = 0;
    uint32_t node = 0;
    for (;;) {
        tt_kd_node n = T->nodes[node];
        while (!tt_kd_is_leaf(n.bits)) {
            TT_COUNT(stats, interior, 1);
            TT_COUNT(stats, nodes, 1);
            const int k = tt_kd_axis(n.bits);
            const uint32_t left = tt_kd_left(node, n.bits), right = tt_kd_right(n.bits);
            const float d = r->dir[k];
            if (d == 0.0f) {
                const float o = r->org[k];
                if (o < n.u.split) node = left;
                else if (o > n.u.split) node = right;
                else {
                    stack[sp].node = right;
                    stack[sp].ta = ta;
                    stack[sp].tb = tb;
                    sp++;
                    node = left;
                }
            } else {
                const float ts = (n.u.split - r->org[k]) * r->inv[k];
                const float e = fabsf(n.u.split) * band.bi[k] + band.bo[k];
                const uint32_t first = d < 0.0f ? right : left, second = d < 0.0f ? left : right;
                if (ts + e < ta) {
                    node = second;
                } else if (ts - e > tb) {
                    node = first;
                } else {
                    stack[sp].node = second;
                    stack[sp].ta = tt_kd_max(ta, ts - e);
                    stack[sp].tb = tb;
                    sp++;
                    node = first;
                    tb = tt_kd_min(tb, ts + e);
                }
            }
            n = T->nodes[node];
        }
        if (TT_VARIANT(tt_kd_leaf)(T, n, r, any, best, stats)) return 1;
        if (!tt_kd_htr_pop(stack, &sp, best->t, &node, &ta, &tb)) return 0;
    }
}

/* The loop for rays that move along every axis (nearly all of them): the
 * general loop less its per-node test for a zero direction component, and
 * with one rounding band per axis instead of one per plane:
 * e_k = band * (M_k + |o_k|) / |d_k|, M_k the largest |coordinate| of the
 * scene box along k. Every split plane lies in that box, so e_k bounds each
 * plane's own band (kd_ray.h) from above; a wider band only visits a thin
 * cell more now and then, and the per-node |p| multiply-add goes away.
 * Both pay a few percent (measured A/B, 1 thread).
 *
 * Branches, not selects: making the near / far / both choice with
 * conditional moves (the far child always written to the stack, kept only
 * when both are visited) cut mispredictions 3x in a simulated predictor
 * but made real runs 2x slower, because the next node's address then
 * waits on the plane test; with a predicted branch the next node is
 * fetched at once and the float work runs beside it. For the same reason
 * the near child is picked by a branch on the direction's sign, not by a
 * mask loaded per axis (about 15% slower). */
TT_HD int TT_VARIANT(tt_kd_htr_moving)(const tt_kd_view *T, const tt_wray *r, int any,
                                       tt_kd_best *best, tt_ray_stats *stats)
{
    tt_kd_htr_entry stack[TT_KD_STACK];
    float ta, tb, e[3];
    (void)stats;
    tt_kd_band band;
    tt_kd_band_init(&band, r);
    if (!tt_kd_root_interval(T, r, &band, &ta, &tb)) return 0;
    /* Cells beginning past tmax hold no hit (the stack drops them anyway);
     * cut here, a split beyond tmax (a shadow ray's light, often inside
     * the scene) takes the near child alone and pushes nothing. */
    tb = tt_kd_min(tb, r->tmax);
    for (int k = 0; k < 3; k++) {
        const float m =
            tt_kd_max(fabsf(TT_LDG(&T->aug[0].lo[k])), fabsf(TT_LDG(&T->aug[0].hi[k])));
        e[k] = m * band.bi[k] + band.bo[k];
    }
    int sp = 0;
    uint32_t node = 0;
    for (;;) {
        tt_kd_node n = T->nodes[node];
        while (!tt_kd_is_leaf(n.bits)) {
            TT_COUNT(stats, interior, 1);
            TT_COUNT(stats, nodes, 1);
            const int k = tt_kd_axis(n.bits);
            const uint32_t left = tt_kd_left(node, n.bits), right = tt_kd_right(n.bits);
            const int down = r->dir[k] < 0.0f;
            const uint32_t first = down ? right : left, second = down ? left : right;
            const float ts = (n.u.split - r->org[k]) * r->inv[k];
            const float lo = ts - e[k], hi = ts + e[k];
            if (hi < ta) {
                node = second;
            } else if (lo > tb) {
                node = first;
            } else {
                stack[sp].node = second;
                stack[sp].ta = tt_kd_max(ta, lo);
                stack[sp].tb = tb;
                sp++;
                node = first;
                tb = tt_kd_min(tb, hi);
            }
            n = T->nodes[node];
        }
        /* An empty leaf (the SAH's empty bonus makes many) costs no leaf
         * call in the fast variant; the counting one still counts it. */
        if ((TT_STATS || tt_kd_leaf_count(n.bits) != 0) &&
            TT_VARIANT(tt_kd_leaf)(T, n, r, any, best, stats))
            return 1;
        if (!tt_kd_htr_pop(stack, &sp, best->t, &node, &ta, &tb)) return 0;
    }
}

TT_HD int TT_VARIANT(tt_kd_htr)(const tt_kd_view *T, const tt_wray *r, int any, tt_kd_best *best,
                                tt_ray_stats *stats)
{
    TT_COUNT(stats, boxes, 1);
    if (r->dir[0] != 0.0f && r->dir[1] != 0.0f && r->dir[2] != 0.0f)
        /* A copy of the loop per kind of query: `any` is then a constant
         * in each, and the leaf's any-hit exits fold away in the closest-
         * hit copy. With the empty-leaf skip above: 4-12% faster primary
         * and 1-10% faster shadow rays on bunny, sibenik and conference
         * (Cornell box level), interleaved A/B, 1 thread, CPU time. */
        return any ? TT_VARIANT(tt_kd_htr_moving)(T, r, 1, best, stats)
                   : TT_VARIANT(tt_kd_htr_moving)(T, r, 0, best, stats);
    return TT_VARIANT(tt_kd_htr_general)(T, r, any, best, stats);
}
