/* The "rtree" structure: R*-tree-style insertion build (rtree_build.c),
 * packed into the complete M-ary level-order array (rtree_pack.c), traced
 * by the stackless, ordered or stack traversal (rtree_trace*.h); or packed
 * into the compact wide layout (rtc_pack.c), traced by its stack traversal
 * per ISA or its stackless traversal (rtc_trace_*). */
#include "accel/rtree/rtree.h"
#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_bulk.h"
#include "accel/rtree/build/rtree_split_refs.h"
#include "accel/rtree/update/rtree_dyn.h"
#include "accel/rtree/rtree_io.h"

#include <math.h>
#include <string.h>

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtree_trace.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtree_trace.h"

/* -------------------------------------------------------------- options */

static tt_status validate(tt_context *ctx, const tt_rtree_options *o)
{
    if ((unsigned)o->build > TT_RTREE_BUILD_SAH)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "rtree: unknown build %d", (int)o->build);
    if ((unsigned)o->strategy > TT_RTREE_RRSTAR)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "rtree: unknown strategy %d",
                        (int)o->strategy);
    if ((unsigned)o->split > TT_RTREE_SPLIT_QUADRATIC)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "rtree: unknown split %d", (int)o->split);
    if ((unsigned)o->traversal > TT_RTREE_STACK)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "rtree: unknown traversal %d",
                        (int)o->traversal);
    if (!(o->split_budget >= 0.0f && o->split_budget <= 4.0f))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "rtree: split_budget = %g is out of range [0, 4]", (double)o->split_budget);
    if ((unsigned)o->layout > TT_RTREE_LAYOUT_COMPACT)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "rtree: unknown layout %d", (int)o->layout);
    if (o->M < 4 || o->M > TT_RT_MAX_M)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "rtree: M = %d is out of range (4 <= M <= %d)", o->M, TT_RT_MAX_M);
    if (o->m < 2 || 2 * o->m > o->M)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "rtree: m = %d is out of range for M = %d (2 <= m <= M/2)", o->m, o->M);
    if (!(o->reinsert_fraction >= 0.0f && o->reinsert_fraction < 1.0f))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "rtree: reinsert_fraction = %g is out of range [0, 1)",
                        (double)o->reinsert_fraction);
    int p = (int)(o->reinsert_fraction * (float)(o->M + 1));
    if (p < 1) p = 1;
    if (o->reinsert && p > o->M + 1 - o->m)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "rtree: reinsert_fraction = %g ejects %d of %d entries, leaving fewer "
                        "than m = %d", (double)o->reinsert_fraction, p, o->M + 1, o->m);
    return TT_OK;
}

/* ---------------------------------------------------------------- build */

static void rtree_destroy(tt_accel *a)
{
    rt_tree *t = a->impl;
    if (!t) return;
    if (t->dyn) {
        rt_dyn_free(a->ctx, t->dyn);
        tt_free(a->ctx, t->dyn);
    }
    tt_free(a->ctx, t->lev_rec);
    tt_free(a->ctx, t->env);
    rt_tree_free(a->ctx, t);
    tt_free(a->ctx, t);
    a->impl = NULL;
}

int tt_rtree_max_entries(const tt_rtree_options *o)
{
    if (!o) return 0;
    if (o->M != 0) return o->M;
    return o->layout == TT_RTREE_LAYOUT_COMPACT ? 16 : 4;
}

