/* SLTR: stackless bottom-up traversal (Havran & Bittner, Algorithm 3) and
 * SEQ: Kaplan's sequential traversal. Templates (see
 * accel/stats_variant.h); include kd_trace_common.h first.
 *
 * Both find one leaf at a time by a descent (tt_kd_descend) and move on
 * from that leaf's exit: SLTR restarts the descent from the cached last
 * augmented node while the ray is still inside its box (t_up), else from
 * the nearest augmented ancestor whose box the ray has not yet left; SEQ
 * restarts from the root every time (after a first descent from the start
 * node). A leaf's exit and the next entry are the same key, so there is no
 * epsilon shift and no leaf is skipped or repeated.
 *
 * A single stackless pass follows one path through the cells. Where the
 * ray meets several cells at once (it lies in a split plane, or passes
 * exactly through an edge or corner of the tree, e.g. from an origin on
 * several split planes) a pass sees only some of them, so such a ray is
 * traced once per way of ordering the tie (see tt_kd_order), the passes
 * sharing the closest hit. Only rays that meet an exact tie pay for more
 * than one pass. */

/* One SLTR pass from augmented node `start`, entering at ta, climbing no
 * higher than `stop` (TT_KD_NO_PARENT: up to the root). 1 on an any-hit. */
TT_HD int TT_VARIANT(tt_kd_sltr_pass)(const tt_kd_view *T, const tt_wray *r, int any,
                                      const tt_kd_order *ord, uint32_t start, float ta,
                                      uint32_t stop, unsigned *ties, tt_kd_best *best,
                                      uint32_t *end, tt_ray_stats *stats)
{
    uint32_t last = start;
    tt_kd_key tup = tt_kd_box_exit_key(&T->aug[start], r, ord, ties);
    tt_kd_key tentry = {ta, -1, -TT_INF};
    for (;;) {
        uint32_t node = T->aug[last].node;
        tt_kd_key texit = tup;
        tt_kd_node leaf = TT_VARIANT(tt_kd_descend)(T, r, ord, &node, &tentry, &texit, ties, &last,
                                                    &tup, stats);
        if (TT_VARIANT(tt_kd_leaf)(T, leaf, r, any, best, stats)) {
            *end = last;
            return 1;
        }
        /* The ray ends in this leaf's box (or, past the last leaf, on the
         * scene box right behind it). */
        if (best->prim != TT_INVALID_ID) *end = last;
        if (best->t <= texit.t) return 0;
        tentry = texit;
        if (tt_kd_key_after(&tup, &tentry, ties)) continue; /* still inside the last box */
        int found = 0;
        uint32_t a = last;
        while (!found && a != stop && T->aug[a].parent != TT_KD_NO_PARENT) {
            a = T->aug[a].parent;
            TT_COUNT(stats, boxes, 1);
            const tt_kd_key e = tt_kd_box_exit_key(&T->aug[a], r, ord, ties);
            if (tt_kd_key_after(&e, &tentry, ties)) {
                found = 1;
                last = a;
                tup = e;
            }
        }
        if (!found) return 0;
    }
}

/* One SEQ pass: the first descent from `start`, every later one from the
 * root. */
TT_HD int TT_VARIANT(tt_kd_seq_pass)(const tt_kd_view *T, const tt_wray *r, int any,
                                     const tt_kd_order *ord, uint32_t start, float ta,
                                     unsigned *ties, tt_kd_best *best, uint32_t *end,
                                     tt_ray_stats *stats)
{
    const tt_kd_key root_exit = tt_kd_box_exit_key(&T->aug[0], r, ord, ties);
    uint32_t node = T->aug[start].node, last = start;
    tt_kd_key tentry = {ta, -1, -TT_INF};
    tt_kd_key texit = tt_kd_box_exit_key(&T->aug[start], r, ord, ties), tup = texit;
    for (;;) {
        tt_kd_node leaf = TT_VARIANT(tt_kd_descend)(T, r, ord, &node, &tentry, &texit, ties, &last,
                                                    &tup, stats);
        if (TT_VARIANT(tt_kd_leaf)(T, leaf, r, any, best, stats)) {
            *end = last;
            return 1;
        }
        /* The ray ends in this leaf's box (or, past the last leaf, on the
         * scene box right behind it). */
        if (best->prim != TT_INVALID_ID) *end = last;
        if (best->t <= texit.t) return 0;
        if (!tt_kd_key_after(&root_exit, &texit, ties)) return 0; /* left the scene */
        tentry = texit;
        node = 0;
        last = 0;
        texit = root_exit;
    }
}

/* The passes (see above), for SLTR (seq == 0) or SEQ. */
TT_HD int TT_VARIANT(tt_kd_stackless)(const tt_kd_view *T, const tt_wray *r, int any, int seq,
                                      uint32_t hint, tt_kd_best *best, uint32_t *end,
                                      tt_ray_stats *stats)
{
    float ta, tb;
    unsigned tests = 1;
    (void)stats;
    if (!tt_kd_root_interval(T, r, NULL, &ta, &tb)) {
        TT_COUNT(stats, boxes, tests);
        return 0;
    }
    const uint32_t start = tt_kd_start_node(T, r, hint, &ta, &tb, &tests);
    TT_COUNT(stats, boxes, tests);
    unsigned ties = 0, pass = 0;
    uint64_t done = 0;
    for (;;) {
        tt_kd_order ord;
        tt_kd_order_init(&ord, pass);
        done |= (uint64_t)1 << pass;
        int hit = seq ? TT_VARIANT(tt_kd_seq_pass)(T, r, any, &ord, start, ta, &ties, best, end, stats)
                      : TT_VARIANT(tt_kd_sltr_pass)(T, r, any, &ord, start, ta, TT_KD_NO_PARENT,
                                                    &ties, best, end, stats);
        if (hit) return 1;
        /* The next untried pass over the ties seen so far. */
        const unsigned perms = (ties & TT_KD_CORNER_TIE) ? 6u : 1u;
        for (pass = 0; pass < 8u * perms; pass++)
            if ((pass & 7u & ~ties) == 0 && !((done >> pass) & 1u)) break;
        if (pass == 8u * perms) return 0;
    }
}
