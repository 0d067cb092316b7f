/* One frame's working state, shared by the trace passes (trace_pass.c), the
 * shading (shade.c) and the driver (render.c). The passes write per-pixel
 * results into flat arrays; the public hit buffer and image are built from
 * them afterwards, outside the timed region. */
#ifndef TT_RENDER_FRAME_H
#define TT_RENDER_FRAME_H

#include "accel/accel.h"
#include "render/camera.h"

/* Square tiles are the unit of parallel work: small enough that dynamic
 * scheduling balances cheap (background) and expensive tiles, large enough
 * that neighbouring rays share cache lines of the structure. */
#define TT_TILE 16
#define TT_HEAT_METRIC_COUNT 5

typedef struct tt_frame {
    const tt_scene *scene;
    const tt_accel *accel;
    const tt_camera *camera;
    tt_camera_basis basis;
    uint32_t width, height;
    uint32_t tiles_x, tiles_y;
    int threads;
    float eps;          /* shadow-ray offset: 1e-4 * scene diagonal           */
    uint32_t eye_hint;  /* tt_accel_locate(eye), once per frame               */
    int caster_hint;    /* shadow rays start at the last caster's node       */
    uint32_t packets;   /* TT_PACKETS_*; OFF where the structure has none    */
    /* the counting passes' per-packet counts (packets, node visits, active
     * lanes, fallback rays), summed over the threads */
    tt_packet_stats packet_primary, packet_shadow;
    uint32_t *prim;     /* per pixel: triangle id or TT_INVALID_ID            */
    float *t;           /* per pixel: hit distance or +inf                    */
    uint32_t *end_hint; /* per pixel: where the primary ray ended             */
    uint8_t *shadow;    /* per pixel: 1 if the shadow ray was occluded        */
    /* per pixel counts of the primary ray, indexed by tt_heat_metric; all
     * NULL unless the caller asked for them */
    uint32_t *pixel_stats[TT_HEAT_METRIC_COUNT];
} tt_frame;

/* The timed passes: the fast traversal variants only. */
void tt_frame_trace_primary(tt_frame *f);
void tt_frame_trace_shadow(tt_frame *f);

/* The counting passes: the same rays through intersect_stats /
 * occluded_stats, each thread summing its own tt_ray_stats, reduced into
 * *sum at the end. The primary pass also fills pixel_stats when present. */
void tt_frame_trace_primary_stats(tt_frame *f, tt_ray_stats *sum);
void tt_frame_trace_shadow_stats(tt_frame *f, tt_ray_stats *sum);

/* The shaded 8-bit RGB image from the frame's per-pixel results. */
void tt_frame_shade(const tt_frame *f, int shadows, uint8_t *rgb);

/* ---- A frame traced in parts (the MPI renderer, cli/mpi/): each process
 * traces some tiles; one gathers every tile's per-pixel results into its
 * frame and makes the result, byte for byte what tt_render gives (a tile's
 * results never depend on which process or thread traced it). ---- */

/* Validates as tt_render does (CPU only) and sets up f with its per-pixel
 * arrays (pixel_stats too with keep_pixel_stats); tt_frame_close frees. */
tt_status tt_frame_open(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                        const tt_camera *camera, const tt_render_options *o, tt_frame *f);
void tt_frame_close(tt_context *ctx, tt_frame *f);
uint32_t tt_frame_tile_count(const tt_frame *f);
void tt_frame_tile_rect(const tt_frame *f, uint32_t tile, uint32_t *x0, uint32_t *y0,
                        uint32_t *x1, uint32_t *y1);
/* Traces tiles[0..n) on the frame's threads: with `counts` not NULL the
 * counting variants first (adding into counts[0] primary, counts[1]
 * shadow, and pixel_stats), then the fast primary and shadow passes, timed
 * into times[0], times[1] (seconds, added). */
void tt_frame_trace_tiles(tt_frame *f, const uint32_t *tiles, uint32_t n, int shadows,
                          tt_ray_stats *counts, double *times);
/* The result of a frame whose per-pixel arrays are complete (hits, image,
 * pixel counts as options ask), its summary `s` with the counts filled
 * in; f's arrays stay f's. */
tt_status tt_frame_result(tt_context *ctx, const tt_frame *f, const tt_render_options *o,
                          const tt_render_summary *s, tt_render_result **out);

#endif
