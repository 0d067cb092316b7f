/* Synthetic scenes for the kd-tree tests, all with exact (integer or
 * dyadic) coordinates so that many triangles lie in split planes and many
 * vertices on cell edges: the hard cases of kd-tree construction and
 * traversal. */
#ifndef TT_TEST_KD_SCENES_H
#define TT_TEST_KD_SCENES_H

#include <stdlib.h>

#include "check.h"

typedef struct kd_mesh {
    float *v;
    uint32_t *idx;
    size_t nv, nt, cap_v, cap_t;
} kd_mesh;

static inline void kd_mesh_vertex(kd_mesh *m, float x, float y, float z)
{
    if (m->nv == m->cap_v) {
        m->cap_v = m->cap_v ? 2 * m->cap_v : 64;
        m->v = realloc(m->v, m->cap_v * 3 * sizeof(float));
        if (!m->v) exit(1);
    }
    m->v[3 * m->nv] = x;
    m->v[3 * m->nv + 1] = y;
    m->v[3 * m->nv + 2] = z;
    m->nv++;
}

static inline void kd_mesh_tri(kd_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->nt == m->cap_t) {
        m->cap_t = m->cap_t ? 2 * m->cap_t : 64;
        m->idx = realloc(m->idx, m->cap_t * 3 * sizeof(uint32_t));
        if (!m->idx) exit(1);
    }
    m->idx[3 * m->nt] = a;
    m->idx[3 * m->nt + 1] = b;
    m->idx[3 * m->nt + 2] = c;
    m->nt++;
}

/* An axis-aligned box as 12 triangles. */
static inline void kd_mesh_cube(kd_mesh *m, float x0, float y0, float z0, float x1, float y1, float z1)
{
    uint32_t b = (uint32_t)m->nv;
    for (int i = 0; i < 8; i++)
        kd_mesh_vertex(m, (i & 1) ? x1 : x0, (i & 2) ? y1 : y0, (i & 4) ? z1 : z0);
    static const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                      {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (int i = 0; i < 12; i++) kd_mesh_tri(m, b + f[i][0], b + f[i][1], b + f[i][2]);
}

static inline tt_scene *kd_mesh_scene(tt_context *ctx, kd_mesh *m)
{
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, m->v, m->nv, m->idx, m->nt, &s));
    free(m->v);
    free(m->idx);
    m->v = NULL;
    m->idx = NULL;
    m->nv = m->nt = m->cap_v = m->cap_t = 0;
    return s;
}

static inline uint32_t kd_rand(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}

static inline float kd_unit(uint32_t *x) { return (float)(kd_rand(x) >> 8) * (1.0f / 16777216.0f); }

/* A city of cubes on a floor: shared coordinates, faces on common planes,
 * a floor of unit squares (many coplanar triangles and shared edges). */
static inline tt_scene *kd_scene_blocks(tt_context *ctx)
{
    kd_mesh m = {0};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            float h = (float)(1 + (i * 3 + j * 5) % 4);
            kd_mesh_cube(&m, 2.0f * i, 0.0f, 2.0f * j, 2.0f * i + 1.0f, h, 2.0f * j + 1.0f);
            if ((i + j) % 3 == 0) /* a second block stacked on the first */
                kd_mesh_cube(&m, 2.0f * i, h, 2.0f * j, 2.0f * i + 0.5f, h + 1.0f, 2.0f * j + 0.5f);
        }
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++) {
            uint32_t b = (uint32_t)m.nv;
            kd_mesh_vertex(&m, i - 0.5f, 0.0f, j - 0.5f);
            kd_mesh_vertex(&m, i + 0.5f, 0.0f, j - 0.5f);
            kd_mesh_vertex(&m, i - 0.5f, 0.0f, j + 0.5f);
            kd_mesh_vertex(&m, i + 0.5f, 0.0f, j + 0.5f);
            kd_mesh_tri(&m, b, b + 2, b + 1);
            kd_mesh_tri(&m, b + 1, b + 2, b + 3);
        }
    return kd_mesh_scene(ctx, &m);
}

/* Random triangles all in the plane z = 0.25. */
static inline tt_scene *kd_scene_coplanar(tt_context *ctx, int n, uint32_t seed)
{
    kd_mesh m = {0};
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++)
            kd_mesh_vertex(&m, kd_unit(&seed) * 4.0f, kd_unit(&seed) * 4.0f, 0.25f);
        kd_mesh_tri(&m, 3 * i, 3 * i + 1, 3 * i + 2);
    }
    return kd_mesh_scene(ctx, &m);
}

/* n copies of the same triangle. */
static inline tt_scene *kd_scene_identical(tt_context *ctx, int n)
{
    kd_mesh m = {0};
    kd_mesh_vertex(&m, 0.0f, 0.0f, 0.0f);
    kd_mesh_vertex(&m, 1.0f, 0.0f, 0.5f);
    kd_mesh_vertex(&m, 0.0f, 1.0f, 1.0f);
    for (int i = 0; i < n; i++) kd_mesh_tri(&m, 0, 1, 2);
    return kd_mesh_scene(ctx, &m);
}

/* Random triangles of all sizes and shapes, some degenerate (collinear or a
 * point), in the unit cube. */
static inline tt_scene *kd_scene_soup(tt_context *ctx, int n, uint32_t seed)
{
    kd_mesh m = {0};
    for (int i = 0; i < n; i++) {
        float c[3], s = (kd_rand(&seed) % 4 == 0) ? 0.5f : 0.05f;
        for (int k = 0; k < 3; k++) c[k] = kd_unit(&seed);
        uint32_t b = (uint32_t)m.nv;
        for (int j = 0; j < 3; j++)
            kd_mesh_vertex(&m, c[0] + s * (kd_unit(&seed) - 0.5f), c[1] + s * (kd_unit(&seed) - 0.5f),
                           c[2] + s * (kd_unit(&seed) - 0.5f));
        if (i % 17 == 0) { /* collinear */
            for (int k = 0; k < 3; k++)
                m.v[3 * (b + 2) + k] = 0.5f * (m.v[3 * b + k] + m.v[3 * (b + 1) + k]);
        }
        if (i % 29 == 0) /* a point */
            for (int k = 0; k < 3; k++) m.v[3 * (b + 1) + k] = m.v[3 * (b + 2) + k] = m.v[3 * b + k];
        kd_mesh_tri(&m, b, b + 1, b + 2);
    }
    return kd_mesh_scene(ctx, &m);
}

#endif
