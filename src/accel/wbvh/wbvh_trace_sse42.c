/* The wide BVH's traversal with the child boxes tested by SSE42
 * instructions (rtree/trace/rtc_box_x86.h; compiled with that ISA's flags,
 * run only where tt_isa_supported says so). */
#include "accel/wbvh/wbvh.h"
#include "accel/rtree/trace/rtc_box_x86.h"
#include "geometry/tri_block_sse42.h"

#define RTC_ISA _sse42

#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_sse42
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_sse42

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/wbvh/wbvh_trace.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/wbvh/wbvh_trace.h"

/* The rows form (the batch calls' single rays). */
#include "accel/rtree/trace/rtc_rows.h"
RTC_DEFINE_ROWS(tt_wbvh_trace_sse42_rows, tt_wbvh_trace_sse42)
