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

#endif
