/* The slab test of a compact node's child boxes in portable C, one box at
 * a time (tt_rt_box_test_at), in the form the stack traversal templates
 * take (rtc_trace_stack.h, wbvh/wbvh_trace.h): for the scalar units. */
#ifndef TT_ACCEL_RTREE_RTC_BOX_SCALAR_H
#define TT_ACCEL_RTREE_RTC_BOX_SCALAR_H

#include "accel/rtree/layout/rtc_layout.h"

typedef struct rtc_lanes {
    const tt_wray *r;
} rtc_lanes;

static inline void rtc_lanes_init(rtc_lanes *s, const tt_wray *r) { s->r = r; }

static inline uint32_t rtc_group_test(const rtc_lanes *s, const tt_rt_planes *p, const float *rec,
                                      uint32_t S, float tmax, float *out)
{
    uint32_t mask = 0;
    for (uint32_t i = 0; i < S; i++) {
        out[i] = tt_rt_box_test_at(s->r, p, rec + i, tmax);
        mask |= (uint32_t)(out[i] < tmax) << i;
    }
    return mask;
}

#endif
