/* The scene's internals: vertices and triangle indices in load order, plus a
 * flat copy of every triangle's three vertices for cache-friendly tests. */
#ifndef TT_IO_SCENE_H
#define TT_IO_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "core/context.h"
#include "geometry/aabb.h"

struct tt_scene {
    tt_context *ctx;
    float *vertices;   /* 3 floats a vertex                                     */
    size_t vertex_count;
    uint32_t *indices; /* 3 a triangle, load order                              */
    size_t triangle_count;
    float *tri;        /* 9 floats a triangle: v0, v1, v2                       */
    tt_aabb bounds;    /* of the vertices used by triangles                     */
};

/* Takes ownership of vertices and indices (allocated with ctx), validates
 * them (finite coordinates, indices in range), fills tri and bounds.
 * `name` prefixes error messages. Frees both arrays on failure. Zero
 * triangles is a valid (empty) scene here; the file loaders refuse it. */
tt_status tt_scene_adopt(tt_context *ctx, const char *name, float *vertices, size_t vertex_count,
                         uint32_t *indices, size_t triangle_count, tt_scene **out);

/* Length of the bounding-box diagonal (shadow-ray epsilon base). */
float tt_scene_diagonal(const tt_scene *scene);

#endif
