/* The kd-tree's fast traversals for AVX-512 (F, VL, BW, DQ; no FMA contraction: see
 * CMakeLists.txt): the kd_trace.h template with the eight-lane block
 * leaf test of kd_leaf_block.h;
 * HTR walks the node lines of kd_lines.h (kd_trace_lines.h) where the view
 * has them. Only the fast variant: the counting one is kd_trace_cpu.c's
 * for every ISA. */
#include "accel/kdtree/trace/kd_trace_cpu.h"

#if defined(TT_HAVE_X86_KERNELS)
#include "accel/kdtree/trace/kd_best.h"
#include "accel/kdtree/trace/kd_ray.h"
#include "geometry/triangle.h"
#include "accel/kdtree/trace/kd_leaf_block.h"

#define TT_KD_LEAF_FAST kd_leaf_block
#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_trace.h"
#include "accel/kdtree/kd_lines.h"
#include "accel/kdtree/trace/kd_trace_lines.h"

void tt_kd_avx512_intersect(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                          tt_hit *hit, uint32_t *end)
{
    /* A view without leaf blocks (kd_blocks.h) is the tree's own: the
     * packet kernel's rare single-ray fallback (kd_packet.h) walks it.
     * The scalar kernel then, with the same answers. */
    if (!T->blocks) {
        tt_kd_cpu_intersect(T, traversal, r, hint, hit, end);
        return;
    }
    if (kd_lines_intersect(T, traversal, r, hit, end)) return;
    tt_kd_intersect(T, traversal, r, hint, hit, end, NULL);
}

int tt_kd_avx512_occluded(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                        uint32_t caster, uint32_t *end)
{
    if (!T->blocks) return tt_kd_cpu_occluded(T, traversal, r, hint, caster, end);
    int occ;
    if (kd_lines_occluded(T, traversal, r, caster, end, &occ)) return occ;
    return tt_kd_occluded(T, traversal, r, hint, caster, end, NULL);
}

/* The rows form (the batch calls' single rays); a view without leaf
 * blocks goes to the scalar kernel's, as above. */
#include "accel/kdtree/trace/kd_rows.h"
/* The rows take the line walk too, as the entry points above do (they
 * used to call the template's walk over the block copy's nodes). */
static inline void kd_avx512_rows_intersect(const tt_kd_view *T, int traversal,
                                            const tt_wray *r, uint32_t hint, tt_hit *hit,
                                            uint32_t *end, tt_ray_stats *stats)
{
    if (kd_lines_intersect(T, traversal, r, hit, end)) return;
    tt_kd_intersect(T, traversal, r, hint, hit, end, stats);
}

static inline int kd_avx512_rows_occluded(const tt_kd_view *T, int traversal,
                                          const tt_wray *r, uint32_t hint, uint32_t caster,
                                          uint32_t *end, tt_ray_stats *stats)
{
    int occ;
    if (kd_lines_occluded(T, traversal, r, caster, end, &occ)) return occ;
    return tt_kd_occluded(T, traversal, r, hint, caster, end, stats);
}
KD_DEFINE_ROWS(kd_avx512_rows_blocks, kd_avx512_rows_intersect, kd_avx512_rows_occluded)

void tt_kd_avx512_rows(const tt_kd_view *T, int traversal, const struct tt_packet_rays *rays,
                    int any, uint32_t hint, tt_hit *hits, uint8_t *occ)
{
    if (!T->blocks) tt_kd_cpu_rows(T, traversal, rays, any, hint, hits, occ);
    else kd_avx512_rows_blocks(T, traversal, rays, any, hint, hits, occ);
}
#endif