static tt_status rtree_build(tt_accel *a)
{
    /* M = 0 resolves here, so that everything after (and the accel's
     * options as callers read them back) sees the M the tree has. */
    a->options.rtree.M = tt_rtree_max_entries(&a->options.rtree);
    const tt_rtree_options *o = &a->options.rtree;
    tt_status st = validate(a->ctx, o);
    if (st != TT_OK) return st;
    const tt_scene *scene = a->scene;
    if (scene->triangle_count >= (size_t)1 << 31)
        return tt_error(a->ctx, TT_ERR_INVALID_ARGUMENT, "rtree: %zu triangles, at most 2^31",
                        scene->triangle_count);
    const uint32_t T = (uint32_t)scene->triangle_count;

    rt_tree *t = tt_calloc(a->ctx, 1, sizeof *t);
    if (!t) return tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory");
    a->impl = t;
    t->m = o->m;
    t->traversal = o->traversal;
    t->layout = o->layout;
    t->compact.m = o->m;

    double t0 = tt_now();
    float *tri_box = tt_alloc_array(a->ctx, T ? T : 1, 6 * sizeof(float));
    if (!tri_box) return tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory");
    for (uint32_t i = 0; i < T; i++) {
        const float *v = scene->tri + 9 * (size_t)i;
        float *bx = tri_box + 6 * (size_t)i;
        for (int k = 0; k < 3; k++) {
            bx[k] = rt_min(rt_min(v[k], v[3 + k]), v[6 + k]);
            bx[k + 3] = rt_max(rt_max(v[k], v[3 + k]), v[6 + k]);
        }
    }
    /* the default (SAH loader, compact layout) packs the loader's level
     * form straight into the layout: the same tree without the pointer
     * tree's node pool (rtree_bulk.h) */
    if (o->build == TT_RTREE_BUILD_SAH && t->layout == TT_RTREE_LAYOUT_COMPACT &&
        T > (uint32_t)o->M) {
        rt_bulk_levels lv;
        memset(&lv, 0, sizeof lv);
        /* early split clipping: the loader builds over references, then a
         * leaf's references of one triangle become that triangle once */
        rt_refs refs = {NULL, NULL, 0};
        if (o->split_budget > 0.0f)
            st = rt_split_refs(a->ctx, scene->tri, tri_box, T, o->split_budget, &refs);
        const int split = st == TT_OK && refs.count > T;
        if (st == TT_OK)
            st = rt_bulk_sah_levels(&lv, a->ctx, o, split ? refs.box : tri_box,
                                    split ? refs.count : T);
        if (st == TT_OK && split) rt_bulk_levels_merge_refs(&lv, refs.tri, T);
        rt_refs_free(a->ctx, &refs);
        double t1 = tt_now();
        if (st == TT_OK) {
            st = rtc_pack_levels(a->ctx, &lv, scene->tri, &t->compact);
            rtc_select(&t->compact, (int)o->traversal, a->isa);
            t->compact.split = split;
            if (split) t->compact.m = 1; /* merged leaves may hold fewer than m */
        }
        double t2 = tt_now();
        rt_bulk_levels_free(a->ctx, &lv);
        tt_free(a->ctx, tri_box);
        t->insert_s = t1 - t0;
        t->pack_s = t2 - t1;
        return st;
    }
    /* the same pointer tree from either kind of builder (the insertion
     * options apply to insertion only) */
    rt_builder b;
    if (o->build == TT_RTREE_BUILD_INSERT) {
        st = rt_builder_init(&b, a->ctx, o, tri_box, T);
        for (uint32_t i = 0; i < T && st == TT_OK; i++) st = rt_builder_insert_triangle(&b, i);
    } else {
        st = rt_bulk_build(&b, a->ctx, o, tri_box, T);
    }
    double t1 = tt_now();
    if (st == TT_OK && t->layout == TT_RTREE_LAYOUT_COMPACT) {
        st = rtc_pack(a->ctx, &b, scene->tri, &t->compact);
        rtc_select(&t->compact, (int)o->traversal, a->isa);
    } else if (st == TT_OK) {
        st = rt_pack(a->ctx, &b, scene->tri, t);
    }
    double t2 = tt_now();
    rt_builder_free(&b);
    tt_free(a->ctx, tri_box);
    t->insert_s = t1 - t0;
    t->pack_s = t2 - t1;
    return st;
}

/* ------------------------------------------------------------- tracing */

uint32_t rt_locate(const rt_tree *t, const float *p)
{
    if (t->layout == TT_RTREE_LAYOUT_COMPACT) /* one traversal for every ray */
        return t->traversal == TT_RTREE_STACKLESS ? TT_RTREE_STACKLESS : TT_RTREE_STACK;
    if (t->traversal != TT_RTREE_AUTO) return (uint32_t)t->traversal;
    const float *b = t->root_box;
    int inside = p[0] >= b[0] && p[0] <= b[3] && p[1] >= b[1] && p[1] <= b[4] && p[2] >= b[2] &&
                 p[2] <= b[5];
    return inside ? TT_RTREE_STACKLESS : TT_RTREE_ORDERED;
}

/* The traversal for one ray: the forced one, or for auto the start hint
 * (see rt_locate), or without a valid hint the ray's own origin. */
