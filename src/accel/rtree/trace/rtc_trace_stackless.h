/* Stackless traversal of the compact layout (rtc_layout.h), a template
 * compiled once per statistics variant (accel/stats_variant.h), scalar and
 * TT_HD so the GPU can run it. Feldmann's Listing 1 walks the complete tree
 * by index arithmetic; here the same walk uses the stored links: at node n
 * the children are tested in memory order from position i; a hit node child is entered at
 * position 0, a hit leaf tested; when n's entries are exhausted the walk
 * climbs to the parent and resumes after n's position there (n minus the
 * parent's first child: siblings are consecutive). The
 * state is (n, i) and the running closest hit, nothing else. */
#include "accel/rtree/layout/rtc_layout.h"

TT_HD int TT_VARIANT(tt_rtc_stackless)(const tt_rtc *TT_RESTRICT t, const tt_wray *r, int any,
                                       tt_hit *hit, tt_ray_stats *stats)
{
    tt_hit h;
    h.t = r->tmax;
    h.u = h.v = 0.0f;
    h.prim = TT_INVALID_ID;
    tt_rt_planes planes;
    tt_rt_planes_init(&planes, r, t->S);
    (void)stats;
    TT_COUNT(stats, rays, 1);
    uint32_t n = 0, i = 0;
    const float *rec = tt_rtc_node(t, 0);
    TT_COUNT(stats, nodes, 1);
    TT_COUNT(stats, interior, 1);
    for (;;) {
        const uint32_t cnt = tt_rtc_count(t, rec);
        const uint32_t *child = tt_rtc_child(t, rec);
        int down = 0;
        for (; i < cnt; i++) {
            TT_COUNT(stats, boxes, 1);
            if (!(tt_rt_box_test_at(r, &planes, rec + i, h.t) < h.t)) continue;
            const uint32_t ref = TT_LDG(child + i);
            TT_COUNT(stats, nodes, 1);
            if (tt_rtc_is_leaf(ref)) {
                uint32_t nb;
                const tt_tri_block *b = tt_rtc_leaf_blocks(t, ref, &nb);
                TT_COUNT(stats, leaves, 1);
                TT_COUNT(stats, triangles, nb * TT_TRI_BLOCK_W);
                if (any) {
                    if (tt_tri_blocks_occluded_scalar(r, b, nb, h.t)) return 1;
                } else {
                    tt_tri_blocks_intersect_scalar(r, b, nb, &h);
                }
                continue;
            }
            TT_COUNT(stats, interior, 1);
            n = ref;
            rec = tt_rtc_node(t, n);
            i = 0;
            down = 1;
            break;
        }
        if (down) continue;
        /* n is done: resume in the parent after n's position */
        const uint32_t p = tt_rtc_parent(t, rec);
        if (p == TT_INVALID_ID) break;
        rec = tt_rtc_node(t, p);
        i = n - TT_LDG(tt_rtc_child(t, rec)) + 1;
        n = p;
    }
    return tt_rtc_finish(any, &h, hit);
}
