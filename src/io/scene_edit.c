/* Editing a scene in place: triangles added, removed by id, moved whole, or
 * vertices moved (every triangle using them follows). Each call validates
 * all of its input before changing anything, so a bad id or a non-finite
 * coordinate leaves the scene as it was. Each successful call is one
 * version; the ids it changed get that version as their stamp, which is
 * how tt_accel_update finds what to redo (io/scene.h). */
#include <math.h>
#include <string.h>

#include "io/scene.h"
#include "io/scene_guard.h"

/* The per-triangle edit arrays exist from the first edit on. */
static tt_status edit_arrays(tt_scene *s, const char *call)
{
    if (s->stamp) return TT_OK;
    const size_t T = s->triangle_count;
    s->stamp = tt_calloc(s->ctx, T ? T : 1, sizeof *s->stamp);
    s->born = tt_calloc(s->ctx, T ? T : 1, sizeof *s->born);
    s->flags = tt_calloc(s->ctx, T ? T : 1, 1);
    if (!s->stamp || !s->flags || !s->born) {
        tt_free(s->ctx, s->stamp);
        tt_free(s->ctx, s->born);
        tt_free(s->ctx, s->flags);
        s->stamp = s->born = NULL;
        s->flags = NULL;
        return tt_error(s->ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", call);
    }
    s->triangle_cap = T;
    s->vertex_cap = s->vertex_count;
    s->live_count = T;
    return TT_OK;
}

/* Room for `nt` more triangles and `nv` more vertices (all arrays grown
 * together, doubling, so a failure leaves every array usable). */
static tt_status reserve(tt_scene *s, size_t nt, size_t nv, const char *call)
{
    tt_context *ctx = s->ctx;
    if (s->triangle_count + nt > 0xFFFFFFFEu || s->vertex_count + nv > 0xFFFFFFFEu)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: the scene would exceed 2^32 - 2 triangles or vertices", call);
    if (s->triangle_count + nt > s->triangle_cap) {
        size_t cap = s->triangle_cap * 2 > s->triangle_count + nt ? s->triangle_cap * 2
                                                                   : s->triangle_count + nt;
        if (cap < 16) cap = 16;
        float *tri = tt_realloc_array(ctx, s->tri, cap, 9 * sizeof(float));
        if (tri) s->tri = tri;
        uint32_t *idx = tri ? tt_realloc_array(ctx, s->indices, cap, 3 * sizeof(uint32_t)) : NULL;
        if (idx) s->indices = idx;
        uint64_t *st = idx ? tt_realloc_array(ctx, s->stamp, cap, sizeof(uint64_t)) : NULL;
        if (st) s->stamp = st;
        uint64_t *bo = st ? tt_realloc_array(ctx, s->born, cap, sizeof(uint64_t)) : NULL;
        if (bo) s->born = bo;
        uint8_t *fl = bo ? tt_realloc_array(ctx, s->flags, cap, 1) : NULL;
        if (fl) s->flags = fl;
        if (!fl) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", call);
        s->triangle_cap = cap;
    }
    if (s->vertex_count + nv > s->vertex_cap) {
        size_t cap = s->vertex_cap * 2 > s->vertex_count + nv ? s->vertex_cap * 2
                                                               : s->vertex_count + nv;
        if (cap < 48) cap = 48;
        float *v = tt_realloc_array(ctx, s->vertices, cap, 3 * sizeof(float));
        if (!v) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", call);
        s->vertices = v;
        s->vertex_cap = cap;
    }
    return TT_OK;
}

/* Re-reads triangle t's corners from the vertices into tri (a live one). */
static void refresh(tt_scene *s, size_t t)
{
    for (int k = 0; k < 3; k++) {
        const float *v = s->vertices + 3 * (size_t)s->indices[3 * t + k];
        memcpy(s->tri + 9 * t + 3 * k, v, 3 * sizeof(float));
        tt_aabb_grow_point(&s->bounds, v);
    }
}

/* Gives triangle t three vertices of its own (appended; room reserved),
 * so that moving it moves no neighbour. */
static void detach(tt_scene *s, size_t t)
{
    if (s->flags[t] & TT_TRI_OWN) return;
    for (int k = 0; k < 3; k++) {
        const uint32_t nv = (uint32_t)s->vertex_count++;
        memcpy(s->vertices + 3 * (size_t)nv, s->vertices + 3 * (size_t)s->indices[3 * t + k],
               3 * sizeof(float));
        s->indices[3 * t + k] = nv;
    }
    s->flags[t] |= TT_TRI_OWN;
    s->adj_valid = 0;
}

/* The bounds stay exact (the structures' checks compare with them): the
 * box of every id slot's vertices in tri, removed ones' points included
 * (as a structure that keeps them sees them); grown as triangles arrive,
 * recomputed when one that touched them shrank or moved. */
static void recompute_bounds(tt_scene *s)
{
    s->bounds = tt_aabb_empty();
    float *lo = s->bounds.lo, *hi = s->bounds.hi;
    for (size_t t = 0; t < s->triangle_count; t++)
        for (int q = 0; q < 9; q++) {
            const float x = s->tri[9 * t + (size_t)q];
            if (x < lo[q % 3]) lo[q % 3] = x;
            if (x > hi[q % 3]) hi[q % 3] = x;
        }
}

static int touches_bounds(const tt_scene *s, const float *tri)
{
    for (int q = 0; q < 9; q++)
        if (tri[q] == s->bounds.lo[q % 3] || tri[q] == s->bounds.hi[q % 3]) return 1;
    return 0;
}

static tt_status check_finite(tt_scene *s, const char *call, const float *p, size_t n, size_t per,
                              const char *what)
{
    for (size_t i = 0; i < n * per; i++)
        if (!isfinite(p[i]))
            return tt_error(s->ctx, TT_ERR_INVALID_ARGUMENT,
                            "%s: %s %zu has a non-finite coordinate", call, what, i / per);
    return TT_OK;
}

/* Every id live, below the count, and none twice in the call. */
static tt_status check_ids(tt_scene *s, const char *call, const uint32_t *ids, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (ids[i] >= s->triangle_count)
            return tt_error(s->ctx, TT_ERR_INVALID_ARGUMENT,
                            "%s: ids[%zu] = %u is not a triangle of the scene (it has ids "
                            "0..%zu)", call, i, ids[i], s->triangle_count - 1);
        if (tt_scene_is_dead(s, ids[i]))
            return tt_error(s->ctx, TT_ERR_INVALID_ARGUMENT,
                            "%s: ids[%zu] = %u was removed", call, i, ids[i]);
    }
    if (n < 2) return TT_OK;
    /* duplicates: a mark bit in flags, cleared again before returning */
    size_t i = 0;
    tt_status st = TT_OK;
    for (; i < n; i++) {
        if (s->flags[ids[i]] & 0x80u) {
            st = tt_error(s->ctx, TT_ERR_INVALID_ARGUMENT, "%s: ids[%zu] = %u is given twice",
                          call, i, ids[i]);
            break;
        }
        s->flags[ids[i]] |= 0x80u;
    }
    for (size_t j = 0; j < i; j++) s->flags[ids[j]] &= (uint8_t)~0x80u;
    return st;
}