static int pick(const rt_tree *t, const tt_wray *r, tt_trace_args *args)
{
    if (t->traversal != TT_RTREE_AUTO) return (int)t->traversal;
    if (args) {
        args->end_hint = TT_INVALID_ID;
        if (args->start_hint == TT_RTREE_STACKLESS || args->start_hint == TT_RTREE_ORDERED)
            return (int)args->start_hint;
    }
    return (int)rt_locate(t, r->org);
}

static void rtree_intersect(const tt_accel *a, const tt_wray *r, tt_hit *hit, tt_trace_args *args)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT) {
        t->compact.trace(&t->compact.c, r, 0, hit, NULL);
        return;
    }
    tt_rt_trace(&t->p, pick(t, r, args), r, 0, hit, NULL);
}

static int rtree_occluded(const tt_accel *a, const tt_wray *r, tt_trace_args *args)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT)
        return t->compact.trace(&t->compact.c, r, 1, NULL, NULL);
    return tt_rt_trace(&t->p, pick(t, r, args), r, 1, NULL, NULL);
}

static void rtree_intersect_stats(const tt_accel *a, const tt_wray *r, tt_hit *hit,
                                  tt_trace_args *args, tt_ray_stats *stats)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT) {
        t->compact.trace_stats(&t->compact.c, r, 0, hit, stats);
        return;
    }
    tt_rt_trace_stats(&t->p, pick(t, r, args), r, 0, hit, stats);
}

static int rtree_occluded_stats(const tt_accel *a, const tt_wray *r, tt_trace_args *args,
                                tt_ray_stats *stats)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT)
        return t->compact.trace_stats(&t->compact.c, r, 1, NULL, stats);
    return tt_rt_trace_stats(&t->p, pick(t, r, args), r, 1, NULL, stats);
}

/* Packets (rtc_packet.h): the compact layout's packet kernel where its ISA
 * has one; otherwise (scalar, SSE4.2, the stackless walk, the complete
 * layout) the rays one by one through the single-ray entries, so the
 * answers are the same either way. */
static void rtree_packet(const tt_accel *a, const tt_packet_rays *rays, int any, tt_hit *hits,
                         uint8_t *occ, tt_packet_stats *stats)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT && t->compact.packet) {
        if (stats) t->compact.packet_stats(&t->compact.c, rays, any, hits, occ, stats);
        else t->compact.packet(&t->compact.c, rays, any, hits, occ, NULL);
        return;
    }
    for (uint32_t i = 0; i < rays->n; i++) {
        tt_wray w;
        tt_packet_ray_wray(rays, i, &w);
        if (stats) {
            stats->fallback_rays++;
            if (any) occ[i] = (uint8_t)(rtree_occluded_stats(a, &w, NULL, &stats->rays) != 0);
            else rtree_intersect_stats(a, &w, &hits[i], NULL, &stats->rays);
        } else {
            if (any) occ[i] = (uint8_t)(rtree_occluded(a, &w, NULL) != 0);
            else rtree_intersect(a, &w, &hits[i], NULL);
        }
    }
}
static void rtree_intersect_packet(const tt_accel *a, const tt_packet_rays *rays, tt_hit *hits)
{
    rtree_packet(a, rays, 0, hits, NULL, NULL);
}
static void rtree_occluded_packet(const tt_accel *a, const tt_packet_rays *rays, uint8_t *occ)
{
    rtree_packet(a, rays, 1, NULL, occ, NULL);
}
static void rtree_intersect_packet_stats(const tt_accel *a, const tt_packet_rays *rays,
                                         tt_hit *hits, tt_packet_stats *stats)
{
    rtree_packet(a, rays, 0, hits, NULL, stats);
}
static void rtree_occluded_packet_stats(const tt_accel *a, const tt_packet_rays *rays,
                                        uint8_t *occ, tt_packet_stats *stats)
{
    rtree_packet(a, rays, 1, NULL, occ, stats);
}

