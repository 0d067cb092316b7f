/* Statistics must not slow the fast path, so each traversal is written once
 * as a template and compiled twice: include it with TT_STATS 0 for the fast
 * variant and with TT_STATS 1 for the counting one. In the fast variant every
 * TT_COUNT vanishes and the stats pointer is dead code.
 *
 *   #define TT_STATS 0
 *   #include "accel/stats_variant.h"
 *   #include "accel/foo/foo_trace.h"      // defines TT_VARIANT(foo_intersect)
 *   #undef TT_STATS
 *   #define TT_STATS 1
 *   #include "accel/stats_variant.h"
 *   #include "accel/foo/foo_trace.h"      // defines foo_intersect_stats
 *
 * A template header therefore has no include guard of its own.
 *
 * The names generated this way (each X has an X_stats twin):
 *   bruteforce/bruteforce_trace.h   tt_bf_intersect, tt_bf_occluded
 *   rtree/trace/rtree_trace*.h         tt_rt_trace (and the tt_rt_stackless, tt_rt_ordered,
 *                                   tt_rt_stack it chooses among; tt_rt_leaf)
 *   rtree/trace/rtc_trace_stack.h      tt_rtc_stack_<isa> (RTC_FN adds the ISA)
 *   rtree/trace/rtc_trace_leaf.h       rtc_leaf_<isa> (one leaf; both compact kernels)
 *   rtree/trace/rtc_trace_stackless.h  tt_rtc_stackless
 *   wbvh/wbvh_trace.h                  tt_wbvh_trace_<isa>
 *   kdtree/trace/kd_trace.h            tt_kd_intersect, tt_kd_occluded (over tt_kd_trace,
 *                                   tt_kd_htr, tt_kd_btr, tt_kd_stackless and their steps)
 *   kdtree/trace/kd_packet.h           tt_kd_packet_<isa> (KD_FN adds the ISA)
 *   render/trace_tile.h             primary_tile, shadow_tile
 *   cuda/gpu_pixel_*.h              tt_gpu_rt_*, tt_gpu_rtc_*, tt_gpu_kd_* (device code) */
#undef TT_COUNT
#undef TT_VARIANT
#undef TT_VARIANT_CAT
#define TT_VARIANT_CAT(a, b) a##b
#if TT_STATS
#define TT_COUNT(stats, field, n) ((stats)->field += (uint64_t)(n))
#define TT_VARIANT(fn) TT_VARIANT_CAT(fn, _stats)
#else
#define TT_COUNT(stats, field, n) ((void)0)
#define TT_VARIANT(fn) fn
#endif
