/* The CPU instantiations of the kd-tree traversal template (kd_trace.h). */
#ifndef TT_ACCEL_KDTREE_KD_TRACE_CPU_H
#define TT_ACCEL_KDTREE_KD_TRACE_CPU_H

#include "accel/kdtree/kd_layout.h"
#include "geometry/ray.h"
#include "treetrace/treetrace.h"

void tt_kd_cpu_intersect(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                         tt_hit *hit, uint32_t *end);
int tt_kd_cpu_occluded(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                       uint32_t caster, uint32_t *end);
void tt_kd_cpu_intersect_stats(const tt_kd_view *T, int traversal, const tt_wray *r,
                               uint32_t hint, tt_hit *hit, uint32_t *end, tt_ray_stats *stats);
int tt_kd_cpu_occluded_stats(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                             uint32_t caster, uint32_t *end, tt_ray_stats *stats);

#endif
