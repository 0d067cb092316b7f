/* The "wbvh" structure's vtable: options, build (binary SAH tree, then the
 * collapse into mixed M-wide records), the traces, and the compact
 * layout's check, statistics and memory (shared with the R-tree, rtc.h).
 * Options: M is options.rtree.M (0: 16, as the R-tree's compact layout);
 * the R-tree's other options do not apply. Rays go one by one (no packet
 * kernel: the batch calls trace them ray by ray). */
#include "accel/wbvh/wbvh.h"

#include <string.h>

#include "accel/rtree/build/rtree_bulk.h" /* rt_bulk_threads */
#include "accel/rtree/rtree_box.h"

static void wbvh_destroy(tt_accel *a)
{
    wbvh_tree *w = a->impl;
    if (!w) return;
    rtc_free(a->ctx, &w->t);
    tt_free(a->ctx, w);
    a->impl = NULL;
}

static tt_status wbvh_build(tt_accel *a)
{
    if (a->options.rtree.M == 0) a->options.rtree.M = 16;
    const int M = a->options.rtree.M;
    if (M < 4 || M > TT_RT_MAX_M)
        return tt_error(a->ctx, TT_ERR_INVALID_ARGUMENT,
                        "wbvh: M = %d is out of range (4 <= M <= %d)", M, TT_RT_MAX_M);
    const tt_scene *scene = a->scene;
    if (scene->triangle_count >= (size_t)1 << 31)
        return tt_error(a->ctx, TT_ERR_INVALID_ARGUMENT, "wbvh: %zu triangles, at most 2^31",
                        scene->triangle_count);
    const uint32_t T = (uint32_t)scene->triangle_count;
    wbvh_tree *w = tt_calloc(a->ctx, 1, sizeof *w);
    if (!w) return tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY, "wbvh: out of memory");
    a->impl = w;
    w->t.m = 1; /* leaves hold 1..M triangles (rtc_check) */
    const double t0 = tt_now();
    float *tri_box = tt_alloc_array(a->ctx, T ? T : 1, 6 * sizeof(float));
    if (!tri_box) return tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY, "wbvh: out of memory");
    for (uint32_t i = 0; i < T; i++) {
        const float *v = scene->tri + 9 * (size_t)i;
        float *bx = tri_box + 6 * (size_t)i;
        for (int k = 0; k < 3; k++) {
            bx[k] = rt_min(rt_min(v[k], v[3 + k]), v[6 + k]);
            bx[k + 3] = rt_max(rt_max(v[k], v[3 + k]), v[6 + k]);
        }
    }
    wbvh_bin_tree b;
    /* leaves of up to M triangles (up to 2 blocks at M = 16): capped at
     * one block (8), Sibenik and the bunny traced alike, the Cornell box
     * 3-8% slower (notes/wbvh.md) */
    tt_status st =
        wbvh_build_binary(a->ctx, tri_box, T, (uint32_t)M, rt_bulk_threads(a->ctx), &b);
    tt_free(a->ctx, tri_box);
    const double t1 = tt_now();
    if (st == TT_OK) st = wbvh_pack(a->ctx, &b, scene->tri, T, (uint32_t)M, &w->t);
    wbvh_bin_free(a->ctx, &b);
    if (st == TT_OK) wbvh_select(&w->t, a->isa);
    w->build_s = t1 - t0;
    w->pack_s = tt_now() - t1;
    return st;
}

static void wbvh_intersect(const tt_accel *a, const tt_wray *r, tt_hit *hit, tt_trace_args *args)
{
    (void)args;
    const wbvh_tree *w = a->impl;
    w->t.trace(&w->t.c, r, 0, hit, NULL);
}

static int wbvh_occluded(const tt_accel *a, const tt_wray *r, tt_trace_args *args)
{
    (void)args;
    const wbvh_tree *w = a->impl;
    return w->t.trace(&w->t.c, r, 1, NULL, NULL);
}

