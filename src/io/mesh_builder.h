/* Growable vertex and triangle arrays that the file parsers fill and then
 * hand to tt_scene_adopt. Limits follow the public types: vertex indices and
 * triangle ids are uint32, and TT_INVALID_ID (0xFFFFFFFF) is reserved. */
#ifndef TT_IO_MESH_BUILDER_H
#define TT_IO_MESH_BUILDER_H

#include <stddef.h>
#include <stdint.h>

#include "io/scene.h"

#define TT_MAX_VERTICES ((size_t)0xFFFFFFFFu)
#define TT_MAX_TRIANGLES ((size_t)0xFFFFFFFFu)

typedef struct tt_mesh_builder {
    tt_context *ctx;
    const char *name;
    float *vertices;
    size_t vertex_count, vertex_cap;
    uint32_t *indices;
    size_t triangle_count, triangle_cap;
} tt_mesh_builder;

void tt_mb_init(tt_mesh_builder *mb, tt_context *ctx, const char *name);
void tt_mb_free(tt_mesh_builder *mb);

/* Room for at least n more vertices / triangles; TT_ERR_OUT_OF_MEMORY (with
 * a message) on failure, TT_ERR_PARSE past the limits above. */
tt_status tt_mb_reserve_vertices(tt_mesh_builder *mb, size_t n);
tt_status tt_mb_reserve_triangles(tt_mesh_builder *mb, size_t n);

static inline tt_status tt_mb_push_vertex(tt_mesh_builder *mb, float x, float y, float z)
{
    if (mb->vertex_count == mb->vertex_cap) {
        tt_status st = tt_mb_reserve_vertices(mb, 1);
        if (st) return st;
    }
    float *v = mb->vertices + 3 * mb->vertex_count++;
    v[0] = x, v[1] = y, v[2] = z;
    return TT_OK;
}

static inline tt_status tt_mb_push_triangle(tt_mesh_builder *mb, uint32_t a, uint32_t b, uint32_t c)
{
    if (mb->triangle_count == mb->triangle_cap) {
        tt_status st = tt_mb_reserve_triangles(mb, 1);
        if (st) return st;
    }
    uint32_t *t = mb->indices + 3 * mb->triangle_count++;
    t[0] = a, t[1] = b, t[2] = c;
    return TT_OK;
}

/* Refuses an empty scene, then gives the arrays to tt_scene_adopt (the
 * builder is emptied either way). */
tt_status tt_mb_finish(tt_mesh_builder *mb, tt_scene **out);

#endif
