/* The rows form of a unit's kd-tree traversal (tt_kd_rows_fn,
 * kd_trace_cpu.h): KD_DEFINE_ROWS(name, intersect, occluded) defines
 * `name` over the unit's instantiation of kd_trace.h's entry points. The
 * batch calls used to reach them a ray at a time through tt_wray_init and
 * two calls through pointers (the vtable's, the tree's kernel); here the
 * rays are prepared eight at a time (accel/wray_rows.h) and the traversal
 * is called directly, with the same answers bit for bit. A caster hint is
 * never given: the batch calls have none. */
#ifndef TT_ACCEL_KDTREE_TRACE_KD_ROWS_H
#define TT_ACCEL_KDTREE_TRACE_KD_ROWS_H

#include "accel/wray_rows.h"

#define KD_DEFINE_ROWS(name, intersect, occluded)                                                \
    void name(const tt_kd_view *T, int traversal, const struct tt_packet_rays *rays, int any,    \
              uint32_t hint, tt_hit *hits, uint8_t *occ)                                         \
    {                                                                                            \
        const uint32_t n = rays->n;                                                              \
        for (uint32_t g = 0; g < n; g += TT_WRAY_ROWS) {                                         \
            tt_wray w[TT_WRAY_ROWS];                                                             \
            const uint32_t c = tt_wray_rows(rays, g, w);                                         \
            uint32_t end;                                                                        \
            if (any)                                                                             \
                for (uint32_t l = 0; l < c; l++)                                                 \
                    occ[g + l] = (uint8_t)(occluded(T, traversal, &w[l], hint, TT_INVALID_ID,    \
                                                    &end, NULL) != 0);                           \
            else                                                                                 \
                for (uint32_t l = 0; l < c; l++)                                                 \
                    intersect(T, traversal, &w[l], hint, &hits[g + l], &end, NULL);              \
        }                                                                                        \
    }

#endif
