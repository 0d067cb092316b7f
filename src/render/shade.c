/* A deliberately simple shading of the frame, enough to see the geometry and
 * the shadows: diffuse light from the point light where the shadow ray got
 * through, a faint headlight term everywhere (so shadowed parts keep their
 * shape), and a dark grey background. Not timed. */
#include <math.h>

#include "render/frame.h"

static uint8_t to_byte(float linear)
{
    /* sqrt approximates the display gamma, so dim regions stay readable */
    float v = sqrtf(linear < 0.0f ? 0.0f : (linear > 1.0f ? 1.0f : linear));
    return (uint8_t)(v * 255.0f + 0.5f);
}

static void shade_pixel(const tt_frame *f, int shadows, uint32_t x, uint32_t y, uint8_t *out)
{
    static const float background[3] = {0.025f, 0.025f, 0.03f};
    static const float albedo[3] = {0.90f, 0.84f, 0.74f};
    size_t i = (size_t)y * f->width + x;
    uint32_t prim = f->prim[i];
    if (prim == TT_INVALID_ID) {
        for (int k = 0; k < 3; k++) out[k] = to_byte(background[k]);
        return;
    }
    tt_ray r;
    tt_camera_basis_ray(&f->basis, x, y, &r);
    tt_vec3 dir = tt_v3_load(r.dir);
    const float *tri = f->scene->tri + 9 * (size_t)prim;
    tt_vec3 v0 = tt_v3_load(tri), v1 = tt_v3_load(tri + 3), v2 = tt_v3_load(tri + 6);
    tt_vec3 n = tt_v3_normalize(tt_v3_cross(tt_v3_sub(v1, v0), tt_v3_sub(v2, v0)));
    if (tt_v3_dot(n, dir) > 0.0f) n = tt_v3_scale(n, -1.0f); /* face the viewer */
    float facing = fabsf(tt_v3_dot(n, dir));
    float light;
    if (f->camera->has_light) {
        tt_vec3 p = tt_v3_add(tt_v3_load(r.org), tt_v3_scale(dir, f->t[i]));
        tt_vec3 l = tt_v3_normalize(tt_v3_sub(tt_v3_load(f->camera->light), p));
        float diffuse = fmaxf(0.0f, tt_v3_dot(n, l));
        if (shadows && f->shadow[i]) diffuse = 0.0f;
        light = 0.04f + 0.10f * facing + 0.86f * diffuse;
    } else {
        light = 0.10f + 0.90f * facing;
    }
    for (int k = 0; k < 3; k++) out[k] = to_byte(albedo[k] * light);
}

void tt_frame_shade(const tt_frame *f, int shadows, uint8_t *rgb)
{
    const long h = (long)f->height;
#pragma omp parallel for schedule(dynamic) num_threads(f->threads)
    for (long y = 0; y < h; y++)
        for (uint32_t x = 0; x < f->width; x++)
            shade_pixel(f, shadows, x, (uint32_t)y, rgb + 3 * ((size_t)y * f->width + x));
}
