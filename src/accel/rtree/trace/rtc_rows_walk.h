/* The rows form of a compact-layout traversal with the walk inlined into
 * the loop (the AVX2 / AVX-512 units): the walk specialised once a call
 * for the tree's S and closest hit / occlusion, where the single-ray entry
 * (whose prologue saves registers and aligns a frame of ~7 KB) switched a
 * ray. The including unit defines
 *   RTC_ROWS_NAME     the function's name (tt_rtc_rows_fn's signature);
 *   RTC_ROWS_WALK     its walk: int walk(t, S, any, r, hit, stats), always
 *                     inlined (rtc_stack_m, wbvh_trace_m);
 *   RTC_ROWS_SCALAR   the scalar unit's entry, for the rays the unit's
 *                     entry sends there (RTC_BOX_NEEDS_SCALAR, rtc_box_x86.h).
 * The same answers as the entry point's, ray by ray. */
#include "accel/rtree/trace/rtc_rows.h"

#define RTC_ROWS_M RTC_CAT(RTC_ROWS_NAME, _m)

TT_RT_INLINE void RTC_ROWS_M(const tt_rtc *t, const uint32_t S, const int any,
                             const tt_packet_rays *rays, tt_hit *hits, uint8_t *occ)
{
    const uint32_t n = rays->n;
    for (uint32_t g = 0; g < n; g += TT_WRAY_ROWS) {
        tt_wray w[TT_WRAY_ROWS];
        const uint32_t c = tt_wray_rows(rays, g, w);
        for (uint32_t l = 0; l < c; l++) {
            const tt_wray *r = &w[l];
            tt_hit *const hit = any ? NULL : &hits[g + l];
            int h;
#ifdef RTC_BOX_NEEDS_SCALAR
            if (RTC_BOX_NEEDS_SCALAR(r)) h = RTC_ROWS_SCALAR(t, r, any, hit, NULL);
            else
#endif
                h = RTC_ROWS_WALK(t, S, any, r, hit, NULL);
            if (any) occ[g + l] = (uint8_t)(h != 0);
        }
    }
}

__attribute__((flatten)) void RTC_ROWS_NAME(const tt_rtc *t, const tt_packet_rays *rays, int any,
                                            tt_hit *hits, uint8_t *occ)
{
    switch (t->S) {
    case 4:
        if (any) RTC_ROWS_M(t, 4, 1, rays, hits, occ);
        else RTC_ROWS_M(t, 4, 0, rays, hits, occ);
        return;
    case 8:
        if (any) RTC_ROWS_M(t, 8, 1, rays, hits, occ);
        else RTC_ROWS_M(t, 8, 0, rays, hits, occ);
        return;
    case 16:
        if (any) RTC_ROWS_M(t, 16, 1, rays, hits, occ);
        else RTC_ROWS_M(t, 16, 0, rays, hits, occ);
        return;
    default:
        if (any) RTC_ROWS_M(t, t->S, 1, rays, hits, occ);
        else RTC_ROWS_M(t, t->S, 0, rays, hits, occ);
        return;
    }
}

#undef RTC_ROWS_M
