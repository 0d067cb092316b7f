/* Near-to-far stack traversal of the compact layout (rtc_layout.h): a
 * template compiled once per ISA unit (rtc_trace_scalar.c, _sse42.c,
 * _avx2.c, _avx512.c) and once per statistics variant
 * (accel/stats_variant.h). The including unit defines
 *   RTC_FN(name)       the name with the unit's ISA suffix;
 *   rtc_lanes, rtc_lanes_init(lanes, ray), rtc_group_test(lanes, planes,
 *                      node, S, tmax, out) -> hit mask: all S child boxes
 *                      of a node in one step, out[i] the entry of a hit
 *                      child i (other lanes: anything);
 *   RTC_BLOCKS_INTERSECT(ray, blocks, n, hit), RTC_BLOCKS_OCCLUDED(ray,
 *                      blocks, n, tmax): the unit's triangle-block kernels.
 *
 * Closest hit: a node's hit children are sorted by entry distance; the
 * nearest is entered at once and the others pushed farthest first, so the
 * stack top is always the nearest waiting entry; a popped entry whose
 * entry distance is not below the closest hit found since is skipped. On
 * level 1 the children are leaves, tested in that near-to-far order
 * without touching the stack, stopping at the first one beyond the closest
 * hit. Occlusion takes the same near-to-far order and ends at the first
 * hit; its closest-hit bound stays the ray's tmax, which every entry that
 * passed a group test is below, so it keeps no entry distances and checks
 * none (one store a push, a load and branch a pop). Visiting children in
 * memory order instead was slower for shadow
 * rays on the bunny and Sibenik (a near occluder is found later), as the
 * complete layout's ordered traversal also measured. */
#include "accel/rtree/layout/rtc_layout.h"
#include "accel/rtree/trace/rtc_trace_leaf.h"

