/* BTR: bottom-up traversal with a stack (Havran & Bittner, Algorithm 2). A
 * template (see accel/stats_variant.h); include kd_trace_common.h first.
 *
 * A round is a stack traversal (exactly HTR's, rounding band included) of
 * one augmented node's subtree over the ray's interval inside its box. The
 * first round starts in the hinted node (or the nearest augmented ancestor
 * holding the origin). When a round ends without a hit closer than its box
 * exit T, the ray continues from the nearest augmented ancestor whose box it
 * has not yet left, over [T, ancestor's exit]: the paper's TraverseUp.
 * Instead of the paper's epsilon shift of the entry point, the new round
 * never enters the subtree the previous round covered, and where the plane
 * the ray left that subtree through is crossed exactly at T (the same
 * number: see kd_ray.h), it takes only the far side. When the ray left
 * near an edge or corner of the covered box (another face crossed within
 * the rounding band), it goes down the near side too, with the band, to
 * visit the cells around the exit point outside the covered subtree. */

/* Rounds from augmented node `start` on [ta, tb], climbing no higher than
 * `stop` (TT_KD_NO_PARENT: up to the root). */
TT_HD int TT_VARIANT(tt_kd_btr_from)(const tt_kd_view *T, const tt_wray *r, int any,
                                     uint32_t start, float ta, float tb, uint32_t stop,
                                     tt_kd_best *best, uint32_t *end, tt_ray_stats *stats)
{
    struct {
        uint32_t node, aug;
        float ta, tb;
        int holds; /* the subtree holds the covered node                    */
    } stack[TT_KD_STACK];
    tt_kd_band band;
    (void)stats;
    tt_kd_band_init(&band, r);
    uint32_t done = TT_KD_NO_PARENT; /* the node the previous round covered */
    float restart = -TT_INF;         /* where it ended (its box exit)       */
    int reached = 0;                 /* *end is the leaf reaching the hit   */
    for (;;) {
        const float round_tb = tb;
        uint32_t node = T->aug[start].node, aug = start;
        int holds = done != TT_KD_NO_PARENT, sp = 0;
        for (;;) {
            tt_kd_node n = T->nodes[node];
            while (!tt_kd_is_leaf(n.bits)) {
                if (node == done) goto next; /* covered by the previous round */
                TT_COUNT(stats, interior, 1);
                TT_COUNT(stats, nodes, 1);
                if (tt_kd_is_aug(n.bits)) aug = tt_kd_aug_index(T->nodes, node);
                const int k = tt_kd_axis(n.bits);
                const uint32_t left = tt_kd_left(node, n.bits), right = tt_kd_right(n.bits);
                const float d = r->dir[k];
                /* Which child holds the covered node (DFS layout: the left
                 * subtree is [left, right)). */
                const int lholds = holds && done < right, rholds = holds && !lholds;
                if (d == 0.0f) {
                    const float o = r->org[k];
                    if (o < n.u.split) node = left, holds = lholds;
                    else if (o > n.u.split) node = right, holds = rholds;
                    else {
                        stack[sp].node = right;
                        stack[sp].aug = aug;
                        stack[sp].ta = ta;
                        stack[sp].tb = tb;
                        stack[sp].holds = rholds;
                        sp++;
                        node = left;
                        holds = lholds;
                    }
                } else {
                    const float ts = (n.u.split - r->org[k]) * r->inv[k];
                    const float e = fabsf(n.u.split) * band.bi[k] + band.bo[k];
                    const int neg = d < 0.0f;
                    const uint32_t first = neg ? right : left, second = neg ? left : right;
                    const int fholds = neg ? rholds : lholds, sholds = neg ? lholds : rholds;
                    if (ts + e < ta || (fholds && ts == restart)) {
                        node = second;
                        holds = sholds;
                    } else if (ts - e > tb) {
                        node = first;
                        holds = fholds;
                    } else {
                        stack[sp].node = second;
                        stack[sp].aug = aug;
                        stack[sp].ta = tt_kd_max(ta, ts - e);
                        stack[sp].tb = tb;
                        stack[sp].holds = sholds;
                        sp++;
                        node = first;
                        holds = fholds;
                        tb = tt_kd_min(tb, ts + e);
                    }
                }
                n = T->nodes[node];
            }
            if (TT_VARIANT(tt_kd_leaf)(T, n, r, any, best, stats)) {
                *end = aug;
                return 1;
            }
            /* The ray ends in the first leaf that reaches its closest hit
             * (or, when the hit lies a rounding error past the last leaf, on
             * the scene box right behind the last one). */
            if (best->prim != TT_INVALID_ID && (best->t <= tb || !reached)) {
                *end = aug;
                reached = best->t <= tb;
            }
        next:
            do {
                if (sp == 0) goto round_done;
                sp--;
            } while (stack[sp].ta >= best->t);
            node = stack[sp].node;
            aug = stack[sp].aug;
            ta = stack[sp].ta;
            tb = stack[sp].tb;
            holds = stack[sp].holds;
        }
    round_done:
        if (best->t <= round_tb) return 0;
        /* TraverseUp: the nearest augmented ancestor the ray is still in. */
        uint32_t a = start;
        int found = 0;
        while (!found && a != stop && T->aug[a].parent != TT_KD_NO_PARENT) {
            a = T->aug[a].parent;
            TT_COUNT(stats, boxes, 1);
            const float e = tt_kd_box_exit(&T->aug[a], r);
            if (round_tb < e) {
                found = 1;
                done = T->aug[start].node;
                /* Near an edge of the covered box, the cells around the exit
                 * point need the near sides too: no shortcut then. */
                restart = tt_kd_exit_near_edge(&T->aug[start], r, &band, round_tb) ? -TT_INF
                                                                                   : round_tb;
                start = a;
                ta = round_tb;
                tb = e;
            }
        }
        if (!found) return 0;
    }
}

TT_HD int TT_VARIANT(tt_kd_btr)(const tt_kd_view *T, const tt_wray *r, int any, uint32_t hint,
                                tt_kd_best *best, uint32_t *end, tt_ray_stats *stats)
{
    float ta, tb;
    unsigned tests = 1;
    tt_kd_band band;
    (void)stats;
    tt_kd_band_init(&band, r);
    if (!tt_kd_root_interval(T, r, &band, &ta, &tb)) {
        TT_COUNT(stats, boxes, tests);
        return 0;
    }
    uint32_t start = tt_kd_start_node(T, r, hint, &ta, &tb, &tests);
    TT_COUNT(stats, boxes, tests);
    return TT_VARIANT(tt_kd_btr_from)(T, r, any, start, ta, tb, TT_KD_NO_PARENT, best, end, stats);
}
