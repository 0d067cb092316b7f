/* The camera's internals, shared by the public per-ray calls (camera.c) and
 * the renderer: both build rays through these functions, so a rendered hit
 * buffer is bit-identical to one built ray by ray with tt_camera_ray and
 * tt_shadow_ray. */
#ifndef TT_RENDER_CAMERA_H
#define TT_RENDER_CAMERA_H

#include "geometry/vec3.h"
#include "io/scene.h"

/* The per-image constants of the conventions' camera formula. */
typedef struct tt_camera_basis {
    tt_vec3 eye, forward, right, up;
    float h, aspect;
    uint32_t width, height;
} tt_camera_basis;

void tt_camera_basis_init(tt_camera_basis *b, const tt_camera *c, uint32_t width,
                          uint32_t height);
/* The primary ray of pixel (x, y); the caller guarantees x < width, y < height. */
void tt_camera_basis_ray(const tt_camera_basis *b, uint32_t x, uint32_t y, tt_ray *out);

/* tt_shadow_ray with the epsilon (1e-4 * scene diagonal) computed once by the
 * caller instead of once a ray. */
int tt_shadow_ray_eps(const tt_scene *scene, const tt_camera *c, float eps,
                      const tt_ray *primary, const tt_hit *hit, tt_ray *out);

/* Whether the camera can make rays: finite values, fov in (0, 180), the eye
 * apart from the look point and up not parallel to the view direction.
 * Returns NULL if so, otherwise a constant string naming the problem. */
const char *tt_camera_problem(const tt_camera *c);

#endif
