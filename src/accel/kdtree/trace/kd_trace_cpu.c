/* Compiles the kd-tree traversal template twice: the fast variant and the
 * counting one (see accel/stats_variant.h). */
#include "accel/kdtree/trace/kd_trace_cpu.h"

#include <stdint.h>

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_trace.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_trace.h"

void tt_kd_cpu_intersect(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                         tt_hit *hit, uint32_t *end)
{
    tt_kd_intersect(T, traversal, r, hint, hit, end, NULL);
}

int tt_kd_cpu_occluded(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                       uint32_t caster, uint32_t *end)
{
    return tt_kd_occluded(T, traversal, r, hint, caster, end, NULL);
}

void tt_kd_cpu_intersect_stats(const tt_kd_view *T, int traversal, const tt_wray *r,
                               uint32_t hint, tt_hit *hit, uint32_t *end, tt_ray_stats *stats)
{
    tt_kd_intersect_stats(T, traversal, r, hint, hit, end, stats);
}

#include "accel/kdtree/trace/kd_rows.h"
KD_DEFINE_ROWS(tt_kd_cpu_rows, tt_kd_intersect, tt_kd_occluded)

int tt_kd_cpu_occluded_stats(const tt_kd_view *T, int traversal, const tt_wray *r, uint32_t hint,
                             uint32_t caster, uint32_t *end, tt_ray_stats *stats)
{
    return tt_kd_occluded_stats(T, traversal, r, hint, caster, end, stats);
}

int tt_kd_cpu_stackless(const tt_kd_view *T, int seq, const tt_wray *r, int any, uint32_t hint,
                        unsigned spare, tt_hit *hit, uint32_t *end, int *gave_up,
                        tt_ray_stats *stats)
{
    tt_kd_best best;
    int s;
    *end = TT_INVALID_ID;
    tt_kd_best_init(&best, r);
    if (stats) {
        stats->rays++;
        s = tt_kd_stackless_within_stats(T, r, any, seq, hint, spare, &best, end, gave_up, stats);
    } else {
        s = tt_kd_stackless_within(T, r, any, seq, hint, spare, &best, end, gave_up, NULL);
    }
    tt_kd_best_store(&best, hit);
    return s;
}

tt_kd_kernels tt_kd_cpu_kernels(tt_isa isa, size_t triangle_count)
{
    tt_kd_kernels k = {tt_kd_cpu_intersect, tt_kd_cpu_occluded, tt_kd_cpu_rows, 0};
    (void)isa;
    (void)triangle_count;
#if defined(TT_HAVE_X86_KERNELS)
    if (isa == TT_ISA_AVX2) {
        k.intersect = tt_kd_avx2_intersect;
        k.occluded = tt_kd_avx2_occluded;
        k.rows = tt_kd_avx2_rows;
        k.blocks = 1;
    } else if (isa == TT_ISA_AVX512) {
        k.intersect = tt_kd_avx512_intersect;
        k.occluded = tt_kd_avx512_occluded;
        k.rows = tt_kd_avx512_rows;
        k.blocks = 1;
    }
#endif
    return k;
}