/* Common entry: arguments, exclusive hold of the scene, edit arrays. */
static tt_status begin(tt_scene *s, const char *call, const void *a, const void *b, size_t n)
{
    if (!s) return TT_ERR_INVALID_ARGUMENT;
    if (n && (!a || !b))
        return tt_error(s->ctx, TT_ERR_INVALID_ARGUMENT, "%s: NULL array", call);
    if (!tt_scene_write_enter(s))
        return tt_error(s->ctx, TT_ERR_BUSY,
                        "%s: the scene is being traced or updated on another thread; edits "
                        "must run alone (treetrace.h: the threading contract)", call);
    tt_status st = edit_arrays(s, call);
    if (st != TT_OK) tt_scene_write_leave(s);
    return st;
}

static tt_status end(tt_scene *s, tt_status st)
{
    if (st == TT_OK) s->version++;
    tt_scene_write_leave(s);
    return st;
}

tt_status tt_scene_add_triangles(tt_scene *s, const float *tri, size_t n, uint32_t *ids)
{
    static const char call[] = "tt_scene_add_triangles";
    const uint32_t dummy = 0;
    tt_status st = begin(s, call, tri, &dummy, n);
    if (st != TT_OK) return st;
    st = check_finite(s, call, tri, n, 9, "triangle");
    const size_t reused = n < s->free_count ? n : s->free_count;
    if (st == TT_OK) st = reserve(s, n - reused, 3 * n, call);
    if (st != TT_OK) return end(s, st);
    const uint64_t v = s->version + 1;
    for (size_t i = 0; i < n; i++) {
        size_t t;
        if (s->free_count) {
            t = s->free_ids[--s->free_count];
        } else {
            t = s->triangle_count++;
            s->flags[t] = 0;
        }
        s->flags[t] &= (uint8_t)~TT_TRI_DEAD;
        if (!(s->flags[t] & TT_TRI_OWN)) {
            for (int k = 0; k < 3; k++) s->indices[3 * t + (size_t)k] = (uint32_t)s->vertex_count++;
            s->flags[t] |= TT_TRI_OWN;
            s->adj_valid = 0;
        }
        for (int k = 0; k < 3; k++)
            memcpy(s->vertices + 3 * (size_t)s->indices[3 * t + (size_t)k], tri + 9 * i + 3 * k,
                   3 * sizeof(float));
        refresh(s, t);
        s->stamp[t] = s->born[t] = v;
        s->live_count++;
        if (ids) ids[i] = (uint32_t)t;
    }
    s->structural = v;
    return end(s, TT_OK);
}

