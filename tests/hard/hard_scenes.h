/* Procedural hard scenes for the hard-geometry and hard-ray tests: each one
 * is built to provoke a known weakness of spatial structures (zero-extent
 * boxes, equal split candidates, precision loss far from the origin, a node
 * every triangle overlaps ...). Small (hundreds to a few thousand
 * triangles) so that every structure variant can be checked ray by ray. */
#ifndef TT_HARD_SCENES_H
#define TT_HARD_SCENES_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

/* xorshift32: fixed, portable sequences. */
static inline uint32_t hard_next(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}
/* Uniform in [0, 1). */
static inline float hard_unit(uint32_t *x) { return (float)(hard_next(x) >> 8) * (1.0f / 16777216.0f); }
/* Uniform in [-1, 1). */
static inline float hard_sym(uint32_t *x) { return 2.0f * hard_unit(x) - 1.0f; }

/* A triangle soup under construction (every triangle has its own three
 * vertices unless a generator shares them on purpose). */
typedef struct hard_mesh {
    const char *name;
    float *v;
    uint32_t *idx;
    size_t nv, nt, vcap, tcap;
} hard_mesh;

static inline void *hard_xrealloc(void *p, size_t n)
{
    void *q = realloc(p, n ? n : 1);
    if (!q) {
        fprintf(stderr, "out of memory in the test\n");
        exit(1);
    }
    return q;
}

static inline uint32_t hard_vertex(hard_mesh *m, float x, float y, float z)
{
    if (m->nv == m->vcap) {
        m->vcap = m->vcap ? 2 * m->vcap : 256;
        m->v = hard_xrealloc(m->v, m->vcap * 3 * sizeof(float));
    }
    float *p = m->v + 3 * m->nv;
    p[0] = x, p[1] = y, p[2] = z;
    return (uint32_t)m->nv++;
}

static inline void hard_triangle_ids(hard_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->nt == m->tcap) {
        m->tcap = m->tcap ? 2 * m->tcap : 256;
        m->idx = hard_xrealloc(m->idx, m->tcap * 3 * sizeof(uint32_t));
    }
    uint32_t *p = m->idx + 3 * m->nt++;
    p[0] = a, p[1] = b, p[2] = c;
}

static inline void hard_triangle(hard_mesh *m, const float a[3], const float b[3], const float c[3])
{
    uint32_t i = hard_vertex(m, a[0], a[1], a[2]);
    uint32_t j = hard_vertex(m, b[0], b[1], b[2]);
    uint32_t k = hard_vertex(m, c[0], c[1], c[2]);
    hard_triangle_ids(m, i, j, k);
}

static inline void hard_mesh_free(hard_mesh *m)
{
    free(m->v);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

/* Every vertex mapped by p * scale + offset, in float (as a file would hold
 * it after loading). */
static inline void hard_mesh_transform(hard_mesh *m, float scale, const float offset[3])
{
    for (size_t i = 0; i < 3 * m->nv; i++) m->v[i] = m->v[i] * scale + offset[i % 3];
}

static inline tt_scene *hard_scene(tt_context *ctx, const hard_mesh *m)
{
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, m->v, m->nv, m->idx, m->nt, &s));
    return s;
}

/* ------------------------------------------------------------- generators */

/* n copies of one (tilted) triangle: every split candidate, box and hit t is
 * shared by all of them. */
static inline void hard_gen_identical(hard_mesh *m, size_t n)
{
    static const float a[3] = {0.1f, 0.2f, 0.3f}, b[3] = {1.3f, 0.1f, 0.7f},
                       c[3] = {0.4f, 1.1f, -0.2f};
    m->name = "identical";
    for (size_t i = 0; i < n; i++) hard_triangle(m, a, b, c);
}

/* Everything in the plane `axis` = 0.5: a grid of cells x cells squares
 * (two triangles each, sharing edges and vertices) plus `extra` small random
 * triangles overlapping it. The scene box has zero extent along `axis`. */
static inline void hard_gen_coplanar(hard_mesh *m, int axis, int cells, size_t extra, uint32_t seed)
{
    static const char *const names[3] = {"coplanar-x", "coplanar-y", "coplanar-z"};
    m->name = names[axis];
    int u = (axis + 1) % 3, w = (axis + 2) % 3;
    uint32_t *grid = hard_xrealloc(NULL, (size_t)(cells + 1) * (cells + 1) * sizeof(uint32_t));
    for (int i = 0; i <= cells; i++)
        for (int j = 0; j <= cells; j++) {
            float p[3];
            p[axis] = 0.5f;
            p[u] = (float)i / (float)cells * 4.0f - 2.0f;
            p[w] = (float)j / (float)cells * 4.0f - 2.0f;
            grid[i * (cells + 1) + j] = hard_vertex(m, p[0], p[1], p[2]);
        }
    for (int i = 0; i < cells; i++)
        for (int j = 0; j < cells; j++) {
            uint32_t a = grid[i * (cells + 1) + j], b = grid[(i + 1) * (cells + 1) + j];
            uint32_t c = grid[(i + 1) * (cells + 1) + j + 1], d = grid[i * (cells + 1) + j + 1];
            hard_triangle_ids(m, a, b, c);
            hard_triangle_ids(m, a, c, d);
        }
    free(grid);
    /* The extra triangles are small (up to 0.8 across): large ones
     * overlapping everywhere in a plane drive a greedy SAH to its depth
     * limit (every split still saves a little), which is a cost question
     * for the overlap scene, not a question of flatness. */
    uint32_t x = seed;
    for (size_t i = 0; i < extra; i++) {
        float p[3][3], cu = 1.6f * hard_sym(&x), cw = 1.6f * hard_sym(&x);
        for (int k = 0; k < 3; k++) {
            p[k][axis] = 0.5f;
            p[k][u] = cu + 0.4f * hard_sym(&x);
            p[k][w] = cw + 0.4f * hard_sym(&x);
        }
        hard_triangle(m, p[0], p[1], p[2]);
    }
}

