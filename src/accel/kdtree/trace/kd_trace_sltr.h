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
 * than one pass.
 *
 * Near-exact ties (a ray aimed at a vertex or at a point where planes
 * cross) meet planes at distances that differ only by rounding, so the
 * computed path may skip a cell the triangle test sees the ray in. Each
 * point location therefore also counts the planes crossed within the
 * rounding band of its entry point, and notes whether the leaf's exit is
 * within the band of another of its planes (an edge). Where the entry
 * point is near a plane other than the one entered through, or the
 * previous leaf was left near an edge, the pass also visits the leaves
 * reached by every other choice at the near planes (tt_kd_around: bounded
 * re-descents from the same cached box, no stack; from the root if the
 * entry point lies within the band of a face of that box). The ray's last
 * exit point is searched around the same way, the scene box is entered
 * with the band, and a pass stops only at a hit clearly (by more than the
 * band) before the current exit. */

/* The searches around entry point *tentry of a descent from augmented node
 * `from` (see tt_kd_around): from the root if the entry point lies within
 * the band of a face of that box; else below `from` if a plane other than
 * the entry plane is crossed within the band there, or the previous leaf
 * was left near an edge (prev_edge; the cells around it behind the entry
 * plane are reached by flipping that plane's choice). */
TT_HD int TT_VARIANT(tt_kd_near_cells)(const tt_kd_view *T, const tt_wray *r, int any,
                                       const tt_kd_order *ord, uint32_t from,
                                       const tt_kd_key *tentry, const tt_kd_amb *amb,
                                       int prev_edge, tt_kd_budget *budget, tt_kd_best *best,
                                       tt_ray_stats *stats)
{
    if (from != 0 && tt_kd_near_faces(&T->aug[from], r, tentry)) {
        TT_COUNT(stats, boxes, 1);
        return TT_VARIANT(tt_kd_around)(T, r, any, ord, 0, tentry, 0, 0, budget, best, stats);
    }
    if (amb->other == 0 && !prev_edge) return 0;
    return TT_VARIANT(tt_kd_around)(T, r, any, ord, from, tentry, 1, amb->all, budget, best,
                                    stats);
}

/* Whether the leaf just left (exit *texit, descent from `from`) was left
 * near an edge: another plane on its path, or another face of the box
 * `from` when the exit is that box's, crossed within the band. */
TT_HD int TT_VARIANT(tt_kd_left_near_edge)(const tt_kd_view *T, const tt_wray *r, uint32_t from,
                                          const tt_kd_key *texit, const tt_kd_amb *amb)
{
    return amb->edge || (amb->box_exit && from != 0 &&
                         tt_kd_box_exit_near_edge(&T->aug[from], r, texit));
}

#ifndef TT_KD_DONE_BEFORE_DEFINED
#define TT_KD_DONE_BEFORE_DEFINED
/* Whether a pass with the closest hit so far at t must still go on past
 * exit: a hit before exit by more than the band cannot be beaten. */
TT_HD int tt_kd_done_before(float t, const tt_kd_key *exit)
{
    return t < exit->t - 2.0f * exit->err;
}
#endif

#ifndef TT_KD_STEP_DEFINED
#define TT_KD_STEP_DEFINED
enum { TT_KD_STEP_ON = 0, TT_KD_STEP_STOP = 1, TT_KD_STEP_DONE = 2 };
#endif

/* The step SLTR and SEQ share: locate the leaf the ray enters after
 * *tentry by a descent from *node (below augmented node `from`), test it
 * and the cells a near tie may hide around the entry point, and see
 * whether the closest hit so far is final. TT_KD_STEP_STOP: an any-hit, or
 * the budget ran out (the caller returns 1); TT_KD_STEP_DONE: the closest
 * hit lies clearly before the leaf's exit (the caller returns 0);
 * TT_KD_STEP_ON: go on from *texit, with *edge telling whether the leaf
 * was left near an edge. */
