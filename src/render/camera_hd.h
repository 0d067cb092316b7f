/* The per-ray camera arithmetic of ../shared/scenes/README.md as TT_HD
 * functions: the CPU renderer and the public per-ray calls (camera.c) and
 * the CUDA tracer (src/cuda/) all build primary and shadow rays through
 * these two functions, so a GPU hit buffer is computed from bit-identical
 * rays (the CUDA code is compiled without FMA contraction, see
 * cmake/cuda.cmake, so the same float operations round the same way). */
#ifndef TT_RENDER_CAMERA_HD_H
#define TT_RENDER_CAMERA_HD_H

#include <stdint.h>

#include "geometry/hd.h"
#include "geometry/vec3.h"
#include "treetrace/treetrace.h"

/* The per-image constants of the conventions' camera formula, computed once
 * on the host (tt_camera_basis_init). */
typedef struct tt_camera_basis {
    tt_vec3 eye, forward, right, up;
    float h, aspect;
    uint32_t width, height;
} tt_camera_basis;

/* The primary ray of pixel (x, y); the caller guarantees x < width, y < height. */
TT_HD void tt_camera_basis_ray(const tt_camera_basis *b, uint32_t x, uint32_t y, tt_ray *out)
{
    float u = (2.0f * ((float)x + 0.5f) / (float)b->width - 1.0f) * b->h * b->aspect;
    float v = (1.0f - 2.0f * ((float)y + 0.5f) / (float)b->height) * b->h;
    tt_vec3 d = tt_v3_add(b->forward, tt_v3_add(tt_v3_scale(b->right, u), tt_v3_scale(b->up, v)));
    d = tt_v3_normalize(d);
    out->org[0] = b->eye.x;
    out->org[1] = b->eye.y;
    out->org[2] = b->eye.z;
    out->dir[0] = d.x;
    out->dir[1] = d.y;
    out->dir[2] = d.z;
    out->tmin = 0.0f;
    out->tmax = TT_INF;
}

/* The shadow ray of a primary hit at distance t on the triangle with the 9
 * floats tri, towards the point light, the origin offset by eps along the
 * normal facing the primary ray's origin. */
TT_HD void tt_shadow_ray_from(const float *tri, const float *light, float eps,
                              const tt_ray *primary, float t, tt_ray *out)
{
    tt_vec3 v0 = tt_v3_load(tri), v1 = tt_v3_load(tri + 3), v2 = tt_v3_load(tri + 6);
    tt_vec3 dir = tt_v3_load(primary->dir);
    tt_vec3 n = tt_v3_normalize(tt_v3_cross(tt_v3_sub(v1, v0), tt_v3_sub(v2, v0)));
    if (tt_v3_dot(n, dir) > 0.0f) n = tt_v3_scale(n, -1.0f);
    tt_vec3 p = tt_v3_add(tt_v3_load(primary->org), tt_v3_scale(dir, t));
    tt_vec3 o = tt_v3_add(p, tt_v3_scale(n, eps));
    tt_vec3 to_light = tt_v3_sub(tt_v3_load(light), o);
    float dist = tt_v3_length(to_light);
    tt_vec3 d = tt_v3_normalize(to_light);
    out->org[0] = o.x;
    out->org[1] = o.y;
    out->org[2] = o.z;
    out->dir[0] = d.x;
    out->dir[1] = d.y;
    out->dir[2] = d.z;
    out->tmin = 0.0f;
    out->tmax = dist * (1.0f - 1e-4f);
}

#endif
