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

    /* Edits (io/scene_edit.c; all zero for a scene never edited). A removed
     * triangle keeps its id and its slot, collapsed to a point (its first
     * vertex: zero area, hit by no structure), until an addition reuses the
     * id. `stamp[id]` is the `version` (edit calls so far) of the id's last
     * change, so a structure built at version v updates by the ids whose
     * stamp is above v. */
    uint64_t version;
    uint64_t *stamp;       /* per triangle, NULL until the first edit          */
    uint64_t *born;        /* per triangle: version of its last addition (an id
                              reused by an addition is a new triangle)         */
    uint8_t *flags;        /* per triangle: TT_TRI_DEAD, TT_TRI_OWN            */
    uint64_t structural;   /* version of the last addition or removal (0: none):
                              an update since then sees no id come or go      */
    size_t triangle_cap, vertex_cap, live_count;
    uint32_t *free_ids;    /* removed ids, reused last removed first           */
    size_t free_count, free_cap;
    uint32_t *adj_start, *adj_tri; /* vertex -> triangles (CSR), built lazily */
    int adj_valid;
    /* Traces in flight through any structure of the scene (> 0), or an
     * edit / update holding it (< 0): io/scene_guard.h. */
    _Atomic long guard;
};

#define TT_TRI_DEAD 0x1u /* removed: the id is free                            */
#define TT_TRI_OWN 0x2u  /* its three vertices are its own (none shared)       */

/* 1 when id is a removed triangle's (its slot a point, never hit). */
static inline int tt_scene_is_dead(const tt_scene *s, size_t id)
{
    return s->flags && (s->flags[id] & TT_TRI_DEAD);
}

/* Takes ownership of vertices and indices (allocated with ctx), validates
 * them (finite coordinates, indices in range), fills tri and bounds.
 * `name` prefixes error messages. Frees both arrays on failure. Zero
 * triangles is a valid (empty) scene here; the file loaders refuse it. */
tt_status tt_scene_adopt(tt_context *ctx, const char *name, float *vertices, size_t vertex_count,
                         uint32_t *indices, size_t triangle_count, tt_scene **out);

/* Length of the bounding-box diagonal (shadow-ray epsilon base). */
float tt_scene_diagonal(const tt_scene *scene);

#endif
