/* Primary and shadow rays exactly per ../shared/scenes/README.md, so that hit
 * buffers can be compared ray by ray with other ray tracers. */
#include <math.h>
#include <string.h>

#include "geometry/vec3.h"
#include "io/scene.h"

typedef struct camera_basis {
    tt_vec3 forward, right, up;
    float h, aspect;
} camera_basis;

static camera_basis basis(const tt_camera *c, uint32_t width, uint32_t height)
{
    camera_basis b;
    tt_vec3 eye = tt_v3_load(c->eye);
    b.forward = tt_v3_normalize(tt_v3_sub(tt_v3_load(c->look), eye));
    b.right = tt_v3_normalize(tt_v3_cross(b.forward, tt_v3_load(c->up)));
    b.up = tt_v3_cross(b.right, b.forward);
    b.aspect = (float)width / (float)height;
    b.h = tanf(c->fov_deg * 3.14159265358979323846f / 360.0f);
    return b;
}

tt_status tt_camera_ray(const tt_camera *c, uint32_t width, uint32_t height, uint32_t x,
                        uint32_t y, tt_ray *out)
{
    if (!c || !out || width == 0 || height == 0 || x >= width || y >= height)
        return TT_ERR_INVALID_ARGUMENT;
    camera_basis b = basis(c, width, height);
    float u = (2.0f * ((float)x + 0.5f) / (float)width - 1.0f) * b.h * b.aspect;
    float v = (1.0f - 2.0f * ((float)y + 0.5f) / (float)height) * b.h;
    tt_vec3 d = tt_v3_add(b.forward, tt_v3_add(tt_v3_scale(b.right, u), tt_v3_scale(b.up, v)));
    d = tt_v3_normalize(d);
    memcpy(out->org, c->eye, sizeof out->org);
    out->dir[0] = d.x;
    out->dir[1] = d.y;
    out->dir[2] = d.z;
    out->tmin = 0.0f;
    out->tmax = INFINITY;
    return TT_OK;
}

int tt_shadow_ray(const tt_scene *scene, const tt_camera *c, const tt_ray *primary,
                  const tt_hit *hit, tt_ray *out)
{
    if (!c->has_light || hit->prim == TT_INVALID_ID) return 0;
    const float *tri = scene->tri + 9 * (size_t)hit->prim;
    tt_vec3 v0 = tt_v3_load(tri), v1 = tt_v3_load(tri + 3), v2 = tt_v3_load(tri + 6);
    tt_vec3 dir = tt_v3_load(primary->dir);
    tt_vec3 n = tt_v3_normalize(tt_v3_cross(tt_v3_sub(v1, v0), tt_v3_sub(v2, v0)));
    if (tt_v3_dot(n, dir) > 0.0f) n = tt_v3_scale(n, -1.0f);
    tt_vec3 p = tt_v3_add(tt_v3_load(primary->org), tt_v3_scale(dir, hit->t));
    float eps = 1e-4f * tt_scene_diagonal(scene);
    tt_vec3 o = tt_v3_add(p, tt_v3_scale(n, eps));
    tt_vec3 to_light = tt_v3_sub(tt_v3_load(c->light), o);
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
    return 1;
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
