/* The kd-tree's packet kernels (kd_packet.h) and their choice by ISA. */
#ifndef TT_ACCEL_KDTREE_KD_PACKET_CPU_H
#define TT_ACCEL_KDTREE_KD_PACKET_CPU_H

#include "accel/accel.h" /* tt_packet_stats */
#include "accel/kdtree/kd_layout.h"
#include "core/isa.h"
#include "geometry/ray.h"

/* rays->n <= TT_PACKET_MAX rows, traced with HTR as packets: closest hits
 * into hits (any = 0) or occlusion bytes into occ (any = 1), each equal to
 * the single-ray HTR's bit for bit. T is the tree's block view (kd_blocks.h:
 * its leaves' triangles as blocks, which the packets test), V the tree's
 * own view (the counting variant's single-ray fallback walks it). The
 * _stats forms count into *stats. */
typedef void (*tt_kd_packet_fn)(const tt_kd_view *T, const tt_kd_view *V,
                                const tt_packet_rays *rays, int any, tt_hit *hits, uint8_t *occ,
                                tt_packet_stats *stats);

#if defined(TT_HAVE_X86_KERNELS)
void tt_kd_packet_avx2(const tt_kd_view *T, const tt_kd_view *V, const tt_packet_rays *rays, int any,
                       tt_hit *hits, uint8_t *occ, tt_packet_stats *stats);
void tt_kd_packet_avx2_stats(const tt_kd_view *T, const tt_kd_view *V, const tt_packet_rays *rays, int any,
                             tt_hit *hits, uint8_t *occ, tt_packet_stats *stats);
void tt_kd_packet_avx512(const tt_kd_view *T, const tt_kd_view *V, const tt_packet_rays *rays, int any,
                         tt_hit *hits, uint8_t *occ, tt_packet_stats *stats);
void tt_kd_packet_avx512_stats(const tt_kd_view *T, const tt_kd_view *V, const tt_packet_rays *rays, int any,
                               tt_hit *hits, uint8_t *occ, tt_packet_stats *stats);
#endif

/* The packet kernel of a resolved isa (stats: the counting one); NULL for
 * scalar and SSE4.2, which trace a packet ray by ray. */
static inline tt_kd_packet_fn tt_kd_packet_kernel(tt_isa isa, int stats)
{
#if defined(TT_HAVE_X86_KERNELS)
    if (isa == TT_ISA_AVX2) return stats ? tt_kd_packet_avx2_stats : tt_kd_packet_avx2;
    if (isa == TT_ISA_AVX512) return stats ? tt_kd_packet_avx512_stats : tt_kd_packet_avx512;
#else
    (void)isa;
    (void)stats;
#endif
    return NULL;
}

#endif
