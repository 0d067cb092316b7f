/* When rays are worth tracing as a packet: the automatic choice of the batch
 * calls (batch.c) and the renderer (render/trace_tile.h), in one place. */
#ifndef TT_ACCEL_PACKETS_H
#define TT_ACCEL_PACKETS_H

#include <math.h>
#include <stdint.h>

#include "geometry/ray.h"

/* Packets of fewer rays go ray by ray: below this a packet's per-node work
 * is shared by too few rays. */
#define TT_PACKET_MIN 16u

/* Coherent: the rays' normalised directions fit in a box no wider than 0.5
 * on every axis (about a 30 degree cone): a camera tile, or the shadow rays
 * of a tile towards one light. Ambient-occlusion and diffuse rays are not,
 * and go ray by ray, so an incoherent batch pays only this pass over its
 * directions. */
static inline int tt_packet_coherent(const tt_wray *w, uint32_t n)
{
    if (n < TT_PACKET_MIN) return 0;
    float lo[3] = {2.0f, 2.0f, 2.0f}, hi[3] = {-2.0f, -2.0f, -2.0f};
    for (uint32_t i = 0; i < n; i++) {
        const float *d = w[i].dir;
        const float s = 1.0f / sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; k++) {
            const float x = d[k] * s;
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    }
    return hi[0] - lo[0] <= 0.5f && hi[1] - lo[1] <= 0.5f && hi[2] - lo[2] <= 0.5f;
}

#endif