/* n needles: length 0.5 .. 1.5 in random directions, width `width`, all
 * crossing the unit cube, so that their boxes are long, thin and overlap. */
static inline void hard_gen_needles(hard_mesh *m, size_t n, float width, uint32_t seed)
{
    m->name = "needles";
    uint32_t x = seed;
    for (size_t i = 0; i < n; i++) {
        float a[3], d[3], b[3], c[3], len2 = 0.0f;
        for (int k = 0; k < 3; k++) {
            a[k] = hard_unit(&x);
            d[k] = hard_sym(&x);
            len2 += d[k] * d[k];
        }
        if (len2 < 1e-6f) d[0] = 1.0f, len2 = 1.0f;
        float len = (0.5f + hard_unit(&x)) / sqrtf(len2);
        /* a unit-ish vector across the needle: d x (some axis not parallel) */
        int ax = fabsf(d[0]) < 0.5f * sqrtf(len2) ? 0 : 1;
        float e[3] = {0, 0, 0};
        e[ax] = 1.0f;
        float s[3] = {d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0]};
        float sl = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        for (int k = 0; k < 3; k++) {
            b[k] = a[k] + d[k] * len;
            c[k] = a[k] + d[k] * len * 0.5f + s[k] / sl * width;
        }
        hard_triangle(m, a, b, c);
    }
}

/* n random triangles of edge ~size with centres in the unit cube. */
static inline void hard_gen_soup(hard_mesh *m, const char *name, size_t n, float size, uint32_t seed)
{
    m->name = name;
    uint32_t x = seed;
    for (size_t i = 0; i < n; i++) {
        float c[3], p[3][3];
        for (int k = 0; k < 3; k++) c[k] = hard_unit(&x);
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) p[j][k] = c[k] + size * hard_sym(&x);
        hard_triangle(m, p[0], p[1], p[2]);
    }
}

/* n triangles all sharing one vertex (index 0, at `centre`), fanning out in
 * random directions to radius 1: every node near the centre overlaps them
 * all. */
static inline void hard_gen_fan(hard_mesh *m, size_t n, uint32_t seed)
{
    m->name = "shared-vertex";
    static const float centre[3] = {0.25f, 0.5f, 0.75f};
    uint32_t x = seed;
    uint32_t c = hard_vertex(m, centre[0], centre[1], centre[2]);
    for (size_t i = 0; i < n; i++) {
        uint32_t ids[2];
        for (int j = 0; j < 2; j++) {
            float d[3], l2 = 0.0f;
            do {
                l2 = 0.0f;
                for (int k = 0; k < 3; k++) {
                    d[k] = hard_sym(&x);
                    l2 += d[k] * d[k];
                }
            } while (l2 > 1.0f || l2 < 1e-4f);
            float l = sqrtf(l2);
            ids[j] = hard_vertex(m, centre[0] + d[0] / l, centre[1] + d[1] / l, centre[2] + d[2] / l);
        }
        hard_triangle_ids(m, c, ids[0], ids[1]);
    }
}

/* n triangles, two thirds of them degenerate (zero area: a repeated
 * vertex, or three collinear points, some of them axis-aligned) among
 * ordinary ones: boxes of zero volume, never a hit. */
static inline void hard_gen_degenerate(hard_mesh *m, size_t n, uint32_t seed)
{
    m->name = "degenerate";
    uint32_t x = seed;
    for (size_t i = 0; i < n; i++) {
        float a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = hard_unit(&x);
            b[k] = a[k] + 0.2f * hard_sym(&x);
            c[k] = a[k] + 0.2f * hard_sym(&x);
        }
        if (i % 3 == 0) memcpy(c, a, sizeof c); /* a repeated vertex */
        if (i % 3 == 1) {                        /* collinear: c on the line ab */
            for (int k = 0; k < 3; k++) c[k] = a[k] + 2.0f * (b[k] - a[k]);
            if (i % 2) b[1] = a[1], c[1] = a[1], b[2] = a[2], c[2] = a[2]; /* along x */
        }
        hard_triangle(m, a, b, c);
    }
}

/* A grid of axis-aligned unit cubes (12 triangles each) at integer
 * coordinates with gaps: faces, edges and vertices on the planes that
 * split candidates come from, and shared edges everywhere. */
static inline void hard_gen_cubes(hard_mesh *m, int per_axis)
{
    m->name = "cubes";
    for (int i = 0; i < per_axis; i++)
        for (int j = 0; j < per_axis; j++)
            for (int k = 0; k < per_axis; k++) {
                if ((i + j + k) % 3 == 1) continue; /* gaps so rays get through */
                uint32_t c[8];
                for (int q = 0; q < 8; q++)
                    c[q] = hard_vertex(m, (float)(2 * i + (q & 1)), (float)(2 * j + ((q >> 1) & 1)),
                                       (float)(2 * k + ((q >> 2) & 1)));
                /* faces as quads of corner indices, split along one diagonal */
                static const int face[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                               {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
                for (int f = 0; f < 6; f++) {
                    hard_triangle_ids(m, c[face[f][0]], c[face[f][1]], c[face[f][2]]);
                    hard_triangle_ids(m, c[face[f][0]], c[face[f][2]], c[face[f][3]]);
                }
            }
}

#endif
