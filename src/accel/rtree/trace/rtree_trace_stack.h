/* Conventional stack-based traversal (the paper's "stack" baseline of Table
 * 3), a template compiled once per statistics variant and shared with the
 * CUDA backend: one stack of (slot, level, entry distance); a node's hit
 * children are pushed in reverse memory order (so they are visited in
 * memory order, like a recursive descent, without sorting), and an entry
 * farther than the closest hit found since it was pushed is dropped when
 * popped. At most M - 1 entries per level wait while a node's children are
 * pushed, so (L + 1) * M <= TT_RT_STACK_SIZE entries suffice. */
#include "accel/rtree/trace/rtree_trace_leaf.h"

TT_RT_INLINE int TT_VARIANT(tt_rt_stack_m)(const tt_rtree_packed *TT_RESTRICT t, const uint32_t Mc,
        const tt_wray *r, int any, tt_hit *hit, tt_ray_stats *stats)
{
    const uint32_t M = Mc, L = t->L; /* M == t->M, a constant when specialised */
    float best = r->tmax, bu = 0.0f, bv = 0.0f;
    uint32_t found = TT_INVALID_ID;
    uint32_t stack_node[TT_RT_STACK_SIZE];
    float stack_t[TT_RT_STACK_SIZE];
    uint8_t stack_l[TT_RT_STACK_SIZE];
    uint32_t sp = 0;
    tt_rt_lanes lanes;
    tt_rt_lanes_init(&lanes, r);
    tt_rt_planes planes; /* the ray's near/far bound arrays, once per ray */
    tt_rt_planes_init(&planes, r, M);
    (void)stats;
    TT_COUNT(stats, rays, 1);

    uint32_t pos;
    const float *g = tt_rt_group(t, 0, &pos);
    if (TT_LDG(g + pos) == TT_INF) goto done; /* empty tree */
    TT_COUNT(stats, boxes, 1);
    {
        const float tb = tt_rt_box_test_at(r, &planes, g + pos, best);
        if (!(tb < best)) goto done;
        stack_node[0] = 0;
        stack_t[0] = tb;
        stack_l[0] = (uint8_t)L;
        sp = 1;
    }
    while (sp > 0) {
        sp--;
        if (!(stack_t[sp] < best)) continue;
        const uint32_t n = stack_node[sp], l = stack_l[sp];
        TT_COUNT(stats, nodes, 1);
        if (l > 0) {
            TT_COUNT(stats, interior, 1);
            const uint32_t c0 = tt_rt_first_child_m(t, M, n, l);
            const float *cg = tt_rt_child_group_m(t, M, n, l);
            TT_COUNT(stats, boxes, TT_LDG(t->count + n)); /* the node's entries */
            float tbox[TT_RT_MAX_M];
            /* the hit children, pushed last in memory order first so that
             * the first is on top (empty slots never hit); a fixed loop
             * over the M slots, unrolled for M = 4: iterating the set bits
             * of a hit mask mispredicts its exit and measured about 25%
             * slower despite fewer instructions */
            tt_rt_group_test(&lanes, r, &planes, cg, M, best, tbox);
            for (uint32_t i = M; i-- > 0;) {
                if (!(tbox[i] < best)) continue;
                stack_node[sp] = c0 + i;
                stack_t[sp] = tbox[i];
                stack_l[sp] = (uint8_t)(l - 1);
                sp++;
            }
        } else {
            if (TT_VARIANT(tt_rt_leaf)(t, n, r, any, &best, &bu, &bv, &found, stats)) return 1;
        }
    }
done:
    return tt_rt_finish(t, any, found, best, bu, bv, hit);
}

/* The traversal, specialised for the default M = 4 (constant index
 * arithmetic and group tests) and generic for every other M. */
TT_HD int TT_VARIANT(tt_rt_stack)(const tt_rtree_packed *TT_RESTRICT t, const tt_wray *r, int any,
                                tt_hit *hit, tt_ray_stats *stats)
{
    if (t->M == 4) return TT_VARIANT(tt_rt_stack_m)(t, 4, r, any, hit, stats);
    return TT_VARIANT(tt_rt_stack_m)(t, t->M, r, any, hit, stats);
}
