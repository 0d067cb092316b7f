/* When rays are worth tracing as a packet: the automatic choice of the batch
 * calls (batch.c) and the renderer (render/trace_tile.h), in one place. */
#ifndef TT_ACCEL_PACKETS_H
#define TT_ACCEL_PACKETS_H

#include <math.h>
#include <stdint.h>

#include "accel/accel.h"
#include "geometry/ray.h"

/* Packets of fewer rays go ray by ray: below this a packet's per-node work
 * is shared by too few rays. */
#define TT_PACKET_MIN 16u
/* The widest spread of a coherent item's unit directions, per axis (about
 * 30 degrees); 1.0 was measured too: shadow rays gained little under auto and
 * ambient-occlusion rays lost more (bunny, conference, 2026-12-02). */
#define TT_PACKET_SPREAD 0.5f

/* Coherent: the rays' normalised directions fit in a box no wider than 0.5
 * on every axis (about a 30 degree cone): a camera tile, or the shadow rays
 * of a tile towards a distant light (a near one: tt_end_box). Ambient-
 * occlusion and diffuse rays are not, and go ray by ray. The box is grown
 * one direction at a time (a NaN direction, from a ray the contract
 * refuses, leaves it as it was); tt_packet_coherent grows the same boxes
 * four rows at a time. */
typedef struct tt_dir_box {
    float lo[3], hi[3];
    uint32_t n;
} tt_dir_box;

static inline void tt_dir_box_init(tt_dir_box *b)
{
    for (int k = 0; k < 3; k++) b->lo[k] = 2.0f, b->hi[k] = -2.0f;
    b->n = 0;
}
static inline void tt_dir_box_add(tt_dir_box *b, const float *d)
{
    const float s = 1.0f / sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) {
        const float x = d[k] * s;
        b->lo[k] = x < b->lo[k] ? x : b->lo[k];
        b->hi[k] = x > b->hi[k] ? x : b->hi[k];
    }
    b->n++;
}
/* (at least 8 directions: a judgement from fewer is a guess) */
static inline int tt_dir_box_coherent(const tt_dir_box *b)
{
    return b->n >= TT_PACKET_MIN / 2 && b->hi[0] - b->lo[0] <= TT_PACKET_SPREAD &&
           b->hi[1] - b->lo[1] <= TT_PACKET_SPREAD && b->hi[2] - b->lo[2] <= TT_PACKET_SPREAD;
}

/* Shadow rays to one light share their far end, not their direction (a
 * tile's hits see the light at angles far apart): rays whose ends
 * org + tmax dir bunch together form a frustum narrowing to that end, which
 * a packet's interval test culls as well as a cone. Together means within
 * TT_PACKET_SPREAD of the shortest ray's length on every axis: seen from
 * any origin, the end region then spans no more than the direction box
 * admits (a point light's rays end within float rounding of it; a light of
 * some size, soft shadows, keeps its rays together too). Random directions
 * (ambient occlusion, diffuse bounces) end at least twice their shortest
 * length apart and fail it. Any ray of infinite or NaN tmax, or a zero
 * length, makes the test fail.
 * The bound was a hundredth until 2026-12-03: shadow rays to a sphere light
 * (ends jittered over a radius of 0.2-3% of the scene's diagonal, items'
 * end width 0.01-0.9 of their shortest ray) went ray by ray under auto, while
 * packets traced them 1.3-1.9x faster than single rays (sibenik, conference,
 * Cornell, bunny; R-tree and kd-tree); at widths of 1-8 packets still gained
 * 1.1-1.4x on most, and lost from about 10 on (/work/notes/pkauto.md). */
typedef struct tt_end_box {
    float lo[3], hi[3];
    float shortest;
    int open;
} tt_end_box;

static inline void tt_end_box_init(tt_end_box *b)
{
    for (int k = 0; k < 3; k++) b->lo[k] = INFINITY, b->hi[k] = -INFINITY;
    b->shortest = INFINITY;
    b->open = 0;
}
static inline void tt_end_box_add(tt_end_box *b, const float *org, const float *dir, float tmax)
{
    if (!(tmax < INFINITY)) {
        b->open = 1;
        return;
    }
    const float len = tmax * sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    b->shortest = len < b->shortest ? len : b->shortest;
    for (int k = 0; k < 3; k++) {
        const float e = org[k] + tmax * dir[k];
        b->lo[k] = e < b->lo[k] ? e : b->lo[k];
        b->hi[k] = e > b->hi[k] ? e : b->hi[k];
    }
}
static inline int tt_end_box_converge(const tt_end_box *b)
{
    if (b->open || !(b->shortest > 0.0f) || !(b->shortest < INFINITY)) return 0;
    for (int k = 0; k < 3; k++)
        if (!(b->hi[k] - b->lo[k] <= TT_PACKET_SPREAD * b->shortest)) return 0;
    return 1;
}

/* The one rule, over the two boxes of the same rays: within a cone, or
 * ending at one point. */
static inline int tt_packet_boxes_coherent(const tt_dir_box *d, const tt_end_box *e)
{
    return tt_dir_box_coherent(d) || tt_end_box_converge(e);
}

/* The rule for a packet's rows (the batch calls' items, after the ray
 * check; the renderer's tiles), judged from a sample: TT_PACKET_RUNS runs of
 * TT_PACKET_RUN consecutive rows, the first and the last run at the two
 * ends of the rows and the others evenly between (a tile's corners, a
 * run's two ends: where the boxes' extremes lie for camera and shadow
 * rays). Rows of fewer than TT_PACKET_MIN rays are not a packet.
 *
 * Why a sample of the rows, computed eight lanes at once (packets.c): the
 * rule had been a walk over every 8th ray of the item before its rows were
 * gathered, each sample a square root and a division in a chain, about 17
 * instructions a ray of a 256-ray item (callgrind, Cornell shadow rays: 195
 * auto vs 178 on) and 10-25% of a shadow batch's time, while every item
 * of every shared and unseen view's point-light shadow batch passed it.
 * The rows are gathered for either path anyway (packets, or the rows entry
 * of single rays); an incoherent item (ambient occlusion) pays the 32
 * sampled rows, about 3 instructions a ray of the item. */
#define TT_PACKET_RUN 8u
#define TT_PACKET_RUNS 4u
int tt_packet_coherent(const tt_packet_rays *p);

#endif
