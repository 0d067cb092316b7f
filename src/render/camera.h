/* The camera's internals, shared by the public per-ray calls (camera.c) and
 * the renderer: both build rays through these functions, so a rendered hit
 * buffer is bit-identical to one built ray by ray with tt_camera_ray and
 * tt_shadow_ray. */
#ifndef TT_RENDER_CAMERA_H
#define TT_RENDER_CAMERA_H

#include "geometry/vec3.h"
#include "io/scene.h"
#include "render/camera_hd.h"

/* The basis of tt_camera_basis_ray (camera_hd.h) for a w x h image. */
void tt_camera_basis_init(tt_camera_basis *b, const tt_camera *c, uint32_t width,
                          uint32_t height);

/* tt_shadow_ray with the epsilon (1e-4 * scene diagonal) computed once by the
 * caller instead of once a ray. */
int tt_shadow_ray_eps(const tt_scene *scene, const tt_camera *c, float eps,
                      const tt_ray *primary, const tt_hit *hit, tt_ray *out);

/* Whether the camera can make rays: finite values, fov in (0, 180), the eye
 * apart from the look point and up not parallel to the view direction.
 * Returns NULL if so, otherwise a constant string naming the problem. */
const char *tt_camera_problem(const tt_camera *c);

#endif
