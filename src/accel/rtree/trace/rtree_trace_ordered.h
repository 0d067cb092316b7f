/* Ordered traversal (Feldmann 2015, Listing 2), a template compiled once per
 * statistics variant and shared with the CUDA backend. One small stack per
 * level l holds the hit children of the node being expanded on l, sorted by
 * entry distance with insertion sort (nearest on top); the walk takes the
 * nearest child, and climbs a level when that level's stack runs dry. Stack
 * l lives at entries l*M .. l*M + M - 1 of one fixed array ((L+1) * M <=
 * TT_RT_STACK_SIZE, checked when packing). An entry farther than the
 * closest hit found since it was pushed is dropped when popped. A bit mask
 * of the non-empty levels finds the next stack without scanning. Occlusion
 * queries (`any`) keep the sorting: taking the children in memory order
 * instead cost about 10% more instructions per shadow ray on the bunny
 * (later occluder found). */
#include "accel/rtree/trace/rtree_trace_leaf.h"

TT_RT_INLINE int TT_VARIANT(tt_rt_ordered_m)(const tt_rtree_packed *TT_RESTRICT t, const uint32_t Mc,
        const tt_wray *r, int any, tt_hit *hit, tt_ray_stats *stats)
{
    const uint32_t M = Mc, L = t->L; /* M == t->M, a constant when specialised */
    float best = r->tmax, bu = 0.0f, bv = 0.0f;
    uint32_t found = TT_INVALID_ID;
    uint32_t stack_node[TT_RT_STACK_SIZE];
    float stack_t[TT_RT_STACK_SIZE];
    uint32_t sp[TT_RT_MAX_LEVELS + 1];
    uint32_t levels = 0; /* bit l set: stack l is not empty */
    tt_rt_lanes lanes;
    tt_rt_lanes_init(&lanes, r);
    tt_rt_planes planes; /* the ray's near/far bound arrays, once per ray */
    tt_rt_planes_init(&planes, r, M);
    (void)stats;
    TT_COUNT(stats, rays, 1);

    uint32_t pos, n = 0, l = L;
    const float *g = tt_rt_group(t, 0, &pos);
    if (TT_LDG(g + pos) == TT_INF) goto done; /* empty tree */
    TT_COUNT(stats, boxes, 1);
    if (!(tt_rt_box_test_at(r, &planes, g + pos, best) < best)) goto done;
    for (;;) {
        TT_COUNT(stats, nodes, 1);
        if (l > 0) {
            TT_COUNT(stats, interior, 1);
            const uint32_t c0 = tt_rt_first_child_m(t, M, n, l);
            const float *cg = tt_rt_child_group_m(t, M, n, l);
            uint32_t *sn = stack_node + l * M;
            float *st = stack_t + l * M;
            uint32_t top = 0;
            TT_COUNT(stats, boxes, TT_LDG(t->count + n)); /* the node's entries */
            float tbox[TT_RT_MAX_M];
            /* a fixed loop over the M slots (unrolled for M = 4; empty
             * slots never hit): iterating the set bits of a hit mask
             * instead executes fewer instructions but mispredicts its
             * exit, and measured about 25% slower */
            tt_rt_group_test(&lanes, r, &planes, cg, M, best, tbox);
            for (uint32_t i = 0; i < M; i++) {
                const float tb = tbox[i];
                if (!(tb < best)) continue;
                /* insertion sort: farthest at the bottom */
                uint32_t j = top++;
                while (j > 0 && st[j - 1] < tb) {
                    st[j] = st[j - 1];
                    sn[j] = sn[j - 1];
                    j--;
                }
                st[j] = tb;
                sn[j] = c0 + i;
            }
            sp[l] = top;
            if (top) levels |= 1u << l;
        } else {
            if (TT_VARIANT(tt_rt_leaf)(t, n, r, any, &best, &bu, &bv, &found, stats)) return 1;
        }
        /* the nearest remaining entry, climbing past empty stacks: the
         * stacks below the level just expanded are all empty, so the next
         * entry is on the lowest level whose bit is set in `levels` */
        for (;;) {
            if (!levels) goto done;
            l = tt_rt_ctz(levels);
            const uint32_t k = --sp[l];
            if (k == 0) levels &= ~(1u << l);
            if (stack_t[l * M + k] < best) {
                n = stack_node[l * M + k];
                l--;
                break;
            }
        }
    }
done:
    return tt_rt_finish(t, any, found, best, bu, bv, hit);
}

/* The traversal, specialised for the default M = 4 (constant index
 * arithmetic and group tests) and generic for every other M. */
TT_HD int TT_VARIANT(tt_rt_ordered)(const tt_rtree_packed *TT_RESTRICT t, const tt_wray *r, int any,
                                tt_hit *hit, tt_ray_stats *stats)
{
    if (t->M == 4) return TT_VARIANT(tt_rt_ordered_m)(t, 4, r, any, hit, stats);
    return TT_VARIANT(tt_rt_ordered_m)(t, t->M, r, any, hit, stats);
}
