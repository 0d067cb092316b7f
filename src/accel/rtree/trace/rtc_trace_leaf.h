/* One leaf of a compact record (rtc_layout.h), tested block by block: the
 * part of a near-to-far walk the R-tree's kernel (rtc_trace_stack.h) and the
 * wide BVH's (wbvh/wbvh_trace.h) share. A template like them, included by
 * each after stats_variant.h (so no include guard), with the unit's RTC_FN
 * and RTC_BLOCKS_INTERSECT / RTC_BLOCKS_OCCLUDED.
 *
 * Leaves share blocks, so a record's walk keeps the set of blocks it has
 * tested (*done, bit i: block base + i, base the record's lowest leaf
 * block, every other within 2 M of it): a block already tested is not
 * tested again, which is exact, since that test saw all of its triangles
 * below a larger (or the same) closest hit. Returns 1 when `any` and a
 * block occludes the ray below h->t (the walk ends), else 0 with h updated. */
TT_RT_INLINE int TT_VARIANT(RTC_FN(rtc_leaf))(const tt_rtc *TT_RESTRICT t, uint32_t ref,
                                              uint32_t base, uint64_t *done, int any,
                                              const tt_wray *r, tt_hit *h, tt_ray_stats *stats)
{
    uint32_t nb;
    const tt_tri_block *b = tt_rtc_leaf_blocks(t, ref, &nb);
    const uint32_t off = tt_rtc_leaf_block(ref) - base;
    (void)stats;
    TT_COUNT(stats, nodes, 1);
    TT_COUNT(stats, leaves, 1);
    for (uint32_t q = 0; q < nb; q++) {
        const uint64_t bit = (uint64_t)1 << (off + q);
        if (*done & bit) continue;
        *done |= bit;
        TT_COUNT(stats, triangles, TT_TRI_BLOCK_W);
        if (any) {
            if (RTC_BLOCKS_OCCLUDED(r, b + q, 1, h->t)) return 1;
        } else {
            RTC_BLOCKS_INTERSECT(r, b + q, 1, h);
        }
    }
    return 0;
}
