/* The CPU instantiations of the kd-tree traversal template (kd_trace.h). */
#ifndef TT_ACCEL_KDTREE_KD_TRACE_CPU_H
#define TT_ACCEL_KDTREE_KD_TRACE_CPU_H

#include "accel/kdtree/kd_layout.h"
#include "geometry/ray.h"
#include "treetrace/treetrace.h"

struct tt_packet_rays; /* accel/accel.h: the rows forms' rays */

void tt_kd_cpu_intersect(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                         tt_hit *hit, uint32_t *end);
int tt_kd_cpu_occluded(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                       uint32_t caster, uint32_t *end);
void tt_kd_cpu_intersect_stats(const tt_kd_view *T, int traversal, const tt_wray *r,
                               uint32_t hint, tt_hit *hit, uint32_t *end, tt_ray_stats *stats);
void tt_kd_cpu_rows(const tt_kd_view *T, int traversal, const struct tt_packet_rays *rays,
                    int any, uint32_t hint, tt_hit *hits, uint8_t *occ);
int tt_kd_cpu_occluded_stats(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                             uint32_t caster, uint32_t *end, tt_ray_stats *stats);

/* The fast entry points of one ISA: tt_kd_cpu_intersect / _occluded's
 * signatures and results. A tree resolves them once when it is built
 * (tt_kd_cpu_kernels) and calls them through these pointers. */
typedef void (*tt_kd_intersect_fn)(const tt_kd_view *T, int traversal, const tt_wray *r,
                                   uint32_t hint, tt_hit *hit, uint32_t *end);
typedef int (*tt_kd_occluded_fn)(const tt_kd_view *T, int traversal, const tt_wray *r,
                                 uint32_t hint, uint32_t caster, uint32_t *end);
/* Their rows form (the vtable's intersect_rows / occluded_rows): rays->n
 * rows one by one, each with start hint `hint` and no caster, answered as
 * the single-ray entry answers tt_wray_init of it, into hits[i] (any = 0)
 * or occ[i] (any = 1); the rays prepared eight at a time
 * (accel/wray_rows.h), the traversal called directly (kd_rows.h). */
typedef void (*tt_kd_rows_fn)(const tt_kd_view *T, int traversal,
                              const struct tt_packet_rays *rays, int any, uint32_t hint,
                              tt_hit *hits, uint8_t *occ);
typedef struct tt_kd_kernels {
    tt_kd_intersect_fn intersect;
    tt_kd_occluded_fn occluded;
    tt_kd_rows_fn rows;
    /* 1: they read leaves from the view's blocks (kd_blocks.h), so they
     * must be given a block view, never the tree's plain one. */
    int blocks;
} tt_kd_kernels;

/* The kernels for a resolved isa: AVX2 and AVX-512 test leaves eight
 * triangles at a time from the leaf blocks of kd_blocks.h (kd_leaf_block.h;
 * before, kd_leaf_gather.h's loads through refs[] and a transpose, once
 * gathers); scalar and SSE4.2 the scalar loop: the
 * gathered kernel measured only level with the scalar loop when leaves
 * held about three triangles (C_I 0.5), so a four-lane one was not
 * written; with the transposed loads and the default C_I 0.2 a four-lane
 * SSE4.2 kernel may now pay (not measured). */
tt_kd_kernels tt_kd_cpu_kernels(tt_isa isa, size_t triangle_count);

#if defined(TT_HAVE_X86_KERNELS)
void tt_kd_avx2_intersect(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                          tt_hit *hit, uint32_t *end);
int tt_kd_avx2_occluded(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                        uint32_t caster, uint32_t *end);
void tt_kd_avx512_intersect(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                            tt_hit *hit, uint32_t *end);
int tt_kd_avx512_occluded(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                          uint32_t caster, uint32_t *end);
void tt_kd_avx2_rows(const tt_kd_view *T, int traversal, const struct tt_packet_rays *rays,
                     int any, uint32_t hint, tt_hit *hits, uint8_t *occ);
void tt_kd_avx512_rows(const tt_kd_view *T, int traversal, const struct tt_packet_rays *rays,
                       int any, uint32_t hint, tt_hit *hits, uint8_t *occ);
#endif

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