TT_RT_INLINE int TT_VARIANT(RTC_FN(rtc_stack_m))(const tt_rtc *TT_RESTRICT t, const uint32_t S,
                                                 const int any, const tt_wray *r, tt_hit *hit,
                                                 tt_ray_stats *stats)
{
    tt_hit h;
    h.t = r->tmax;
    h.u = h.v = 0.0f;
    h.prim = TT_INVALID_ID;
    uint32_t stack_node[TT_RTC_STACK_SIZE];
    float stack_t[TT_RTC_STACK_SIZE];
    uint8_t stack_l[TT_RTC_STACK_SIZE]; /* levels travel with the entries: */
    uint32_t sp = 0;                    /* no read of the record's header */
    rtc_lanes lanes;
    rtc_lanes_init(&lanes, r);
    tt_rt_planes planes; /* the ray's near/far bound rows, once per ray */
    tt_rt_planes_init(&planes, r, S);
    (void)stats;
    TT_COUNT(stats, rays, 1);
    uint32_t n = 0, level = t->height;
    for (;;) {
        /* Record n at n * tt_rtc_words(S): a power of two for S = 4, 8, 16
         * (32, 64, 128 words), so a shift instead of t->words' multiply on
         * the walk's chain of dependent loads. Every record array has that
         * size (rtc_pack, the in-place update, and the loader checks it). */
        const float *rec = t->node + (size_t)n * tt_rtc_words(S);
        const uint32_t *child = (const uint32_t *)(rec + 6 * S);
        float tb[TT_RT_MAX_M];
        uint32_t mask = rtc_group_test(&lanes, &planes, rec, S, h.t, tb);
        TT_COUNT(stats, nodes, 1);
        TT_COUNT(stats, interior, 1);
        TT_COUNT(stats, boxes, tt_rtc_count(t, rec));
        if (mask) {
            /* One or two hit children of an interior node, the common
             * cases, without the sort's loops (their exits are branches
             * the predictor misses when the count varies); the same order
             * as the sort below (equal distances keep lane order). */
            const uint32_t rest = mask & (mask - 1); /* the hits after the first */
            if (!rest) {
                if (level > 1) {
                    n = child[tt_rt_ctz(mask)];
                    level--;
                    continue;
                }
                /* the one hit leaf of a level-1 node (the commonest
                 * level-1 case): its entry is below h.t, the group test's
                 * bound; the record's lowest block as in the loop below */
                uint64_t done = 0;
                if (TT_VARIANT(RTC_FN(rtc_leaf))(t, child[tt_rt_ctz(mask)],
                                                 tt_rtc_leaf_block(child[0]), &done, any, r, &h,
                                                 stats))
                    return 1;
                goto pop;
            }
            if (!(rest & (rest - 1))) {
                const uint32_t i0 = tt_rt_ctz(mask), i1 = tt_rt_ctz(rest);
                const float t0 = tb[i0], t1 = tb[i1];
                const int swap = t1 < t0;
                if (level == 1) {
                    /* two hit leaves, the nearer first; the farther while
                     * still in front of the closest hit */
                    const uint32_t base = tt_rtc_leaf_block(child[0]);
                    uint64_t done = 0;
                    if (TT_VARIANT(RTC_FN(rtc_leaf))(t, child[swap ? i1 : i0], base, &done, any,
                                                     r, &h, stats))
                        return 1;
                    if ((any || (swap ? t0 : t1) < h.t) &&
                        TT_VARIANT(RTC_FN(rtc_leaf))(t, child[swap ? i0 : i1], base, &done, any,
                                                     r, &h, stats))
                        return 1;
                    goto pop;
                }
                stack_node[sp] = child[swap ? i0 : i1];
                stack_l[sp] = (uint8_t)(level - 1);
                if (!any) stack_t[sp] = swap ? t0 : t1;
                sp++;
                n = child[swap ? i1 : i0];
                level--;
                continue;
            }
            /* the hit children in ascending entry distance */
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
            if (level == 1) {
                /* the record's lowest leaf block is its first leaf's
                 * (rtc_trace_leaf.h: the tested-block set) */
                const uint32_t base = tt_rtc_leaf_block(child[0]);
                uint64_t done = 0;
                for (uint32_t j = 0; j < k && (any || ot[j] < h.t); j++)
                    if (TT_VARIANT(RTC_FN(rtc_leaf))(t, child[ord[j]], base, &done, any, r, &h,
                                                     stats))
                        return 1;
            } else {
                for (uint32_t j = k - 1; j > 0; j--) {
                    stack_node[sp] = child[ord[j]];
                    stack_l[sp] = (uint8_t)(level - 1);
                    if (!any) stack_t[sp] = ot[j];
                    sp++;
                }
                n = child[ord[0]];
                level--;
                continue;
            }
        }
    pop:
        /* the nearest waiting entry still in front of the closest hit */
        for (;;) {
            if (!sp) goto done;
            sp--;
            if (any || stack_t[sp] < h.t) {
                n = stack_node[sp];
                level = stack_l[sp];
                break;
            }
        }
    }
done:
    return tt_rtc_finish(any, &h, hit);
}

/* The entry point: specialised for S = 4, 8, 16 (the group test's loops
 * and offsets fold) and for closest hit / occlusion. Flattened, or GCC
 * keeps rtc_group_test out of line with S a run-time argument (perf on
 * Sibenik: 31% of the time in that call; wbvh/wbvh_trace.h). */
__attribute__((flatten)) int TT_VARIANT(RTC_FN(tt_rtc_stack))(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,
                                     tt_ray_stats *stats)
{
#ifdef RTC_BOX_NEEDS_SCALAR
    if (RTC_BOX_NEEDS_SCALAR(r)) return TT_VARIANT(tt_rtc_stack_scalar)(t, r, any, hit, stats);
#endif
    switch (t->S) {
    case 4:
        return any ? TT_VARIANT(RTC_FN(rtc_stack_m))(t, 4, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(rtc_stack_m))(t, 4, 0, r, hit, stats);
    case 8:
        return any ? TT_VARIANT(RTC_FN(rtc_stack_m))(t, 8, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(rtc_stack_m))(t, 8, 0, r, hit, stats);
    case 16:
        return any ? TT_VARIANT(RTC_FN(rtc_stack_m))(t, 16, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(rtc_stack_m))(t, 16, 0, r, hit, stats);
    default:
        return any ? TT_VARIANT(RTC_FN(rtc_stack_m))(t, t->S, 1, r, hit, stats)
                   : TT_VARIANT(RTC_FN(rtc_stack_m))(t, t->S, 0, r, hit, stats);
    }
}