/* Whether an item's packets paid (vt->packets_pay): an occlusion packet's
 * node visit tests all its rays' groups, a single ray's only its own, so
 * packets pay while a visit finds enough of the packet's rays still in the
 * node: active lanes a visit over rays a packet, at least PK_PAY_SHARE.
 * Measured (1 thread CPU, 512^2 views, shadow rays, packets on / off against
 * that share; /work/notes/dyn8.md): the shared views 0.51-0.91x at 0.53-0.88,
 * the unseen ones 0.57-0.99x at 0.38-0.76 (field:main 0.99x at 0.378), bench
 * D's bunny after 1% edits a frame 0.93x at 0.58 (frame 0), ~1.0x at 0.41
 * (frame 4), 1.11x at 0.37 (frame 6), 1.3-1.7x at 0.22-0.27 (frames 25-100:
 * the edits scatter shifted copies, and rays toward the light from hits at
 * many depths part early). Camera tiles were 0.37-0.63x at 0.46-0.81 and no
 * loss was seen: closest-hit packets are left to the coherence rule. A
 * probe without packets (a complete layout's fallback) has no say. */
#define PK_PAY_SHARE 0.375
static int rtree_packets_pay(const tt_accel *a, int any, const tt_packet_stats *probe)
{
    (void)a;
    if (!any || probe->packets == 0 || probe->node_visits == 0) return 1;
    const double lanes = (double)probe->active_lanes / (double)probe->node_visits;
    const double width = (double)(probe->rays.rays - probe->fallback_rays) / (double)probe->packets;
    return lanes >= PK_PAY_SHARE * width;
}

/* Rows one by one (the batch's single rays): the compact layout's unit
 * loops over its own traversal (rtc_rows.h); the complete layout, whose
 * auto traversal takes the start hint, ray by ray here. */
static void rtree_rows(const tt_accel *a, const tt_packet_rays *rays, uint32_t start_hint,
                       int any, tt_hit *hits, uint8_t *occ)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT && t->compact.rows) {
        t->compact.rows(&t->compact.c, rays, any, hits, occ);
        return;
    }
    for (uint32_t i = 0; i < rays->n; i++) {
        tt_wray w;
        tt_trace_args args = {start_hint, TT_INVALID_ID, NULL};
        tt_packet_ray_wray(rays, i, &w);
        if (any) occ[i] = (uint8_t)(rtree_occluded(a, &w, &args) != 0);
        else rtree_intersect(a, &w, &hits[i], &args);
    }
}
static void rtree_intersect_rows(const tt_accel *a, const tt_packet_rays *rays,
                                 uint32_t start_hint, tt_hit *hits)
{
    rtree_rows(a, rays, start_hint, 0, hits, NULL);
}
static void rtree_occluded_rows(const tt_accel *a, const tt_packet_rays *rays,
                                uint32_t start_hint, uint8_t *occ)
{
    rtree_rows(a, rays, start_hint, 1, NULL, occ);
}

static uint32_t rtree_locate(const tt_accel *a, const float *p) { return rt_locate(a->impl, p); }

static tt_status rtree_check(const tt_accel *a)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT) return rtc_check(a->ctx, &t->compact, a->scene);
    return rt_check(a->ctx, t, a->scene);
}

static void rtree_statistics(const tt_accel *a, tt_stat_fn fn, void *user)
{
    const rt_tree *t = a->impl;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT) {
        rtc_statistics(&t->compact, fn, user);
        fn(user, "insert_s", t->insert_s);
        fn(user, "pack_s", t->pack_s);
        /* updates keep the slack layout, compacted past this free share */
        fn(user, "update_compaction_free", 1.0 / RT_DYN_COMPACT_FREE);
        if (t->dyn) { /* what the last tt_accel_update did */
            fn(user, "update_refit", (double)t->dyn->last_refit);
            fn(user, "update_removed", (double)t->dyn->last_removed);
            fn(user, "update_inserted", (double)t->dyn->last_inserted);
            fn(user, "update_moved_far", (double)t->dyn->last_moved_far);
            fn(user, "update_tree_s", t->dyn->last_tree_s);
            fn(user, "update_layout_s", t->dyn->last_layout_s);
            fn(user, "update_repacks", (double)t->dyn->repacks);
            /* the slack layout (rtree_dyn.h): full rewrites, and what the
             * last update wrote in place */
            fn(user, "update_compactions", (double)t->dyn->compactions);
            fn(user, "update_records_written", (double)t->dyn->last_records);
            fn(user, "update_blocks_written", (double)t->dyn->last_blocks);
        }
        return;
    }
    rt_statistics(t, fn, user);
}

