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

/* SLTR (seq == 0) or SEQ with a near-tie search budget of `spare` descents
 * instead of TT_KD_SPARE, for the tests that force or measure the fallback
 * (see kd_trace_sltr.h): the closest hit (any == 0) into *hit, or the
 * occlusion (any == 1) returned; *gave_up tells whether the search ran out
 * and BTR finished the ray; *end as tt_kd_cpu_intersect's. stats NULL:
 * the fast variant, else the counting one. */
int tt_kd_cpu_stackless(const tt_kd_view *T, int seq, const tt_wray *r, int any, uint32_t hint,
                        unsigned spare, tt_hit *hit, uint32_t *end, int *gave_up,
                        tt_ray_stats *stats);

#endif
