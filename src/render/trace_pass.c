/* The parallel trace passes of a frame: OpenMP over image tiles with dynamic
 * scheduling, calling the structure's dispatch table directly (no argument
 * checks per ray, unlike the public tt_intersect1). */
#include <string.h>

#include "accel/packets.h"
#include "render/frame.h"

static void tile_bounds(const tt_frame *f, uint32_t tile, uint32_t *x0, uint32_t *y0,
                        uint32_t *x1, uint32_t *y1)
{
    uint32_t tx = tile % f->tiles_x, ty = tile / f->tiles_x;
    *x0 = tx * TT_TILE;
    *y0 = ty * TT_TILE;
    *x1 = *x0 + TT_TILE < f->width ? *x0 + TT_TILE : f->width;
    *y1 = *y0 + TT_TILE < f->height ? *y0 + TT_TILE : f->height;
}

static uint32_t saturate(uint64_t v) { return v > UINT32_MAX ? UINT32_MAX : (uint32_t)v; }

static void store_pixel_stats(tt_frame *f, size_t i, const tt_ray_stats *s)
{
    f->pixel_stats[TT_HEAT_NODES][i] = saturate(s->nodes);
    f->pixel_stats[TT_HEAT_INTERIOR][i] = saturate(s->interior);
    f->pixel_stats[TT_HEAT_LEAVES][i] = saturate(s->leaves);
    f->pixel_stats[TT_HEAT_TRIANGLES][i] = saturate(s->triangles);
    f->pixel_stats[TT_HEAT_BOXES][i] = saturate(s->boxes);
}

/* A tile's packet counts into the frame's (counting passes only). */
static void packet_stats_add(tt_packet_stats *sum, const tt_packet_stats *s)
{
#pragma omp atomic
    sum->packets += s->packets;
#pragma omp atomic
    sum->node_visits += s->node_visits;
#pragma omp atomic
    sum->active_lanes += s->active_lanes;
#pragma omp atomic
    sum->fallback_rays += s->fallback_rays;
}

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "render/trace_tile.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "render/trace_tile.h"
#undef TT_STATS

static long tile_count(const tt_frame *f) { return (long)f->tiles_x * (long)f->tiles_y; }

void tt_frame_trace_primary(tt_frame *f)
{
    const long n = tile_count(f);
#pragma omp parallel for schedule(dynamic) num_threads(f->threads)
    for (long tile = 0; tile < n; tile++) primary_tile(f, (uint32_t)tile, NULL);
}

void tt_frame_trace_shadow(tt_frame *f)
{
    const long n = tile_count(f);
#pragma omp parallel for schedule(dynamic) num_threads(f->threads)
    for (long tile = 0; tile < n; tile++) shadow_tile(f, (uint32_t)tile, NULL);
}

typedef void (*stats_tile_fn)(tt_frame *f, uint32_t tile, tt_ray_stats *sum);

/* Each thread sums into its own tt_ray_stats (no sharing of counters in the
 * hot loop) and adds it to *sum once at the end. The counting passes are not
 * the timed ones, so one loop serves both ray kinds through a pointer. */
static void trace_stats(tt_frame *f, stats_tile_fn tile_fn, tt_ray_stats *sum)
{
    const long n = tile_count(f);
    memset(sum, 0, sizeof *sum);
#pragma omp parallel num_threads(f->threads)
    {
        tt_ray_stats local;
        memset(&local, 0, sizeof local);
#pragma omp for schedule(dynamic)
        for (long tile = 0; tile < n; tile++) tile_fn(f, (uint32_t)tile, &local);
#pragma omp critical(tt_render_stats_reduce)
        tt_ray_stats_add(sum, &local);
    }
}

void tt_frame_trace_primary_stats(tt_frame *f, tt_ray_stats *sum)
{
    trace_stats(f, primary_tile_stats, sum);
}

void tt_frame_trace_shadow_stats(tt_frame *f, tt_ray_stats *sum)
{
    trace_stats(f, shadow_tile_stats, sum);
}

/* ---- tiles of a frame traced in parts (frame.h; the MPI renderer) ---- */

uint32_t tt_frame_tile_count(const tt_frame *f) { return f->tiles_x * f->tiles_y; }

void tt_frame_tile_rect(const tt_frame *f, uint32_t tile, uint32_t *x0, uint32_t *y0,
                        uint32_t *x1, uint32_t *y1)
{
    tile_bounds(f, tile, x0, y0, x1, y1);
}

static void trace_list_stats(tt_frame *f, const uint32_t *tiles, long n, stats_tile_fn fn,
                             tt_ray_stats *sum)
{
#pragma omp parallel num_threads(f->threads)
    {
        tt_ray_stats local;
        memset(&local, 0, sizeof local);
#pragma omp for schedule(dynamic)
        for (long i = 0; i < n; i++) fn(f, tiles[i], &local);
#pragma omp critical(tt_render_stats_reduce)
        tt_ray_stats_add(sum, &local);
    }
}

void tt_frame_trace_tiles(tt_frame *f, const uint32_t *tiles, uint32_t count, int shadows,
                          tt_ray_stats *counts, double *times)
{
    const long n = (long)count;
    if (counts) {
        trace_list_stats(f, tiles, n, primary_tile_stats, &counts[0]);
        if (shadows) trace_list_stats(f, tiles, n, shadow_tile_stats, &counts[1]);
    }
    double t0 = tt_now();
#pragma omp parallel for schedule(dynamic) num_threads(f->threads)
    for (long i = 0; i < n; i++) primary_tile(f, tiles[i], NULL);
    double t1 = tt_now();
    if (shadows) {
#pragma omp parallel for schedule(dynamic) num_threads(f->threads)
        for (long i = 0; i < n; i++) shadow_tile(f, tiles[i], NULL);
    }
    times[0] += t1 - t0;
    times[1] += tt_now() - t1;
}
