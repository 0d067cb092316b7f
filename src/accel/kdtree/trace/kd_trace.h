/* The kd-tree's per-ray entry points, a template (see accel/stats_variant.h):
 * the CPU tracer (kd_trace_cpu.c) and the CUDA tracer include this same
 * header, twice each (fast and counting). No allocation, no function
 * pointers, fixed-size stacks.
 *
 *   traversal  TT_KD_HTR, TT_KD_BTR, TT_KD_SLTR or TT_KD_SEQ
 *   hint       start node (aug[] index) for the ray origin, or TT_INVALID_ID
 *   caster     occlusion only: the node of the last shadow caster, probed
 *              first, or TT_INVALID_ID
 *   *end       on return: the augmented node where the ray ended (the hint
 *              for rays from its hit point), TT_INVALID_ID if none
 */
#include "accel/kdtree/trace/kd_trace_common.h"
#include "accel/kdtree/trace/kd_trace_htr.h"
#include "accel/kdtree/trace/kd_trace_btr.h"
#include "accel/kdtree/trace/kd_trace_sltr.h"

TT_HD int TT_VARIANT(tt_kd_trace)(const tt_kd_view *T, int traversal, const tt_wray *r, int any,
                                  uint32_t hint, tt_kd_best *best, uint32_t *end,
                                  tt_ray_stats *stats)
{
    switch (traversal) {
    case TT_KD_BTR:
        return TT_VARIANT(tt_kd_btr)(T, r, any, hint, best, end, stats);
    case TT_KD_SLTR:
        return TT_VARIANT(tt_kd_stackless)(T, r, any, 0, hint, best, end, stats);
    case TT_KD_SEQ:
        return TT_VARIANT(tt_kd_stackless)(T, r, any, 1, hint, best, end, stats);
    default:
        return TT_VARIANT(tt_kd_htr)(T, r, any, best, stats);
    }
}

TT_HD void TT_VARIANT(tt_kd_intersect)(const tt_kd_view *T, int traversal, const tt_wray *r,
                                       uint32_t hint, tt_hit *hit, uint32_t *end,
                                       tt_ray_stats *stats)
{
    tt_kd_best best;
    (void)stats;
    TT_COUNT(stats, rays, 1);
    tt_kd_best_init(&best, r);
    *end = TT_INVALID_ID;
    TT_VARIANT(tt_kd_trace)(T, traversal, r, 0, hint, &best, end, stats);
    tt_kd_best_store(&best, hit);
}

/* Havran & Bittner's optional shadow-caster cache: a shadow ray coherent
 * with the previous one is likely blocked by the same object, so the part
 * of the ray inside the last caster's augmented box is searched first. Any
 * hit there is a true hit, so a miss simply falls back to the full search. */
TT_HD int TT_VARIANT(tt_kd_probe)(const tt_kd_view *T, int traversal, const tt_wray *r,
                                  uint32_t caster, tt_kd_best *best, uint32_t *end,
                                  tt_ray_stats *stats)
{
    float ta, tb;
    unsigned ties = 0;
    (void)stats;
    if (caster == 0 || caster >= T->aug_count) return 0;
    TT_COUNT(stats, boxes, 1);
    if (T->empty || !tt_kd_box_interval(&T->aug[caster], r, NULL, &ta, &tb)) return 0;
    if (traversal == TT_KD_SLTR || traversal == TT_KD_SEQ) {
        tt_kd_order ord;
        tt_kd_order_init(&ord, 0);
        /* A probe that would exceed the near-tie budget simply misses. */
        tt_kd_budget budget = {TT_KD_SPARE, 0u, 0};
        return TT_VARIANT(tt_kd_sltr_pass)(T, r, 1, &ord, caster, ta, 0.0f, caster, &ties,
                                           &budget, best, end, stats) &&
               !budget.over;
    }
    return TT_VARIANT(tt_kd_btr_from)(T, r, 1, caster, ta, tb, caster, best, end, stats);
}

TT_HD int TT_VARIANT(tt_kd_occluded)(const tt_kd_view *T, int traversal, const tt_wray *r,
                                     uint32_t hint, uint32_t caster, uint32_t *end,
                                     tt_ray_stats *stats)
{
    tt_kd_best best;
    (void)stats;
    TT_COUNT(stats, rays, 1);
    tt_kd_best_init(&best, r);
    *end = TT_INVALID_ID;
    if (caster != TT_INVALID_ID && TT_VARIANT(tt_kd_probe)(T, traversal, r, caster, &best, end, stats))
        return 1;
    *end = TT_INVALID_ID;
    return TT_VARIANT(tt_kd_trace)(T, traversal, r, 1, hint, &best, end, stats);
}
