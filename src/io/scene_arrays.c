/* tt_scene_copy_arrays: the scene's vertex, index and triangle arrays copied
 * out whole, so a binding gets a 331k-triangle scene in one call instead of
 * one call per triangle. */
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
