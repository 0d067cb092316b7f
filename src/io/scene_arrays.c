/* tt_scene_copy_arrays and tt_scene_normals: the scene's vertex, index and triangle arrays copied
 * out whole, so a binding gets a 331k-triangle scene in one call instead of
 * one call per triangle; the geometric normals of a batch of hits. */
#include <math.h>
#include <string.h>

#include "io/scene.h"

tt_status tt_scene_copy_arrays(const tt_scene *scene, float *vertices, size_t vertex_capacity,
                               uint32_t *indices, float *triangles, size_t triangle_capacity)
{
    if (!scene) return TT_ERR_INVALID_ARGUMENT;
    /* every check before any write: a refused call leaves the arrays as they were */
    if (vertices && vertex_capacity < scene->vertex_count)
        return tt_error(scene->ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_scene_copy_arrays: room for %zu vertices, the scene has %zu",
                        vertex_capacity, scene->vertex_count);
    if ((indices || triangles) && triangle_capacity < scene->triangle_count)
        return tt_error(scene->ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_scene_copy_arrays: room for %zu triangles, the scene has %zu",
                        triangle_capacity, scene->triangle_count);
    if (vertices && scene->vertex_count)
        memcpy(vertices, scene->vertices, scene->vertex_count * 3 * sizeof(float));
    if (indices && scene->triangle_count)
        memcpy(indices, scene->indices, scene->triangle_count * 3 * sizeof(uint32_t));
    if (triangles && scene->triangle_count)
        memcpy(triangles, scene->tri, scene->triangle_count * 9 * sizeof(float));
    return TT_OK;
}

tt_status tt_scene_normals(const tt_scene *scene, const uint32_t *prims, size_t count,
                           float *normals)
{
    if (!scene) return TT_ERR_INVALID_ARGUMENT;
    if (count && (!prims || !normals))
        return tt_error(scene->ctx, TT_ERR_INVALID_ARGUMENT, "tt_scene_normals: NULL array");
    for (size_t i = 0; i < count; i++) {
        float *n = normals + 3 * i;
        uint32_t p = prims[i];
        n[0] = n[1] = n[2] = 0.0f;
        if (p == TT_INVALID_ID) continue;
        if (p >= scene->triangle_count)
            return tt_error(scene->ctx, TT_ERR_INVALID_ARGUMENT,
                            "tt_scene_normals: prims[%zu] = %u, but the scene has %zu triangles", i,
                            p, scene->triangle_count);
        const float *t = scene->tri + 9 * (size_t)p;
        float e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = t[3 + k] - t[k];
            e2[k] = t[6 + k] - t[k];
        }
        float c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
        /* in double: a tiny triangle's squared length would underflow in float */
        double len = sqrt((double)c[0] * c[0] + (double)c[1] * c[1] + (double)c[2] * c[2]);
        if (!(len > 0.0) || !isfinite(len)) continue;
        for (int k = 0; k < 3; k++) n[k] = (float)(c[k] / len);
    }
    return TT_OK;
}
