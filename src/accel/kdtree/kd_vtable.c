/* The kd-tree with sparse boxes (Havran & Bittner 2007) as a treetrace
 * structure: the dispatch table and its glue. */
#include "accel/kdtree/kd_tree.h"
#include "accel/kdtree/kd_io.h"
#include "accel/kdtree/kd_blocks.h"

#include "accel/kdtree/trace/kd_trace_cpu.h"
#include "accel/kdtree/trace/kd_packet_cpu.h"

int tt_kdtree_dmin(const tt_kdtree_options *o)
{
    if (!o) return 0;
    if (o->dmin != 0) return o->dmin;
    return o->traversal == TT_KD_HTR ? -1 : TT_KD_DMIN_BOXES;
}

static tt_status kd_build(tt_accel *a)
{
    tt_kdtree *t = NULL;
    /* d_min = 0 (auto) resolves here, so the accel's options say what the
     * tree has: no boxes for HTR, which never reads them (memory), else
     * Havran & Bittner's every 4 levels. */
    a->options.kdtree.dmin = tt_kdtree_dmin(&a->options.kdtree);
    tt_status st = tt_kdtree_build(a->ctx, a->scene, &a->options.kdtree, &t);
    a->impl = t;
    if (st == TT_OK && t)
        st = tt_kdtree_use_isa(a->ctx, t, a->isa, a->scene->tri, a->scene->triangle_count);
    return st;
}

static void kd_destroy(tt_accel *a)
{
    tt_kdtree_destroy(a->ctx, a->impl);
    a->impl = NULL;
}

static const tt_kdtree *tree(const tt_accel *a) { return a->impl; }

static uint32_t hint_of(const tt_trace_args *args)
{
    return args ? args->start_hint : TT_INVALID_ID;
}

/* The last caster travels in args->end_hint on input (the renderer hands
 * back what the previous shadow ray returned there); only with the option. */
static uint32_t caster_of(const tt_accel *a, const tt_trace_args *args)
{
    return (args && a->options.kdtree.shadow_caster_hint) ? args->end_hint : TT_INVALID_ID;
}

static void kd_intersect(const tt_accel *a, const tt_wray *r, tt_hit *hit, tt_trace_args *args)
{
    uint32_t end;
    tree(a)->fast.intersect(&tree(a)->fast_view, a->options.kdtree.traversal, r, hint_of(args), hit,
                            &end);
    if (args) args->end_hint = end;
}

static int kd_occluded(const tt_accel *a, const tt_wray *r, tt_trace_args *args)
{
    uint32_t end;
    int o = tree(a)->fast.occluded(&tree(a)->fast_view, a->options.kdtree.traversal, r, hint_of(args),
                                   caster_of(a, args), &end);
    if (args) args->end_hint = end;
    return o;
}

static void kd_intersect_stats(const tt_accel *a, const tt_wray *r, tt_hit *hit,
                               tt_trace_args *args, tt_ray_stats *stats)
{
    uint32_t end;
    tt_kd_cpu_intersect_stats(&tree(a)->view, a->options.kdtree.traversal, r, hint_of(args), hit,
                              &end, stats);
    if (args) args->end_hint = end;
}

static int kd_occluded_stats(const tt_accel *a, const tt_wray *r, tt_trace_args *args,
                             tt_ray_stats *stats)
{
    uint32_t end;
    int o = tt_kd_cpu_occluded_stats(&tree(a)->view, a->options.kdtree.traversal, r, hint_of(args),
                                     caster_of(a, args), &end, stats);
    if (args) args->end_hint = end;
    return o;
}

/* Packets (kd_packet.h): the ISA's packet kernel for HTR (the default
 * traversal); other traversals and ISAs without a kernel trace the rays
 * one by one through the single-ray entries, so the answers are the same
 * either way. */
static void kd_packet(const tt_accel *a, const tt_packet_rays *rays, int any, tt_hit *hits,
                      uint8_t *occ, tt_packet_stats *stats)
{
    const int trav = a->options.kdtree.traversal;
    /* the kernel tests the leaves' blocks: the block view (the ISAs with
     * a packet kernel have one once the tree is built or loaded) */
    const tt_kd_packet_fn fn =
        (trav != TT_KD_BTR && trav != TT_KD_SLTR && trav != TT_KD_SEQ &&
         tree(a)->fast_view.blocks)
            ? tt_kd_packet_kernel(a->isa, stats != NULL)
            : NULL;
    if (fn) {
        fn(&tree(a)->fast_view, &tree(a)->view, rays, any, hits, occ, stats);
        return;
    }
    for (uint32_t i = 0; i < rays->n; i++) {
        tt_wray w;
        tt_packet_ray_wray(rays, i, &w);
        if (stats) {
            stats->fallback_rays++;
            if (any) occ[i] = (uint8_t)(kd_occluded_stats(a, &w, NULL, &stats->rays) != 0);
            else kd_intersect_stats(a, &w, &hits[i], NULL, &stats->rays);
        } else {
            if (any) occ[i] = (uint8_t)(kd_occluded(a, &w, NULL) != 0);
            else kd_intersect(a, &w, &hits[i], NULL);
        }
    }
}
/* Packets pay only with the kernel, which is HTR's: BTR, SLTR and SEQ stay
 * ray by ray in the batch calls and the renderer, where they take start and
 * caster hints (the packet entries have none). */
