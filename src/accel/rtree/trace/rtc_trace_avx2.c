/* The compact layout's stack traversal with the child boxes tested by
 * AVX2 instructions (rtc_box_x86.h; this unit is compiled with that ISA's
 * flags and runs only where tt_isa_supported says so). */
#include "accel/rtree/rtc.h"
#include "accel/rtree/trace/rtc_box_x86.h"
#include "geometry/tri_block_avx2.h"

#define RTC_ISA _avx2

/* The triangle blocks: the ISA's own kernels (bit-identical to the scalar
 * ones). */
#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_avx2
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_avx2

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_trace_stack.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_trace_stack.h"

/* The rows form (the batch calls' single rays), the fast variant's walk
 * inlined (TT_STATS is 1 here: the names are spelled out). */
#define RTC_ROWS_NAME tt_rtc_stack_avx2_rows
#define RTC_ROWS_WALK rtc_stack_m_avx2
#define RTC_ROWS_SCALAR tt_rtc_stack_scalar
#include "accel/rtree/trace/rtc_rows_walk.h"