TT_HD int TT_VARIANT(tt_kd_stackless_step)(const tt_kd_view *T, const tt_wray *r, int any,
                                           const tt_kd_order *ord, uint32_t from, uint32_t *node,
                                           const tt_kd_key *tentry, tt_kd_key *texit,
                                           unsigned *ties, uint32_t *last, tt_kd_key *tup,
                                           int *edge, tt_kd_budget *budget, tt_kd_best *best,
                                           uint32_t *end, tt_ray_stats *stats)
{
    tt_kd_amb amb = {0u, 0u, 0, 0};
    if (!tt_kd_budget_take(budget, budget->main)) return TT_KD_STEP_STOP;
    tt_kd_node leaf = TT_VARIANT(tt_kd_descend)(T, r, ord, node, tentry, texit, ties, last, tup,
                                                &amb, stats);
    if (TT_VARIANT(tt_kd_leaf)(T, leaf, r, any, best, stats) ||
        TT_VARIANT(tt_kd_near_cells)(T, r, any, ord, from, tentry, &amb, *edge, budget, best,
                                     stats)) {
        *end = *last;
        return TT_KD_STEP_STOP;
    }
    /* The ray ends in this leaf's box (or, past the last leaf, on the
     * scene box right behind it). */
    if (best->prim != TT_INVALID_ID) *end = *last;
    if (tt_kd_done_before(best->t, texit)) return TT_KD_STEP_DONE;
    *edge = TT_VARIANT(tt_kd_left_near_edge)(T, r, from, texit, &amb);
    return TT_KD_STEP_ON;
}

/* One SLTR pass from augmented node `start`, entering at ta, climbing no
 * higher than `stop` (TT_KD_NO_PARENT: up to the root). 1 on an any-hit,
 * and when the budget is spent (budget->over: the pass is abandoned). */
TT_HD int TT_VARIANT(tt_kd_sltr_pass)(const tt_kd_view *T, const tt_wray *r, int any,
                                      const tt_kd_order *ord, uint32_t start, float ta,
                                      float ta_err, uint32_t stop, unsigned *ties,
                                      tt_kd_budget *budget, tt_kd_best *best, uint32_t *end,
                                      tt_ray_stats *stats)
{
    uint32_t last = start;
    tt_kd_key tup = tt_kd_box_exit_key(&T->aug[start], r, ord, ties);
    tt_kd_key tentry = {ta, -1, -TT_INF, ta_err};
    int edge = 0;
    for (;;) {
        uint32_t node = T->aug[last].node;
        tt_kd_key texit = tup;
        const int step = TT_VARIANT(tt_kd_stackless_step)(T, r, any, ord, last, &node, &tentry,
                                                          &texit, ties, &last, &tup, &edge, budget,
                                                          best, end, stats);
        if (step != TT_KD_STEP_ON) return step == TT_KD_STEP_STOP;
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
        if (!found) /* left the scene (or the box `stop`): search around the exit */
            return stop == TT_KD_NO_PARENT && edge &&
                   TT_VARIANT(tt_kd_around)(T, r, any, ord, 0, &tentry, 0, 0, budget, best, stats);
    }
}

/* One SEQ pass: the first descent from `start`, every later one from the
 * root. Returns as tt_kd_sltr_pass. */
TT_HD int TT_VARIANT(tt_kd_seq_pass)(const tt_kd_view *T, const tt_wray *r, int any,
                                     const tt_kd_order *ord, uint32_t start, float ta,
                                     float ta_err, unsigned *ties, tt_kd_budget *budget,
                                     tt_kd_best *best, uint32_t *end, tt_ray_stats *stats)
{
    const tt_kd_key root_exit = tt_kd_box_exit_key(&T->aug[0], r, ord, ties);
    uint32_t node = T->aug[start].node, last = start;
    tt_kd_key tentry = {ta, -1, -TT_INF, ta_err};
    tt_kd_key texit = tt_kd_box_exit_key(&T->aug[start], r, ord, ties), tup = texit;
    uint32_t from = start;
    int edge = 0;
    for (;;) {
        const int step = TT_VARIANT(tt_kd_stackless_step)(T, r, any, ord, from, &node, &tentry,
                                                          &texit, ties, &last, &tup, &edge, budget,
                                                          best, end, stats);
        if (step != TT_KD_STEP_ON) return step == TT_KD_STEP_STOP;
        if (!tt_kd_key_after(&root_exit, &texit, ties)) /* left the scene: search around the exit */
            return edge &&
                   TT_VARIANT(tt_kd_around)(T, r, any, ord, 0, &texit, 0, 0, budget, best, stats);
        from = 0;
        tentry = texit;
        node = 0;
        last = 0;
        texit = root_exit;
    }
}

#ifndef TT_KD_GAVE_UP
/* tt_kd_stackless_passes' answer when it gave up on the ray. */
#define TT_KD_GAVE_UP 2
#endif

