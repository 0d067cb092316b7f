/* All R-tree traversals of one statistics variant, and the choice among
 * them: include after accel/stats_variant.h (see there). The CUDA backend
 * includes this same file, so CPU and GPU run identical traversal code. */
#include "accel/rtree/trace/rtree_trace_ordered.h"
#include "accel/rtree/trace/rtree_trace_stack.h"
#include "accel/rtree/trace/rtree_trace_stackless.h"

/* Runs the traversal `which` (TT_RTREE_STACKLESS, _ORDERED or _STACK);
 * returns whether something was hit (for `any`, whether occluded). */
TT_HD int TT_VARIANT(tt_rt_trace)(const tt_rtree_packed *t, int which, const tt_wray *r, int any,
                                   tt_hit *hit, tt_ray_stats *stats)
{
    if (which == TT_RTREE_ORDERED) return TT_VARIANT(tt_rt_ordered)(t, r, any, hit, stats);
    if (which == TT_RTREE_STACK) return TT_VARIANT(tt_rt_stack)(t, r, any, hit, stats);
    return TT_VARIANT(tt_rt_stackless)(t, r, any, hit, stats);
}
