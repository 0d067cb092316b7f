/* The compact layout's traversals in portable C (TT_ISA_SCALAR): the stack
 * traversal with one box test per child, and the stackless traversal (the
 * code the GPU shares; it has no SIMD form). */
#include "accel/rtree/rtc.h"

#define RTC_ISA _scalar

#include "accel/rtree/trace/rtc_box_scalar.h"

#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_scalar
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_scalar

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_trace_stack.h"
#include "accel/rtree/trace/rtc_trace_stackless.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_trace_stack.h"
#include "accel/rtree/trace/rtc_trace_stackless.h"

/* The stackless template is TT_HD (static): these give it external names. */
int tt_rtc_stackless_scalar(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,
                            tt_ray_stats *stats)
{
    return tt_rtc_stackless(t, r, any, hit, stats);
}
int tt_rtc_stackless_scalar_stats(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,
                                  tt_ray_stats *stats)
{
    return tt_rtc_stackless_stats(t, r, any, hit, stats);
}

/* The rows forms (the batch calls' single rays). */
#include "accel/rtree/trace/rtc_rows.h"
RTC_DEFINE_ROWS(tt_rtc_stack_scalar_rows, tt_rtc_stack_scalar)
RTC_DEFINE_ROWS(tt_rtc_stackless_scalar_rows, tt_rtc_stackless_scalar)
