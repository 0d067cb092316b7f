/* Human names of the options, as the papers write them, for the CSV and the
 * report. */
#include <stdio.h>
#include <string.h>

#include "bench/bench.h"

const char *bench_rays_name(bench_rays r)
{
    return r == BENCH_PRIMARY ? "primary" : "primary+shadow";
}

const char *bench_strategy_name(tt_rtree_strategy s)
{
    switch (s) {
    case TT_RTREE_MIN_VOLUME: return "minVolume";
    case TT_RTREE_MIN_SURFACE: return "minSurface";
    case TT_RTREE_MIN_OVERLAP: return "minOverlap";
    case TT_RTREE_RSTAR: return "R*-tree";
    case TT_RTREE_RSTAR_SURFACE: return "R*-treeSrfc";
    case TT_RTREE_RRSTAR: return "RR*-tree";
    }
    return "?";
}

const char *bench_rtree_traversal_name(tt_rtree_traversal t)
{
    switch (t) {
    case TT_RTREE_AUTO: return "auto";
    case TT_RTREE_STACKLESS: return "stackless";
    case TT_RTREE_ORDERED: return "ordered";
    case TT_RTREE_STACK: return "stack";
    }
    return "?";
}

const char *bench_kd_traversal_name(tt_kd_traversal t)
{
    switch (t) {
    case TT_KD_HTR: return "HTR";
    case TT_KD_BTR: return "BTR";
    case TT_KD_SLTR: return "SLTR";
    case TT_KD_SEQ: return "SEQ";
    }
    return "?";
}

const char *bench_traversal_name(const tt_build_options *b)
{
    if (strcmp(b->accel, "rtree") == 0) return bench_rtree_traversal_name(b->rtree.traversal);
    if (strcmp(b->accel, "kdtree") == 0) return bench_kd_traversal_name(b->kdtree.traversal);
    return "-";
}

void bench_options_string(const tt_build_options *b, char *buf, size_t size)
{
    if (strcmp(b->accel, "rtree") == 0) {
        const tt_rtree_options *r = &b->rtree;
        static const char *const builds[] = {"insert", "str", "hilbert", "sah"};
        snprintf(buf, size, "build=%s layout=%s strategy=%s m=%d M=%d reinsert=%d p=%.2f %s split=%s",
                 (unsigned)r->build < 4 ? builds[r->build] : "?",
                 r->layout == TT_RTREE_LAYOUT_COMPACT ? "compact" : "complete",
                 bench_strategy_name(r->strategy), r->m, r->M, r->reinsert,
                 (double)r->reinsert_fraction, r->reinsert_far ? "far" : "close",
                 r->split == TT_RTREE_SPLIT_RSTAR ? "R*" : "quadratic");
    } else if (strcmp(b->accel, "kdtree") == 0) {
        const tt_kdtree_options *k = &b->kdtree;
        snprintf(buf, size, "builder=%s dmin=%d CT=%g CI=%g bonus=%g max_depth=%d",
                 k->builder == TT_KD_NLOGN    ? "nlogn"
                 : k->builder == TT_KD_NLOG2N ? "nlog2n"
                                              : "binned",
                 k->dmin, (double)k->cost_traversal,
                 (double)k->cost_intersect, (double)k->empty_bonus, k->max_depth);
    } else if (strcmp(b->accel, "embree") == 0) {
        static const char *const q[] = {"high", "medium", "low"};
        snprintf(buf, size, "quality=%s robust",
                 (unsigned)b->embree.quality < 3 ? q[b->embree.quality] : "?");
    } else {
        snprintf(buf, size, "-");
    }
}