tt_status tt_scene_remove_triangles(tt_scene *s, const uint32_t *ids, size_t n)
{
    static const char call[] = "tt_scene_remove_triangles";
    tt_status st = begin(s, call, ids, ids, n);
    if (st != TT_OK) return st;
    st = check_ids(s, call, ids, n);
    if (st == TT_OK && s->free_count + n > s->free_cap) {
        size_t cap = (s->free_count + n) * 2;
        uint32_t *f = tt_realloc_array(s->ctx, s->free_ids, cap, sizeof *f);
        if (!f) st = tt_error(s->ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", call);
        else {
            s->free_ids = f;
            s->free_cap = cap;
        }
    }
    if (st != TT_OK) return end(s, st);
    const uint64_t v = s->version + 1;
    int shrink = 0;
    for (size_t i = 0; i < n; i++) {
        const uint32_t t = ids[i];
        float *p = s->tri + 9 * (size_t)t;
        shrink |= touches_bounds(s, p);
        memcpy(p + 3, p, 3 * sizeof(float)); /* a point: zero area, never hit */
        memcpy(p + 6, p, 3 * sizeof(float));
        /* the same point for structures that read vertices and indices */
        uint32_t *ix = s->indices + 3 * (size_t)t;
        if (s->flags[t] & TT_TRI_OWN) {
            memcpy(s->vertices + 3 * (size_t)ix[1], p, 3 * sizeof(float));
            memcpy(s->vertices + 3 * (size_t)ix[2], p, 3 * sizeof(float));
        } else {
            ix[1] = ix[2] = ix[0];
            s->adj_valid = 0;
        }
        s->flags[t] |= TT_TRI_DEAD;
        s->stamp[t] = v;
        s->free_ids[s->free_count++] = t;
        s->live_count--;
    }
    s->structural = v;
    if (shrink) recompute_bounds(s);
    return end(s, TT_OK);
}

tt_status tt_scene_set_triangles(tt_scene *s, const uint32_t *ids, const float *tri, size_t n)
{
    static const char call[] = "tt_scene_set_triangles";
    tt_status st = begin(s, call, ids, tri, n);
    if (st != TT_OK) return st;
    st = check_ids(s, call, ids, n);
    if (st == TT_OK) st = check_finite(s, call, tri, n, 9, "triangle");
    size_t shared = 0;
    for (size_t i = 0; st == TT_OK && i < n; i++) shared += !(s->flags[ids[i]] & TT_TRI_OWN);
    if (st == TT_OK) st = reserve(s, 0, 3 * shared, call);
    if (st != TT_OK) return end(s, st);
    const uint64_t v = s->version + 1;
    int shrink = 0;
    for (size_t i = 0; i < n; i++) {
        const uint32_t t = ids[i];
        shrink |= touches_bounds(s, s->tri + 9 * (size_t)t);
        detach(s, t);
        for (int k = 0; k < 3; k++)
            memcpy(s->vertices + 3 * (size_t)s->indices[3 * (size_t)t + (size_t)k],
                   tri + 9 * i + 3 * k, 3 * sizeof(float));
        refresh(s, t);
        s->stamp[t] = v;
    }
    if (shrink) recompute_bounds(s);
    return end(s, TT_OK);
}

/* vertex -> the live triangles that use it, as compressed rows. */
static tt_status build_adjacency(tt_scene *s, const char *call)
{
    tt_context *ctx = s->ctx;
    tt_free(ctx, s->adj_start);
    tt_free(ctx, s->adj_tri);
    s->adj_start = tt_calloc(ctx, s->vertex_count + 1, sizeof(uint32_t));
    s->adj_tri = tt_alloc_array(ctx, 3 * s->triangle_count + 1, sizeof(uint32_t));
    if (!s->adj_start || !s->adj_tri) {
        tt_free(ctx, s->adj_start);
        tt_free(ctx, s->adj_tri);
        s->adj_start = s->adj_tri = NULL;
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", call);
    }
    for (size_t t = 0; t < s->triangle_count; t++)
        for (int k = 0; k < 3; k++) s->adj_start[s->indices[3 * t + (size_t)k] + 1]++;
    for (size_t v = 0; v < s->vertex_count; v++) s->adj_start[v + 1] += s->adj_start[v];
    for (size_t t = 0; t < s->triangle_count; t++)
        for (int k = 0; k < 3; k++) s->adj_tri[s->adj_start[s->indices[3 * t + (size_t)k]]++] = (uint32_t)t;
    for (size_t v = s->vertex_count; v > 0; v--) s->adj_start[v] = s->adj_start[v - 1];
    s->adj_start[0] = 0;
    s->adj_valid = 1;
    return TT_OK;
}

tt_status tt_scene_move_vertices(tt_scene *s, const uint32_t *ids, const float *pos, size_t n)
{
    static const char call[] = "tt_scene_move_vertices";
    tt_status st = begin(s, call, pos, pos, n);
    if (st != TT_OK) return st;
    if (!ids && n > s->vertex_count)
        st = tt_error(s->ctx, TT_ERR_INVALID_ARGUMENT,
                      "%s: %zu positions for the scene's %zu vertices", call, n, s->vertex_count);
    for (size_t i = 0; st == TT_OK && ids && i < n; i++)
        if (ids[i] >= s->vertex_count)
            st = tt_error(s->ctx, TT_ERR_INVALID_ARGUMENT,
                          "%s: ids[%zu] = %u is not a vertex of the scene (it has %zu)", call, i,
                          ids[i], s->vertex_count);
    if (st == TT_OK) st = check_finite(s, call, pos, n, 3, "position");
    /* many vertices: re-read every triangle; few: only their triangles */
    const int all = n * 8 >= s->vertex_count;
    if (st == TT_OK && !all && !s->adj_valid) st = build_adjacency(s, call);
    if (st != TT_OK) return end(s, st);
    const uint64_t v = s->version + 1;
    int shrink = 0;
    for (size_t i = 0; i < n; i++) {
        float *p = s->vertices + 3 * (size_t)(ids ? ids[i] : i);
        for (int k = 0; k < 3; k++)
            shrink |= p[k] == s->bounds.lo[k] || p[k] == s->bounds.hi[k];
        memcpy(p, pos + 3 * i, 3 * sizeof(float));
    }
    if (all) { /* one pass: re-read, stamp what changed, bounds anew */
        for (size_t t = 0; t < s->triangle_count; t++) {
            if (s->flags[t] & TT_TRI_DEAD) continue;
            float *p = s->tri + 9 * t;
            int moved = 0;
            for (int k = 0; k < 3; k++) {
                const float *q = s->vertices + 3 * (size_t)s->indices[3 * t + (size_t)k];
                moved |= p[3 * k] != q[0] || p[3 * k + 1] != q[1] || p[3 * k + 2] != q[2];
                p[3 * k] = q[0];
                p[3 * k + 1] = q[1];
                p[3 * k + 2] = q[2];
            }
            if (moved) s->stamp[t] = v;
        }
        recompute_bounds(s);
    } else {
        for (size_t i = 0; i < n; i++) {
            const uint32_t vx = ids ? ids[i] : (uint32_t)i;
            for (uint32_t j = s->adj_start[vx]; j < s->adj_start[vx + 1]; j++) {
                const uint32_t t = s->adj_tri[j];
                if (s->flags[t] & TT_TRI_DEAD) continue;
                refresh(s, t);
                s->stamp[t] = v;
            }
        }
    }
    if (shrink && !all) recompute_bounds(s);
    return end(s, TT_OK);
}

int tt_scene_triangle_alive(const tt_scene *s, uint32_t id)
{
    return s && id < s->triangle_count && !tt_scene_is_dead(s, id);
}

size_t tt_scene_live_triangle_count(const tt_scene *s)
{
    if (!s) return 0;
    return s->stamp ? s->live_count : s->triangle_count;
}

uint64_t tt_scene_version(const tt_scene *s) { return s ? s->version : 0; }

tt_status tt_scene_vertex(const tt_scene *s, size_t i, float out[3])
{
    if (!s || !out || i >= s->vertex_count) return TT_ERR_INVALID_ARGUMENT;
    memcpy(out, s->vertices + 3 * i, 3 * sizeof(float));
    return TT_OK;
}
