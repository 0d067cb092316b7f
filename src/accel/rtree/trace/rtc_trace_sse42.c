/* The compact layout's stack traversal with the child boxes tested by
 * SSE4.2 instructions (rtc_box_x86.h; this unit is compiled with that ISA's
 * flags and runs only where tt_isa_supported says so). */
#include "accel/rtree/rtc.h"
#include "accel/rtree/trace/rtc_box_x86.h"
#include "geometry/tri_block_sse42.h"

#define RTC_ISA _sse42

/* The triangle blocks: the ISA's own kernels (bit-identical to the scalar
 * ones). */
#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_sse42
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_sse42

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_trace_stack.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_trace_stack.h"

/* The rows form (the batch calls' single rays). */
#include "accel/rtree/trace/rtc_rows.h"
RTC_DEFINE_ROWS(tt_rtc_stack_sse42_rows, tt_rtc_stack_sse42)
