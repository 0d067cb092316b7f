/* HTR over the engine's cache-line node layout (kd_lines.h), for the fast
 * kernels of kd_trace_avx2.c / kd_trace_avx512.c: include after
 * kd_leaf_block.h, only from those units.
 *
 * The same walk as kd_trace_htr.h's tt_kd_htr_moving, decision for
 * decision (the same planes, the same per-axis rounding band, the same near
 * child first, the same stack order and cut at the closest hit), so the same
 * leaves are tested in the same order and the answers are bit for bit
 * those of the depth-first nodes; only where the nodes lie differs. For
 * rays that move along every axis; the others take tt_kd_htr_general. A
 * stack entry names a position: line << 4 | h. */

/* A small leaf's 4-lane block (kd_lines.h). */
static inline const tt_kd_block4 *kd_lines_small(const tt_kd_view *T, uint32_t x)
{
    return (const tt_kd_block4 *)((const char *)T->lines + ((size_t)(x & TT_KD_LINE_INDEX) << 5));
}

static inline int kd_lines_leaf(const tt_kd_view *T, uint32_t x, const tt_wray *r, int any,
                                tt_kd_best *best)
{
    tt_kd_node leaf;
    const uint32_t n = (x >> 27) & 15u;
    if (n == TT_KD_LINE_SMALL)
        return kd_leaf_block4(T, kd_lines_small(T, x), r, any, best);
    if (n) {
        leaf.u.first = x & TT_KD_LINE_INDEX;
        leaf.bits = (n * TT_TRI_BLOCK_W) << 3 | TT_KD_LEAF; /* n blocks' lanes */
    } else {
        leaf = T->nodes[x & TT_KD_LINE_INDEX];
    }
    return kd_leaf_block(T, leaf, r, any, best);
}

/* The any-hit leaf: the same blocks, kd_leaf_block_any's test. */
TT_TRI_KERNEL int kd_lines_leaf_any(const tt_kd_view *T, uint32_t x, const tt_wray *r,
                                    const kd_bray *q)
{
    const uint32_t n = (x >> 27) & 15u;
    if (n == TT_KD_LINE_SMALL) return kd_block4_any(T, kd_lines_small(T, x), r, q);
    if (n) return kd_leaf_block_any(T, x & TT_KD_LINE_INDEX, n, r, q);
    const tt_kd_node leaf = T->nodes[x & TT_KD_LINE_INDEX];
    return kd_leaf_block_any(T, leaf.u.first, tt_tri_block_count(tt_kd_leaf_count(leaf.bits)), r,
                             q);
}

/* Inlined into each entry point with `any` a constant: the occlusion copy
 * tests leaves with kd_leaf_block_any, its ray broadcasts made once. */
TT_TRI_KERNEL int kd_lines_htr(const tt_kd_view *T, const tt_wray *r, int any, tt_kd_best *best)
{
    kd_bray q;
    if (any) kd_bray_init(&q, r);
    tt_kd_htr_entry stack[TT_KD_STACK];
    float ta, tb, e[3];
    tt_kd_band band;
    tt_kd_band_init(&band, r);
    if (!tt_kd_root_interval(T, r, &band, &ta, &tb)) return 0;
    tb = tt_kd_min(tb, r->tmax);
    for (int k = 0; k < 3; k++) {
        const float m = tt_kd_max(fabsf(T->aug[0].lo[k]), fabsf(T->aug[0].hi[k]));
        e[k] = m * band.bi[k] + band.bo[k];
    }
    /* Branches, not arithmetic, pick the next position (as in
     * tt_kd_htr_moving): a predicted branch hands the next level its
     * position at once, where computing it from the ray's direction put
     * a compare (or a load of dir[k]) on the chain from level to level:
     * 10-30% slower than the depth-first walk. Hence the two copies of
     * the plane test, one per direction along the axis. */
    const uint32_t oct = (uint32_t)(r->dir[0] < 0.0f) | (uint32_t)(r->dir[1] < 0.0f) << 1 |
                         (uint32_t)(r->dir[2] < 0.0f) << 2;
    int sp = 0;
    uint32_t line = 0, h = 0;
    for (;;) {
        uint32_t x;
        for (;;) {
            const tt_kd_line *L = T->lines + line;
            const uint32_t axes = L->axes;
            while (h < 7u) {
                const uint32_t k = (axes >> (2u * h)) & 3u;
                if (k == 3u) {
                    h = 2u * h + 1u;
                    continue;
                }
                const float ts = (L->split[h] - r->org[k]) * r->inv[k];
                const float lo = ts - e[k], hi = ts + e[k];
                const uint32_t left = 2u * h + 1u, right = 2u * h + 2u;
                if ((oct >> k) & 1u) {
                    if (hi < ta) {
                        h = left;
                    } else if (lo > tb) {
                        h = right;
                    } else {
                        stack[sp].node = line << 4 | left;
                        stack[sp].ta = tt_kd_max(ta, lo);
                        stack[sp].tb = tb;
                        sp++;
                        h = right;
                        tb = tt_kd_min(tb, hi);
                    }
                } else {
                    if (hi < ta) {
                        h = right;
                    } else if (lo > tb) {
                        h = left;
                    } else {
                        stack[sp].node = line << 4 | right;
                        stack[sp].ta = tt_kd_max(ta, lo);
                        stack[sp].tb = tb;
                        sp++;
                        h = left;
                        tb = tt_kd_min(tb, hi);
                    }
                }
            }
            x = L->exit[h - 7u];
            if (x & TT_KD_LINE_LEAF) break;
            line = x;
            h = 0;
        }
        if (x != TT_KD_LINE_EMPTY &&
            (any ? kd_lines_leaf_any(T, x, r, &q) : kd_lines_leaf(T, x, r, any, best)))
            return 1;
        uint32_t pos;
        if (!tt_kd_htr_pop(stack, &sp, best->t, &pos, &ta, &tb)) return 0;
        line = pos >> 4;
        h = pos & 15u;
    }
}

/* The entry points' HTR over the lines (include after kd_trace.h): 1 when
 * they took the ray (a view with lines, HTR, a ray moving along every
 * axis), with tt_kd_intersect's / tt_kd_occluded's results; 0 to leave it
 * to them. */
static inline int kd_lines_intersect(const tt_kd_view *T, int traversal, const tt_wray *r,
                                     tt_hit *hit, uint32_t *end)
{
    if (!T->lines || traversal != TT_KD_HTR || r->dir[0] == 0.0f || r->dir[1] == 0.0f ||
        r->dir[2] == 0.0f)
        return 0;
    tt_kd_best best;
    tt_kd_best_init(&best, r);
    *end = TT_INVALID_ID;
    kd_lines_htr(T, r, 0, &best);
    tt_kd_best_store(&best, hit);
    return 1;
}

static inline int kd_lines_occluded(const tt_kd_view *T, int traversal, const tt_wray *r,
                                    uint32_t caster, uint32_t *end, int *occluded)
{
    if (!T->lines || traversal != TT_KD_HTR || r->dir[0] == 0.0f || r->dir[1] == 0.0f ||
        r->dir[2] == 0.0f)
        return 0;
    tt_kd_best best;
    tt_kd_best_init(&best, r);
    *end = TT_INVALID_ID;
    if (caster != TT_INVALID_ID && tt_kd_probe(T, traversal, r, caster, &best, end, NULL)) {
        *occluded = 1;
        return 1;
    }
    *end = TT_INVALID_ID;
    *occluded = kd_lines_htr(T, r, 1, &best);
    return 1;
}
