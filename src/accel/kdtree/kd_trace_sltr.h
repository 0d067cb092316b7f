/* SLTR: stackless bottom-up traversal (Havran & Bittner, Algorithm 3) and
 * SEQ: Kaplan's sequential traversal. Templates (see
 * accel/stats_variant.h); include kd_trace_common.h first.
 *
 * Both find one leaf at a time by a descent (tt_kd_descend) and move on
 * from that leaf's exit distance: SLTR restarts the descent from the cached
 * last augmented node while the ray is still inside its box (t_up), else
 * from the nearest augmented ancestor whose box the ray has not yet left;
 * SEQ restarts from the root every time (after a first descent from the
 * start node). The exit distance of a leaf and the entry of the next are
 * the same number, so there is no epsilon shift and no leaf is skipped or
 * repeated.
 *
 * A ray lying in a split plane belongs to both sides of it, which a single
 * stackless pass cannot visit; such a ray is traced once per combination of
 * sides for the tied axes (at most 2 axes, 4 passes; only rays with zero
 * direction components can tie), the passes sharing the closest hit. */

/* One SLTR pass from start node `start` on [ta, tb], climbing no higher
 * than `stop` (TT_KD_NO_PARENT: up to the root). Returns 1 on an any-hit. */
TT_HD int TT_VARIANT(tt_kd_sltr_pass)(const tt_kd_view *T, const tt_wray *r, int any,
                                      uint32_t start, float ta, float tb, uint32_t stop,
                                      unsigned rule,
                                      unsigned *ties, tt_kd_best *best, uint32_t *end,
                                      tt_ray_stats *stats)
{
    uint32_t last = start;
    float tup = tb, tentry = ta;
    int inclusive = 1;
    for (;;) {
        uint32_t node = T->aug[last].node;
        float texit = tup;
        tt_kd_node leaf = TT_VARIANT(tt_kd_descend)(T, r, &node, tentry, &texit, inclusive, rule,
                                                    ties, &last, &tup, stats);
        if (TT_VARIANT(tt_kd_leaf)(T, leaf, r, any, best, stats)) {
            *end = last;
            return 1;
        }
        if (best->t <= texit) {
            if (best->prim != TT_INVALID_ID) *end = last;
            return 0;
        }
        tentry = texit;
        inclusive = 0;
        if (tentry < tup) continue; /* still inside the last augmented box */
        int found = 0;
        uint32_t a = last;
        while (!found && a != stop && T->aug[a].parent != TT_KD_NO_PARENT) {
            a = T->aug[a].parent;
            TT_COUNT(stats, boxes, 1);
            const float e = tt_kd_box_exit(&T->aug[a], r);
            if (tentry < e) {
                found = 1;
                last = a;
                tup = e;
            }
        }
        if (!found) return 0;
    }
}

/* One SEQ pass: the first descent from `start` on [ta, tb], every later
 * one from the root on [tentry, root_tb]. */
TT_HD int TT_VARIANT(tt_kd_seq_pass)(const tt_kd_view *T, const tt_wray *r, int any,
                                     uint32_t start, float ta, float tb, float root_tb,
                                     unsigned rule, unsigned *ties, tt_kd_best *best,
                                     uint32_t *end, tt_ray_stats *stats)
{
    uint32_t node = T->aug[start].node, last = start;
    float tentry = ta, texit = tb, tup = tb;
    int inclusive = 1;
    for (;;) {
        tt_kd_node leaf = TT_VARIANT(tt_kd_descend)(T, r, &node, tentry, &texit, inclusive, rule,
                                                    ties, &last, &tup, stats);
        if (TT_VARIANT(tt_kd_leaf)(T, leaf, r, any, best, stats)) {
            *end = last;
            return 1;
        }
        if (best->t <= texit) {
            if (best->prim != TT_INVALID_ID) *end = last;
            return 0;
        }
        if (!(texit < root_tb)) return 0; /* left the scene */
        tentry = texit;
        inclusive = 0;
        node = 0;
        last = 0;
        texit = root_tb;
    }
}

/* The passes over tied sides (see above), for SLTR (seq == 0) or SEQ. */
TT_HD int TT_VARIANT(tt_kd_stackless)(const tt_kd_view *T, const tt_wray *r, int any, int seq,
                                      uint32_t hint, tt_kd_best *best, uint32_t *end,
                                      tt_ray_stats *stats)
{
    float ta, tb;
    unsigned tests = 1;
    (void)stats;
    if (!tt_kd_root_interval(T, r, &ta, &tb)) {
        TT_COUNT(stats, boxes, tests);
        return 0;
    }
    const float root_tb = tb;
    const uint32_t start = tt_kd_start_node(T, r, hint, &ta, &tb, &tests);
    TT_COUNT(stats, boxes, tests);
    unsigned ties = 0, done = 0, rule = 0;
    for (;;) {
        done |= 1u << rule;
        int hit = seq ? TT_VARIANT(tt_kd_seq_pass)(T, r, any, start, ta, tb, root_tb, rule, &ties,
                                                   best, end, stats)
                      : TT_VARIANT(tt_kd_sltr_pass)(T, r, any, start, ta, tb, TT_KD_NO_PARENT,
                                                    rule, &ties, best, end, stats);
        if (hit) return 1;
        /* The next combination of sides over the tied axes seen so far. */
        unsigned m = 0;
        while (m < 8 && ((m & ~ties) != 0 || ((done >> m) & 1u))) m++;
        if (m == 8) return 0;
        rule = m;
    }
}