static size_t rtree_memory(const tt_accel *a)
{
    const rt_tree *t = a->impl;
    return t->layout == TT_RTREE_LAYOUT_COMPACT
               ? rtc_bytes(&t->compact) + (t->dyn ? rt_dyn_bytes(t->dyn) : 0)
               : rt_tree_bytes(t);
}

/* ------------------------------------------------------------- update */

/* In place for the compact layout (rtree/update/); the complete layout's
 * level-order array has no room to change, so it is rebuilt. So is a tree
 * built with split references (split_budget): the update code maps a
 * triangle to its one lane and would leave a moved triangle's other
 * references behind. */
static int rtree_updates_in_place(const tt_accel *a)
{
    const rt_tree *t = a->impl;
    return t->layout == TT_RTREE_LAYOUT_COMPACT && !t->compact.split;
}

static tt_status rtree_update(tt_accel *a, uint64_t since)
{
    rt_tree *t = a->impl;
    if (!rtree_updates_in_place(a)) return TT_ERR_UNSUPPORTED;
    if (!t->dyn) {
        /* a deformation of a tree with no pointer tree yet (fresh from a
         * build or an envelope rebuild): refit on its records alone; the
         * pointer tree and the slack layout wait for the first edit (the
         * first update made them, 89 ms of a bunny's 100-frame deformation
         * run of 256 ms) */
        const size_t moved = rt_dyn_pure_deformation(a->scene, since, a->scene->triangle_count);
        const int threads = rt_dyn_threads(a->ctx, moved);
        double cost = 0.0;
        if (moved && rt_compact_deform(a->ctx, &t->compact.c, a->scene->tri, NULL, &t->lev_rec,
                                       &t->lev_cap, threads, &cost)) {
            rt_env_after_deform(a, cost, threads);
            return TT_OK;
        }
        rt_dyn *d = tt_calloc(a->ctx, 1, sizeof *d);
        if (!d) return tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
        tt_status st = rt_dyn_from_compact(d, a->ctx, &a->options.rtree, &t->compact, a->scene);
        if (st != TT_OK) {
            rt_dyn_free(a->ctx, d);
            tt_free(a->ctx, d);
            return st;
        }
        t->dyn = d;
    }
    tt_status st = rt_dyn_update(t->dyn, a->ctx, &t->compact, a->scene, since);
    /* a rewritten layout (repack, compaction) keeps only some of the
     * kernel pointers: choose them all again */
    rtc_select(&t->compact, (int)a->options.rtree.traversal, a->isa);
    if (st != TT_OK) { /* the pointer tree may be half-changed: start over next time */
        rt_dyn_free(a->ctx, t->dyn);
        tt_free(a->ctx, t->dyn);
        t->dyn = NULL;
    } else if (t->dyn->last_deform) {
        rt_env_after_deform(a, t->dyn->last_cost, rt_dyn_threads(a->ctx, t->dyn->last_refit));
    } else { /* an edit: the envelope starts again */
        tt_free(a->ctx, t->env);
        t->env = NULL;
        t->cost_base = 0.0;
        t->since_build = 0;
    }
    return st;
}

const tt_accel_vtable tt_rtree_vtable = {
    .name = "rtree",
    .gpu = TT_ACCEL_GPU_RTREE,
    .build = rtree_build,
    .destroy = rtree_destroy,
    .intersect = rtree_intersect,
    .occluded = rtree_occluded,
    .intersect_stats = rtree_intersect_stats,
    .occluded_stats = rtree_occluded_stats,
    .intersect_packet = rtree_intersect_packet,
    .occluded_packet = rtree_occluded_packet,
    .intersect_packet_stats = rtree_intersect_packet_stats,
    .occluded_packet_stats = rtree_occluded_packet_stats,
    .packets_pay = rtree_packets_pay,
    .intersect_rows = rtree_intersect_rows,
    .occluded_rows = rtree_occluded_rows,
    .locate = rtree_locate,
    .check = rtree_check,
    .statistics = rtree_statistics,
    .memory = rtree_memory,
    .update = rtree_update,
    .updates_in_place = rtree_updates_in_place,
    /* saved structures (rtree_io.c) */
    .save = rtree_io_save,
    .load = rtree_io_load,
    .unload = rtree_io_unload,
};
