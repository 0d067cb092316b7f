#include "io/scene.h"

#include <math.h>
#include <string.h>

/* Finite coordinates and indices in range; `status` is what a violation
 * is reported as (a parse error in a file, an invalid argument in an API
 * call). */
static tt_status validate(tt_context *ctx, const char *name, tt_status status, const float *vertices,
                          size_t vertex_count, const uint32_t *indices, size_t triangle_count)
{
    for (size_t i = 0; i < vertex_count * 3; i++)
        if (!isfinite(vertices[i]))
            return tt_error(ctx, status, "%s: vertex %zu has a non-finite coordinate", name, i / 3);
    for (size_t i = 0; i < triangle_count * 3; i++)
        if (indices[i] >= vertex_count)
            return tt_error(ctx, status,
                            "%s: triangle %zu refers to vertex %u, but there are only %zu vertices",
                            name, i / 3, indices[i], vertex_count);
    return TT_OK;
}

tt_status tt_scene_adopt(tt_context *ctx, const char *name, float *vertices, size_t vertex_count,
                         uint32_t *indices, size_t triangle_count, tt_scene **out)
{
    *out = NULL;
    tt_scene *s = NULL;
    tt_status st = validate(ctx, name, TT_ERR_PARSE, vertices, vertex_count, indices, triangle_count);
    if (st) goto fail;
    s = tt_calloc(ctx, 1, sizeof *s);
    if (!s) goto oom;
    s->tri = tt_alloc_array(ctx, triangle_count, 9 * sizeof(float));
    if (!s->tri) goto oom;
    s->ctx = ctx;
    s->vertices = vertices;
    s->vertex_count = vertex_count;
    s->indices = indices;
    s->triangle_count = triangle_count;
    s->bounds = tt_aabb_empty();
    for (size_t t = 0; t < triangle_count; t++) {
        for (int k = 0; k < 3; k++) {
            const float *v = vertices + 3 * (size_t)indices[3 * t + k];
            memcpy(s->tri + 9 * t + 3 * k, v, 3 * sizeof(float));
            tt_aabb_grow_point(&s->bounds, v);
        }
    }
    *out = s;
    return TT_OK;
oom:
    st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory for %zu triangles", name,
                  triangle_count);
    if (s) tt_free(ctx, s->tri);
    tt_free(ctx, s);
fail:
    tt_free(ctx, vertices);
    tt_free(ctx, indices);
    return st;
}

tt_status tt_scene_create(tt_context *ctx, const float *vertices, size_t vertex_count,
                          const uint32_t *indices, size_t triangle_count, tt_scene **out)
{
    if (!out) return TT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if ((!vertices && vertex_count) || (!indices && triangle_count))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_scene_create: NULL array");
    /* Triangle ids are uint32 with TT_INVALID_ID reserved; the byte sizes
     * below must not overflow. */
    if (triangle_count > 0xFFFFFFFEu || vertex_count > SIZE_MAX / (3 * sizeof(float)))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_scene_create: %zu vertices and %zu triangles are more than it can hold",
                        vertex_count, triangle_count);
    /* The caller's arrays are checked before anything is allocated, and a
     * bad value is an invalid argument (a file's is a parse error). */
    tt_status st = validate(ctx, "tt_scene_create", TT_ERR_INVALID_ARGUMENT, vertices, vertex_count,
                            indices, triangle_count);
    if (st) return st;
    float *v = tt_alloc_array(ctx, vertex_count, 3 * sizeof(float));
    uint32_t *i = tt_alloc_array(ctx, triangle_count, 3 * sizeof(uint32_t));
    if (!v || !i) {
        tt_free(ctx, v);
        tt_free(ctx, i);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_scene_create: out of memory");
    }
    if (vertex_count) memcpy(v, vertices, vertex_count * 3 * sizeof(float));
    if (triangle_count) memcpy(i, indices, triangle_count * 3 * sizeof(uint32_t));
    return tt_scene_adopt(ctx, "tt_scene_create", v, vertex_count, i, triangle_count, out);
}

void tt_scene_destroy(tt_scene *scene)
{
    if (!scene) return;
    tt_context *ctx = scene->ctx;
    tt_free(ctx, scene->vertices);
    tt_free(ctx, scene->indices);
    tt_free(ctx, scene->tri);
    tt_free(ctx, scene->stamp); /* the edit arrays (io/scene_edit.c) */
    tt_free(ctx, scene->born);
    tt_free(ctx, scene->flags);
    tt_free(ctx, scene->free_ids);
    tt_free(ctx, scene->adj_start);
    tt_free(ctx, scene->adj_tri);
    tt_free(ctx, scene);
}

size_t tt_scene_triangle_count(const tt_scene *scene) { return scene ? scene->triangle_count : 0; }
size_t tt_scene_vertex_count(const tt_scene *scene) { return scene ? scene->vertex_count : 0; }

void tt_scene_bounds(const tt_scene *scene, float min[3], float max[3])
{
    if (!min || !max) return;
    for (int i = 0; i < 3; i++) {
        if (!scene) { /* as for an empty scene */
            min[i] = INFINITY;
            max[i] = -INFINITY;
            continue;
        }
        min[i] = scene->bounds.lo[i];
        max[i] = scene->bounds.hi[i];
    }
}

tt_status tt_scene_triangle(const tt_scene *scene, size_t i, float out[9])
{
    if (!scene || !out || i >= scene->triangle_count) return TT_ERR_INVALID_ARGUMENT;
    memcpy(out, scene->tri + 9 * i, 9 * sizeof(float));
    return TT_OK;
}

float tt_scene_diagonal(const tt_scene *scene)
{
    float d[3];
    for (int i = 0; i < 3; i++) d[i] = scene->bounds.hi[i] - scene->bounds.lo[i];
    return sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}
