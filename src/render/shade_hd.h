/* The shading of one pixel as a TT_HD function: the CPU (shade.c) and the
 * GPU (a kernel in src/cuda/) shade the same per-pixel results through it,
 * so their images are byte-identical. A deliberately simple shading, enough
 * to see the geometry and the shadows: diffuse light from the point light
 * where the shadow ray got through, a faint headlight term everywhere (so
 * shadowed parts keep their shape), and a dark grey background. */
#ifndef TT_RENDER_SHADE_HD_H
#define TT_RENDER_SHADE_HD_H

#include <math.h>
#include <stdint.h>

#include "render/camera_hd.h"

TT_HD uint8_t tt_shade_byte(float linear)
{
    /* sqrt approximates the display gamma, so dim regions stay readable */
    float v = sqrtf(linear < 0.0f ? 0.0f : (linear > 1.0f ? 1.0f : linear));
    return (uint8_t)(v * 255.0f + 0.5f);
}

/* Pixel (x, y) whose primary ray hit triangle prim (TT_INVALID_ID: a miss)
 * at distance t, the shadow ray occluded when `shadow` (only looked at with
 * shadows set). tri: the scene's triangles in load order; light used when
 * has_light. Writes 3 bytes of RGB. */
TT_HD void tt_shade_pixel(const tt_camera_basis *b, const float *tri, const float *light,
                          int has_light, int shadows, uint32_t x, uint32_t y, uint32_t prim,
                          float t, uint8_t shadow, uint8_t *out)
{
    const float background[3] = {0.025f, 0.025f, 0.03f};
    const float albedo[3] = {0.90f, 0.84f, 0.74f};
    if (prim == TT_INVALID_ID) {
        for (int k = 0; k < 3; k++) out[k] = tt_shade_byte(background[k]);
        return;
    }
    tt_ray r;
    tt_camera_basis_ray(b, x, y, &r);
    tt_vec3 dir = tt_v3_load(r.dir);
    const float *v = tri + 9 * (size_t)prim;
    tt_vec3 v0 = tt_v3_load(v), v1 = tt_v3_load(v + 3), v2 = tt_v3_load(v + 6);
    tt_vec3 n = tt_v3_normalize(tt_v3_cross(tt_v3_sub(v1, v0), tt_v3_sub(v2, v0)));
    if (tt_v3_dot(n, dir) > 0.0f) n = tt_v3_scale(n, -1.0f); /* face the viewer */
    float facing = fabsf(tt_v3_dot(n, dir));
    float lit;
    if (has_light) {
        tt_vec3 p = tt_v3_add(tt_v3_load(r.org), tt_v3_scale(dir, t));
        tt_vec3 l = tt_v3_normalize(tt_v3_sub(tt_v3_load(light), p));
        float diffuse = fmaxf(0.0f, tt_v3_dot(n, l));
        if (shadows && shadow) diffuse = 0.0f;
        lit = 0.04f + 0.10f * facing + 0.86f * diffuse;
    } else {
        lit = 0.10f + 0.90f * facing;
    }
    for (int k = 0; k < 3; k++) out[k] = tt_shade_byte(albedo[k] * lit);
}

#endif