static int kd_packets_for(const tt_accel *a)
{
    const int trav = a->options.kdtree.traversal;
    return trav != TT_KD_BTR && trav != TT_KD_SLTR && trav != TT_KD_SEQ;
}
static void kd_intersect_packet(const tt_accel *a, const tt_packet_rays *rays, tt_hit *hits)
{
    kd_packet(a, rays, 0, hits, NULL, NULL);
}
static void kd_occluded_packet(const tt_accel *a, const tt_packet_rays *rays, uint8_t *occ)
{
    kd_packet(a, rays, 1, NULL, occ, NULL);
}
static void kd_intersect_packet_stats(const tt_accel *a, const tt_packet_rays *rays,
                                      tt_hit *hits, tt_packet_stats *stats)
{
    kd_packet(a, rays, 0, hits, NULL, stats);
}
static void kd_occluded_packet_stats(const tt_accel *a, const tt_packet_rays *rays,
                                     uint8_t *occ, tt_packet_stats *stats)
{
    kd_packet(a, rays, 1, NULL, occ, stats);
}

/* Rows one by one (the batch's single rays): the kernel unit's loop over
 * its own traversal (kd_rows.h), every traversal, start hint included. */
static void kd_intersect_rows(const tt_accel *a, const tt_packet_rays *rays, uint32_t start_hint,
                              tt_hit *hits)
{
    tree(a)->fast.rows(&tree(a)->fast_view, a->options.kdtree.traversal, rays, 0, start_hint,
                       hits, NULL);
}
static void kd_occluded_rows(const tt_accel *a, const tt_packet_rays *rays, uint32_t start_hint,
                             uint8_t *occ)
{
    tree(a)->fast.rows(&tree(a)->fast_view, a->options.kdtree.traversal, rays, 1, start_hint,
                       NULL, occ);
}

static uint32_t kd_locate(const tt_accel *a, const float *p) { return tt_kdtree_locate(tree(a), p); }

static tt_status kd_check(const tt_accel *a) { return tt_kdtree_check(a->ctx, a->scene, tree(a)); }

static void kd_statistics(const tt_accel *a, tt_stat_fn fn, void *user)
{
    const tt_kdtree *t = tree(a);
    size_t tris = a->scene->triangle_count;
    fn(user, "N_B", (double)t->aug_count);
    fn(user, "M_KD", (double)tt_kdtree_memory(t));
    fn(user, "nodes", (double)t->nodes_total);
    fn(user, "interior", (double)t->interior);
    fn(user, "leaves", (double)t->leaves);
    fn(user, "empty_leaves", (double)t->empty_leaves);
    fn(user, "depth_max", (double)t->depth_max);
    fn(user, "depth_mean", t->depth_mean);
    fn(user, "depth_limit", (double)t->max_depth);
    fn(user, "dmin", (double)t->dmin);
    fn(user, "references", (double)t->ref_count);
    fn(user, "refs_per_triangle", tris ? (double)t->ref_count / (double)tris : 0.0);
    /* 1 when the reference budget (kd_build.c) stopped some split: the
     * tree is then shallower than the SAH alone would have made it. */
    fn(user, "ref_budget_reached", (double)t->ref_budget_hit);
    fn(user, "sah_cost", t->sah_cost);
    fn(user, "triangles", (double)tris);
}

/* The tree (M_KD, the papers' measure) and the engine's leaf blocks. */
static size_t kd_memory(const tt_accel *a)
{
    return tt_kdtree_memory(tree(a)) + tt_kdtree_blocks_memory(tree(a));
}

const tt_kdtree *tt_kdtree_of(const tt_accel *a)
{
    return (a && a->vt == &tt_kdtree_vtable) ? a->impl : NULL;
}

const tt_accel_vtable tt_kdtree_vtable = {
    .name = "kdtree",
    .caps = TT_CAP_CASTER_HINT,
    .gpu = TT_ACCEL_GPU_KDTREE,
    .build = kd_build,
    .destroy = kd_destroy,
    .intersect = kd_intersect,
    .occluded = kd_occluded,
    .intersect_stats = kd_intersect_stats,
    .occluded_stats = kd_occluded_stats,
    .intersect_packet = kd_intersect_packet,
    .occluded_packet = kd_occluded_packet,
    .intersect_packet_stats = kd_intersect_packet_stats,
    .occluded_packet_stats = kd_occluded_packet_stats,
    .intersect_rows = kd_intersect_rows,
    .occluded_rows = kd_occluded_rows,
    .packets_for = kd_packets_for,
    .locate = kd_locate,
    .check = kd_check,
    .statistics = kd_statistics,
    .memory = kd_memory,
    /* saved structures (kd_io.c) */
    .save = kd_io_save,
    .load = kd_io_load,
    .unload = kd_io_unload,
};