/* The passes (see above), for SLTR (seq == 0) or SEQ, with a near-tie
 * search of at most `spare` descents: 1 on an any-hit, TT_KD_GAVE_UP when
 * the search would exceed it (*best then holds true hits found so far, or
 * none), else 0. */
TT_HD int TT_VARIANT(tt_kd_stackless_passes)(const tt_kd_view *T, const tt_wray *r, int any,
                                             int seq, uint32_t hint, unsigned spare,
                                             tt_kd_best *best, uint32_t *end, tt_ray_stats *stats)
{
    float ta, tb;
    unsigned tests = 1;
    tt_kd_band band;
    (void)stats;
    tt_kd_band_init(&band, r);
    /* The scene box is entered with the band, so a ray grazing its edge is
     * not lost to rounding; the entry point is then uncertain by the
     * widest face band. */
    if (!tt_kd_root_interval(T, r, &band, &ta, &tb)) {
        TT_COUNT(stats, boxes, tests);
        return 0;
    }

    const uint32_t start = tt_kd_start_node(T, r, hint, &ta, &tb, &tests);
    TT_COUNT(stats, boxes, tests);
    /* A start in a hinted box is at the origin itself, exact. */
    float ta_err = 0.0f;
    for (int k = 0; start == 0 && k < 3; k++) {
        if (r->dir[k] == 0.0f) continue;
        ta_err = tt_kd_max(ta_err, tt_kd_cross_err(r, k, tt_kd_max(fabsf(T->aug[0].lo[k]),
                                                                   fabsf(T->aug[0].hi[k]))));
    }
    ta_err *= 2.0f;
    unsigned ties = 0, pass = 0;
    uint64_t done = 0;
    tt_kd_budget budget = {spare, 0u, 0};
    for (;;) {
        tt_kd_order ord;
        tt_kd_order_init(&ord, pass);
        done |= (uint64_t)1 << pass;
        budget.main = pass != 0; /* the first pass's own path is free */
        int hit = seq ? TT_VARIANT(tt_kd_seq_pass)(T, r, any, &ord, start, ta, ta_err, &ties,
                                                   &budget, best, end, stats)
                      : TT_VARIANT(tt_kd_sltr_pass)(T, r, any, &ord, start, ta, ta_err,
                                                    TT_KD_NO_PARENT, &ties, &budget, best, end,
                                                    stats);
        if (budget.over) return TT_KD_GAVE_UP;
        if (hit) return 1;
        if (ties == 0) return 0; /* no tie: the first pass was the only one */
        /* The next untried pass over the ties seen so far. */
        const unsigned perms = (ties & TT_KD_CORNER_TIE) ? 6u : 1u;
        for (pass = 0; pass < 8u * perms; pass++)
            if ((pass & 7u & ~ties) == 0 && !((done >> pass) & 1u)) break;
        if (pass == 8u * perms) return 0;
    }
}

/* SLTR or SEQ with a near-tie search of at most `spare` descents. A ray
 * whose search gives up (*gave_up) is finished by BTR, which needs no
 * search: it visits every cell whose interval, widened by the rounding band
 * at each plane, touches the ray's, and tests leaves on the ray's whole
 * [tmin, best), so rounding in its choices costs time, never a hit. The
 * hits the passes found are true hits and stay in *best (BTR only narrows
 * it). Its stack is bounded by the tree depth. */
TT_HD int TT_VARIANT(tt_kd_stackless_within)(const tt_kd_view *T, const tt_wray *r, int any,
                                             int seq, uint32_t hint, unsigned spare,
                                             tt_kd_best *best, uint32_t *end, int *gave_up,
                                             tt_ray_stats *stats)
{
    const int s = TT_VARIANT(tt_kd_stackless_passes)(T, r, any, seq, hint, spare, best, end,
                                                     stats);
    *gave_up = s == TT_KD_GAVE_UP;
    if (!*gave_up) return s;
    *end = TT_INVALID_ID;
    return TT_VARIANT(tt_kd_btr)(T, r, any, hint, best, end, stats);
}

TT_HD int TT_VARIANT(tt_kd_stackless)(const tt_kd_view *T, const tt_wray *r, int any, int seq,
                                      uint32_t hint, tt_kd_best *best, uint32_t *end,
                                      tt_ray_stats *stats)
{
    int gave_up;
    return TT_VARIANT(tt_kd_stackless_within)(T, r, any, seq, hint, TT_KD_SPARE, best, end,
                                              &gave_up, stats);
}
