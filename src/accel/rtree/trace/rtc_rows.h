/* The rows form of a compact-layout traversal (tt_rtc_rows_fn, rtc.h):
 * RTC_DEFINE_ROWS(name, single) defines `name` over the unit's single-ray
 * entry `single` (the R-tree's units, the wide BVH's). The batch calls
 * used to reach the kernel a ray at a time through tt_wray_init and two
 * calls through pointers (the vtable's, the tree's); here the rays are
 * prepared eight at a time (accel/wray_rows.h) and `single` is a direct
 * call, with the same answers bit for bit. */
#ifndef TT_ACCEL_RTREE_TRACE_RTC_ROWS_H
#define TT_ACCEL_RTREE_TRACE_RTC_ROWS_H

#include "accel/rtree/rtc.h"
#include "accel/wray_rows.h"

#define RTC_DEFINE_ROWS(name, single)                                                            \
    void name(const tt_rtc *t, const tt_packet_rays *rays, int any, tt_hit *hits, uint8_t *occ)  \
    {                                                                                            \
        const uint32_t n = rays->n;                                                              \
        for (uint32_t g = 0; g < n; g += TT_WRAY_ROWS) {                                         \
            tt_wray w[TT_WRAY_ROWS];                                                             \
            const uint32_t c = tt_wray_rows(rays, g, w);                                         \
            if (any)                                                                             \
                for (uint32_t l = 0; l < c; l++)                                                 \
                    occ[g + l] = (uint8_t)(single(t, &w[l], 1, NULL, NULL) != 0);                \
            else                                                                                 \
                for (uint32_t l = 0; l < c; l++) single(t, &w[l], 0, &hits[g + l], NULL);        \
        }                                                                                        \
    }

#endif
