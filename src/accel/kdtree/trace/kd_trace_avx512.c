/* The kd-tree's fast traversals for AVX-512 (F, VL, BW, DQ; no FMA contraction: see
 * CMakeLists.txt): the kd_trace.h template with the eight-lane gathered
 * leaf test of kd_leaf_gather.h. Only the fast variant: the counting one is
 * kd_trace_cpu.c's for every ISA. */
#include "accel/kdtree/trace/kd_trace_cpu.h"

#if defined(TT_HAVE_X86_KERNELS)
#include "accel/kdtree/trace/kd_best.h"
#include "accel/kdtree/trace/kd_ray.h"
#include "geometry/triangle.h"
#include "accel/kdtree/trace/kd_leaf_gather.h"

#define TT_KD_LEAF_FAST kd_leaf_gather
#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_trace.h"

void tt_kd_avx512_intersect(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                          tt_hit *hit, uint32_t *end)
{
    tt_kd_intersect(T, traversal, r, hint, hit, end, NULL);
}

int tt_kd_avx512_occluded(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                        uint32_t caster, uint32_t *end)
{
    return tt_kd_occluded(T, traversal, r, hint, caster, end, NULL);
}
#endif
