/* Near-to-far stack traversal of the wide BVH's mixed records (wbvh.h): a
 * template compiled per ISA unit (wbvh_trace_scalar.c, _sse42.c, _avx2.c,
 * _avx512.c) and per statistics variant (accel/stats_variant.h), with the
 * same unit interface as the R-tree's rtc_trace_stack.h (rtc_lanes,
 * rtc_group_test, RTC_BLOCKS_INTERSECT / _OCCLUDED, RTC_FN).
 *
 * A record's hit entries are sorted by entry distance and taken in that
 * order: a leaf is tested at once, unless its entry is not below the
 * closest hit found so far (then neither is anything after it); the nodes
 * are collected, pushed farthest first, and the nearest is entered. Leaves
 * before nodes in near-to-far order is the point: a near leaf's hit culls
 * the farther nodes before they are pushed. Occlusion ends at the first
 * hit. The leaves of a record share blocks (first fit, wbvh.h): a block
 * already tested for this record is skipped, exactly as in the R-tree's
 * kernel. Closest hits are the block kernels', so bit-identical to
 * bruteforce (geometry/tri_block.h; equal t: the smaller id). */
#include "accel/wbvh/wbvh.h"
#include "accel/rtree/trace/rtc_trace_leaf.h"

TT_RT_INLINE int TT_VARIANT(RTC_FN(wbvh_trace_m))(const tt_rtc *TT_RESTRICT t, const uint32_t S,
                                                  const int any, const tt_wray *r, tt_hit *hit,
                                                  tt_ray_stats *stats)
{
    tt_hit h;
    h.t = r->tmax;
    h.u = h.v = 0.0f;
    h.prim = TT_INVALID_ID;
    uint32_t stack_node[TT_WBVH_STACK_SIZE];
    float stack_t[TT_WBVH_STACK_SIZE];
    uint32_t sp = 0;
    rtc_lanes lanes;
    rtc_lanes_init(&lanes, r);
    tt_rt_planes planes;
    tt_rt_planes_init(&planes, r, S);
    (void)stats;
    TT_COUNT(stats, rays, 1);
    uint32_t n = 0;
    for (;;) {
        const float *rec = tt_rtc_node(t, n);
        const uint32_t *child = tt_rtc_child(t, rec);
        float tb[TT_RT_MAX_M];
        uint32_t mask = rtc_group_test(&lanes, &planes, rec, S, h.t, tb);
        TT_COUNT(stats, nodes, 1);
        TT_COUNT(stats, interior, 1);
        TT_COUNT(stats, boxes, tt_rtc_count(t, rec));
        if (mask) {
            uint32_t ord[TT_RT_MAX_M];
            float ot[TT_RT_MAX_M];
            uint32_t k = 0;
            while (mask) {
                const uint32_t i = tt_rt_ctz(mask);
                mask &= mask - 1;
                const float ti = tb[i];
                uint32_t j = k++;
                while (j > 0 && ot[j - 1] > ti) {
                    ot[j] = ot[j - 1];
                    ord[j] = ord[j - 1];
                    j--;
                }
                ot[j] = ti;
                ord[j] = i;
            }
            /* the first entry is a leaf when the record has any: its block
             * is the lowest of the record's leaves */
            const uint32_t base = tt_rtc_leaf_block(child[0]);
            uint64_t done = 0;
            uint32_t near_node[TT_RT_MAX_M];
            float near_t[TT_RT_MAX_M];
            uint32_t nn = 0;
            for (uint32_t j = 0; j < k && ot[j] < h.t; j++) {
                const uint32_t ref = child[ord[j]];
                if (!tt_rtc_is_leaf(ref)) {
                    near_node[nn] = ref;
                    near_t[nn++] = ot[j];
                    continue;
                }
                if (TT_VARIANT(RTC_FN(rtc_leaf))(t, ref, base, &done, any, r, &h, stats))
                    return 1;
            }
            /* the nodes still in front of the closest hit: farther ones
             * wait, the nearest is entered */
            while (nn > 0 && near_t[nn - 1] >= h.t) nn--;
            if (nn > 0) {
                for (uint32_t j = nn - 1; j > 0; j--) {
                    stack_node[sp] = near_node[j];
                    stack_t[sp++] = near_t[j];
                }
                n = near_node[0];
                continue;
            }
        }
        for (;;) {
            if (!sp) goto done;
            sp--;
            if (stack_t[sp] < h.t) {
                n = stack_node[sp];
                break;
            }
        }
    }
done:
    return tt_rtc_finish(any, &h, hit);
}

/* The entry point: specialised for S = 4, 8, 16 and for closest hit /
 * occlusion, as the R-tree's. Flattened: GCC otherwise keeps the unit's
 * rtc_group_test out of line, one copy for every S, so its loops over S
 * stay loops and every node visit pays a call (perf on Sibenik: a quarter
 * of the time inside it). */
__attribute__((flatten)) int TT_VARIANT(RTC_FN(tt_wbvh_trace))(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,
                                      tt_ray_stats *stats)
{
#ifdef RTC_BOX_NEEDS_SCALAR /* (rtc_box_x86.h: rays no FMA unit can cull) */
    if (RTC_BOX_NEEDS_SCALAR(r)) return TT_VARIANT(tt_wbvh_trace_scalar)(t, r, any, hit, stats);
#endif
    switch (t->S) {
    case 4:
        return any ? TT_VARIANT(RTC_FN(wbvh_trace_m))(t, 4, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(wbvh_trace_m))(t, 4, 0, r, hit, stats);
    case 8:
        return any ? TT_VARIANT(RTC_FN(wbvh_trace_m))(t, 8, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(wbvh_trace_m))(t, 8, 0, r, hit, stats);
    case 16:
        return any ? TT_VARIANT(RTC_FN(wbvh_trace_m))(t, 16, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(wbvh_trace_m))(t, 16, 0, r, hit, stats);
    default:
        return any ? TT_VARIANT(RTC_FN(wbvh_trace_m))(t, t->S, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(wbvh_trace_m))(t, t->S, 0, r, hit, stats);
    }
}