static void wbvh_intersect_stats(const tt_accel *a, const tt_wray *r, tt_hit *hit,
                                 tt_trace_args *args, tt_ray_stats *stats)
{
    (void)args;
    const wbvh_tree *w = a->impl;
    w->t.trace_stats(&w->t.c, r, 0, hit, stats);
}

static int wbvh_occluded_stats(const tt_accel *a, const tt_wray *r, tt_trace_args *args,
                               tt_ray_stats *stats)
{
    (void)args;
    const wbvh_tree *w = a->impl;
    return w->t.trace_stats(&w->t.c, r, 1, NULL, stats);
}

/* Rows one by one (the batch's single rays): the unit's loop over its own
 * traversal (rtree/trace/rtc_rows.h); no start hints. */
static void wbvh_intersect_rows(const tt_accel *a, const tt_packet_rays *rays,
                                uint32_t start_hint, tt_hit *hits)
{
    (void)start_hint;
    const wbvh_tree *w = a->impl;
    w->t.rows(&w->t.c, rays, 0, hits, NULL);
}

static void wbvh_occluded_rows(const tt_accel *a, const tt_packet_rays *rays,
                               uint32_t start_hint, uint8_t *occ)
{
    (void)start_hint;
    const wbvh_tree *w = a->impl;
    w->t.rows(&w->t.c, rays, 1, NULL, occ);
}

static tt_status wbvh_check(const tt_accel *a)
{
    const wbvh_tree *w = a->impl;
    return rtc_check(a->ctx, &w->t, a->scene);
}

/* The compact layout's statistics (rtc_stats.c) less its per-level rows,
 * which mean nothing here (every record is level 0), plus the leaves'
 * depths. */
typedef struct stat_filter {
    tt_stat_fn fn;
    void *user;
} stat_filter;

static void drop_levels(void *user, const char *key, double value)
{
    const stat_filter *f = user;
    if (strncmp(key, "level", 5) == 0 || strcmp(key, "height") == 0 ||
        strcmp(key, "interior_fill") == 0)
        return;
    f->fn(f->user, key, value);
}

static void leaf_depths(const tt_rtc *c, uint32_t n, uint32_t d, double *sum, double *count,
                        double *entries)
{
    const float *rec = tt_rtc_node(c, n);
    const uint32_t *ref = tt_rtc_child(c, rec);
    *entries += tt_rtc_count(c, rec);
    for (uint32_t i = 0; i < tt_rtc_count(c, rec); i++) {
        if (tt_rtc_is_leaf(ref[i])) {
            *sum += d;
            *count += 1.0;
        } else {
            leaf_depths(c, ref[i], d + 1, sum, count, entries);
        }
    }
}

static void wbvh_statistics(const tt_accel *a, tt_stat_fn fn, void *user)
{
    const wbvh_tree *w = a->impl;
    stat_filter f = {fn, user};
    rtc_statistics(&w->t, drop_levels, &f);
    double sum = 0.0, count = 0.0, entries = 0.0;
    leaf_depths(&w->t.c, 0, 1, &sum, &count, &entries);
    fn(user, "interior_fill", entries / w->t.c.nodes); /* leaves and nodes */
    fn(user, "depth", w->t.c.height);
    fn(user, "leaf_depth_mean", count > 0 ? sum / count : 0.0);
    fn(user, "build_s", w->build_s);
    fn(user, "pack_s", w->pack_s);
}

static size_t wbvh_memory(const tt_accel *a)
{
    const wbvh_tree *w = a->impl;
    return rtc_bytes(&w->t);
}

const tt_accel_vtable tt_wbvh_vtable = {
    .name = "wbvh",
    .build = wbvh_build,
    .destroy = wbvh_destroy,
    .intersect = wbvh_intersect,
    .occluded = wbvh_occluded,
    .intersect_stats = wbvh_intersect_stats,
    .occluded_stats = wbvh_occluded_stats,
    .intersect_rows = wbvh_intersect_rows,
    .occluded_rows = wbvh_occluded_rows,
    .check = wbvh_check,
    .statistics = wbvh_statistics,
    .memory = wbvh_memory,
    .no_save = "wbvh: saving is not implemented (its mixed records would need their own loader "
               "checks); rebuild it",
};
