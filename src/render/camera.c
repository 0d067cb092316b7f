/* Primary and shadow rays exactly per ../shared/scenes/README.md, so that hit
 * buffers can be compared ray by ray with other ray tracers. */
#include "render/camera.h"

#include <math.h>
#include <string.h>

void tt_camera_basis_init(tt_camera_basis *b, const tt_camera *c, uint32_t width,
                          uint32_t height)
{
    b->eye = tt_v3_load(c->eye);
    b->forward = tt_v3_normalize(tt_v3_sub(tt_v3_load(c->look), b->eye));
    b->right = tt_v3_normalize(tt_v3_cross(b->forward, tt_v3_load(c->up)));
    b->up = tt_v3_cross(b->right, b->forward);
    b->aspect = (float)width / (float)height;
    b->h = tanf(c->fov_deg * 3.14159265358979323846f / 360.0f);
    b->width = width;
    b->height = height;
}

tt_status tt_camera_ray(const tt_camera *c, uint32_t width, uint32_t height, uint32_t x,
                        uint32_t y, tt_ray *out)
{
    if (!c || !out || width == 0 || height == 0 || x >= width || y >= height)
        return TT_ERR_INVALID_ARGUMENT;
    /* A camera that cannot make rays (NaN/Inf values, eye == look, up zero
     * or parallel to the view, fov outside (0, 180)) would give NaN rays.
     * The check costs a few square roots, about as much as the basis below;
     * the renderer never comes through here (it checks once and builds its
     * rays with tt_camera_basis_ray), so only per-ray callers pay it. No
     * context here to carry a message: tt_render names the problem. */
    if (tt_camera_problem(c)) return TT_ERR_INVALID_ARGUMENT;
    tt_camera_basis b;
    tt_camera_basis_init(&b, c, width, height);
    tt_camera_basis_ray(&b, x, y, out);
    return TT_OK;
}

tt_status tt_camera_rays(const tt_camera *c, uint32_t width, uint32_t height, tt_ray *out)
{
    if (!c || !out || width == 0 || height == 0 || tt_camera_problem(c))
        return TT_ERR_INVALID_ARGUMENT;
    tt_camera_basis b;
    tt_camera_basis_init(&b, c, width, height);
    const long rows = (long)height;
#pragma omp parallel for schedule(static)
    for (long y = 0; y < rows; y++)
        for (uint32_t x = 0; x < width; x++)
            tt_camera_basis_ray(&b, x, (uint32_t)y, out + (size_t)y * width + x);
    return TT_OK;
}

int tt_shadow_ray_eps(const tt_scene *scene, const tt_camera *c, float eps,
                      const tt_ray *primary, const tt_hit *hit, tt_ray *out)
{
    if (!c->has_light || hit->prim == TT_INVALID_ID) return 0;
    tt_shadow_ray_from(scene->tri + 9 * (size_t)hit->prim, c->light, eps, primary, hit->t, out);
    return 1;
}

int tt_shadow_ray(const tt_scene *scene, const tt_camera *c, const tt_ray *primary,
                  const tt_hit *hit, tt_ray *out)
{
    return tt_shadow_ray_eps(scene, c, 1e-4f * tt_scene_diagonal(scene), primary, hit, out);
}

static int finite3(const float *v) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

const char *tt_camera_problem(const tt_camera *c)
{
    if (!finite3(c->eye)) return "the eye is not finite";
    if (!finite3(c->look)) return "the look point is not finite";
    if (!finite3(c->up)) return "the up vector is not finite";
    if (c->has_light && !finite3(c->light)) return "the light is not finite";
    if (!(c->fov_deg > 0.0f && c->fov_deg < 180.0f)) return "the field of view is not in (0, 180)";
    tt_vec3 f = tt_v3_sub(tt_v3_load(c->look), tt_v3_load(c->eye));
    float dist = tt_v3_length(f);
    if (!(dist > 0.0f)) return "the eye and the look point coincide";
    /* the basis normalizes look - eye: its length must be a float too */
    if (!isfinite(dist)) return "the eye and the look point are too far apart for float";
    tt_vec3 r = tt_v3_cross(tt_v3_normalize(f), tt_v3_load(c->up));
    if (!(tt_v3_length(r) > 0.0f) || !isfinite(tt_v3_length(r)))
        return "the up vector is zero or parallel to the view direction";
    return NULL;
}

void tt_camera_frame_scene(const tt_scene *scene, tt_camera *out)
{
    /* Look at the box centre from the front (+z) and a little above, far
     * enough that the whole bounding sphere fits the 45 degree view. */
    const tt_aabb *b = &scene->bounds;
    tt_vec3 lo = tt_v3_load(b->lo), hi = tt_v3_load(b->hi);
    if (tt_aabb_is_empty(b)) lo = hi = tt_v3(0, 0, 0);
    tt_vec3 centre = tt_v3_scale(tt_v3_add(lo, hi), 0.5f);
    float radius = 0.5f * tt_v3_length(tt_v3_sub(hi, lo));
    if (!(radius > 0.0f)) radius = 1.0f;
    float fov = 45.0f;
    float dist = radius / sinf(fov * 3.14159265358979323846f / 360.0f) * 1.05f;
    tt_vec3 dir = tt_v3_normalize(tt_v3(0.0f, 0.25f, 1.0f));
    tt_vec3 eye = tt_v3_add(centre, tt_v3_scale(dir, dist));
    tt_vec3 light = tt_v3_add(centre, tt_v3(-radius * 1.5f, radius * 2.5f, radius * 1.5f));
    memset(out, 0, sizeof *out);
    out->eye[0] = eye.x; out->eye[1] = eye.y; out->eye[2] = eye.z;
    out->look[0] = centre.x; out->look[1] = centre.y; out->look[2] = centre.z;
    out->up[1] = 1.0f;
    out->fov_deg = fov;
    out->light[0] = light.x; out->light[1] = light.y; out->light[2] = light.z;
    out->has_light = 1;
}
