#include "io/mesh_builder.h"

#include <string.h>

void tt_mb_init(tt_mesh_builder *mb, tt_context *ctx, const char *name)
{
    memset(mb, 0, sizeof *mb);
    mb->ctx = ctx;
    mb->name = name;
}

void tt_mb_free(tt_mesh_builder *mb)
{
    tt_free(mb->ctx, mb->vertices);
    tt_free(mb->ctx, mb->indices);
    mb->vertices = NULL;
    mb->indices = NULL;
    mb->vertex_count = mb->vertex_cap = mb->triangle_count = mb->triangle_cap = 0;
}

/* Grows *cap to hold count + n items of item_size bytes (doubling, so pushes
 * are amortised O(1)), never beyond max items. */
static tt_status grow(tt_mesh_builder *mb, void **array, size_t *cap, size_t count, size_t n,
                      size_t max, size_t item_size, const char *what)
{
    if (n > max - count)
        return tt_error(mb->ctx, TT_ERR_PARSE, "%s: more than %zu %s (32-bit indices and ids)",
                        mb->name, max, what);
    size_t need = count + n;
    if (need <= *cap) return TT_OK;
    size_t new_cap = *cap < 1024 ? 1024 : *cap;
    while (new_cap < need) new_cap = new_cap > max / 2 ? max : new_cap * 2;
    if (new_cap > max) new_cap = max;
    void *p = tt_realloc_array(mb->ctx, *array, new_cap, item_size);
    if (!p)
        return tt_error(mb->ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory for %zu %s", mb->name,
                        new_cap, what);
    *array = p;
    *cap = new_cap;
    return TT_OK;
}

tt_status tt_mb_reserve_vertices(tt_mesh_builder *mb, size_t n)
{
    void *p = mb->vertices;
    tt_status st = grow(mb, &p, &mb->vertex_cap, mb->vertex_count, n, TT_MAX_VERTICES,
                        3 * sizeof(float), "vertices");
    mb->vertices = p;
    return st;
}

tt_status tt_mb_reserve_triangles(tt_mesh_builder *mb, size_t n)
{
    void *p = mb->indices;
    tt_status st = grow(mb, &p, &mb->triangle_cap, mb->triangle_count, n, TT_MAX_TRIANGLES - 1,
                        3 * sizeof(uint32_t), "triangles");
    mb->indices = p;
    return st;
}

tt_status tt_mb_finish(tt_mesh_builder *mb, tt_scene **out)
{
    if (mb->triangle_count == 0) {
        tt_mb_free(mb);
        return tt_error(mb->ctx, TT_ERR_PARSE, "%s: the scene has no triangles", mb->name);
    }
    /* tt_scene_adopt owns the arrays from here, on success and failure. */
    float *v = mb->vertices;
    uint32_t *i = mb->indices;
    size_t nv = mb->vertex_count, nt = mb->triangle_count;
    mb->vertices = NULL;
    mb->indices = NULL;
    tt_mb_free(mb);
    if (!v) { /* triangles without vertices cannot pass the index checks */
        tt_free(mb->ctx, i);
        return tt_error(mb->ctx, TT_ERR_PARSE, "%s: triangles but no vertices", mb->name);
    }
    return tt_scene_adopt(mb->ctx, mb->name, v, nv, i, nt, out);
}
