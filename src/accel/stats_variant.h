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
 * A template header therefore has no include guard of its own. */
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
