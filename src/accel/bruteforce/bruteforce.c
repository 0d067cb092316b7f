/* The bruteforce "structure": no structure at all, the ground truth. */
#include "accel/accel.h"

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/bruteforce/bruteforce_trace.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/bruteforce/bruteforce_trace.h"

static tt_status bf_build(tt_accel *a)
{
    if (a->scene->triangle_count > UINT32_MAX - 1)
        return tt_error(a->ctx, TT_ERR_INVALID_ARGUMENT, "bruteforce: too many triangles");
    return TT_OK;
}

static void bf_destroy(tt_accel *a) { (void)a; }

static void bf_intersect(const tt_accel *a, const tt_wray *r, tt_hit *hit, tt_trace_args *args)
{
    (void)args;
    tt_bf_intersect(a->scene->tri, (uint32_t)a->scene->triangle_count, r, hit, NULL);
}

static int bf_occluded(const tt_accel *a, const tt_wray *r, tt_trace_args *args)
{
    (void)args;
    return tt_bf_occluded(a->scene->tri, (uint32_t)a->scene->triangle_count, r, NULL);
}

static void bf_intersect_stats(const tt_accel *a, const tt_wray *r, tt_hit *hit,
                               tt_trace_args *args, tt_ray_stats *stats)
{
    (void)args;
    tt_bf_intersect_stats(a->scene->tri, (uint32_t)a->scene->triangle_count, r, hit, stats);
}

static int bf_occluded_stats(const tt_accel *a, const tt_wray *r, tt_trace_args *args,
                             tt_ray_stats *stats)
{
    (void)args;
    return tt_bf_occluded_stats(a->scene->tri, (uint32_t)a->scene->triangle_count, r, stats);
}

static tt_status bf_check(const tt_accel *a)
{
    (void)a;
    return TT_OK;
}

static void bf_statistics(const tt_accel *a, tt_stat_fn fn, void *user)
{
    fn(user, "triangles", (double)a->scene->triangle_count);
}

static size_t bf_memory(const tt_accel *a)
{
    (void)a;
    return 0; /* it uses the scene's own triangle array */
}

/* Saved structures: bruteforce has no arrays of its own, so its file holds
 * only the container's header (the scene's hash) and the options; saving
 * it is allowed so that every structure round-trips the same way. */
static tt_status bf_save(const tt_accel *a, struct tt_af_writer *w)
{
    (void)a;
    (void)w;
    return TT_OK;
}

static tt_status bf_load(tt_accel *a, const struct tt_af_file *f)
{
    (void)f;
    return bf_build(a);
}

static void bf_unload(tt_accel *a) { (void)a; }

const tt_accel_vtable tt_bruteforce_vtable = {
    .name = "bruteforce",
    .gpu = TT_ACCEL_GPU_NONE,
    .build = bf_build,
    .destroy = bf_destroy,
    .intersect = bf_intersect,
    .occluded = bf_occluded,
    .intersect_stats = bf_intersect_stats,
    .occluded_stats = bf_occluded_stats,
    .locate = NULL,
    .check = bf_check,
    .statistics = bf_statistics,
    .memory = bf_memory,
    .save = bf_save,
    .load = bf_load,
    .unload = bf_unload,
};
