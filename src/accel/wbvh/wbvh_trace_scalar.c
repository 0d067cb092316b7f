/* The wide BVH's traversal in portable C (TT_ISA_SCALAR), one box test per
 * child; and the choice of unit, made once when the tree is built. */
#include "accel/wbvh/wbvh.h"
#include "accel/rtree/trace/rtc_box_scalar.h"

#define RTC_ISA _scalar

#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_scalar
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_scalar

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/wbvh/wbvh_trace.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/wbvh/wbvh_trace.h"

/* The rows form (the batch calls' single rays). */
#include "accel/rtree/trace/rtc_rows.h"
RTC_DEFINE_ROWS(tt_wbvh_trace_scalar_rows, tt_wbvh_trace_scalar)

void wbvh_select(rtc_tree *t, tt_isa isa)
{
    t->packet = t->packet_stats = NULL; /* rays go one by one */
    t->trace = tt_wbvh_trace_scalar;
    t->trace_stats = tt_wbvh_trace_scalar_stats;
    t->rows = tt_wbvh_trace_scalar_rows;
#ifdef TT_HAVE_X86_KERNELS
    if (isa == TT_ISA_SSE42) {
        t->trace = tt_wbvh_trace_sse42;
        t->trace_stats = tt_wbvh_trace_sse42_stats;
        t->rows = tt_wbvh_trace_sse42_rows;
    } else if (isa == TT_ISA_AVX2) {
        t->trace = tt_wbvh_trace_avx2;
        t->trace_stats = tt_wbvh_trace_avx2_stats;
        t->rows = tt_wbvh_trace_avx2_rows;
    } else if (isa == TT_ISA_AVX512) {
        t->trace = tt_wbvh_trace_avx512;
        t->trace_stats = tt_wbvh_trace_avx512_stats;
        t->rows = tt_wbvh_trace_avx512_rows;
    }
#else
    (void)isa;
#endif
}
