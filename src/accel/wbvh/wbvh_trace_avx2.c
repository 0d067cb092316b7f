/* The wide BVH's traversal with the child boxes tested by AVX2
 * instructions (rtree/trace/rtc_box_x86.h; compiled with that ISA's flags,
 * run only where tt_isa_supported says so). */
#include "accel/wbvh/wbvh.h"
#include "accel/rtree/trace/rtc_box_x86.h"
#include "geometry/tri_block_avx2.h"

#define RTC_ISA _avx2

#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_avx2
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_avx2

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/wbvh/wbvh_trace.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/wbvh/wbvh_trace.h"

/* The rows form (the batch calls' single rays), the fast variant's walk
 * inlined (TT_STATS is 1 here: the names are spelled out). */
#define RTC_ROWS_NAME tt_wbvh_trace_avx2_rows
#define RTC_ROWS_WALK wbvh_trace_m_avx2
#define RTC_ROWS_SCALAR tt_wbvh_trace_scalar
#include "accel/rtree/trace/rtc_rows_walk.h"
