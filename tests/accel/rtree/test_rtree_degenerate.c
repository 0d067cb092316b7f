/* Degenerate inputs, every strategy x traversal and several (m, M), built,
 * checked and compared ray by ray with bruteforce: 0, 1 and 2 triangles;
 * many identical triangles; an axis-aligned planar grid (every box has zero
 * volume, so the volume and overlap criteria tie everywhere and only the
 * surface fallback keeps the tree sane — its SAH cost must stay close to
 * min-surface's); zero-area triangles mixed in. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"
#include "rtree_test.h"

static tt_scene *make_scene(tt_context *ctx, const float *v, size_t nv, const uint32_t *idx,
                            size_t nt)
{
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, nv, idx, nt, &s));
    return s;
}

/* A g x g grid of unit quads (two triangles each) in the plane z = 0. */
static tt_scene *grid_scene(tt_context *ctx, int g)
{
    size_t nv = (size_t)(g + 1) * (g + 1), nt = (size_t)g * g * 2;
    float *v = malloc(nv * 3 * sizeof *v);
    uint32_t *idx = malloc(nt * 3 * sizeof *idx);
    if (!v || !idx) exit(1);
    for (int y = 0; y <= g; y++)
        for (int x = 0; x <= g; x++) {
            float *p = v + 3 * ((size_t)y * (g + 1) + x);
            p[0] = (float)x;
            p[1] = (float)y;
            p[2] = 0.0f;
        }
    size_t t = 0;
    for (int y = 0; y < g; y++)
        for (int x = 0; x < g; x++) {
            uint32_t a = (uint32_t)(y * (g + 1) + x), b = a + 1, c = a + (uint32_t)g + 1,
                     d = c + 1;
            uint32_t q[6] = {a, b, d, a, d, c};
            memcpy(idx + 3 * t, q, sizeof q);
            t += 2;
        }
    tt_scene *s = make_scene(ctx, v, nv, idx, nt);
    free(v);
    free(idx);
    return s;
}

typedef struct sah_get {
    double sah;
} sah_get;

static void get_sah(void *user, const char *key, double value)
{
    if (!strcmp(key, "sah_cost")) ((sah_get *)user)->sah = value;
}

/* Rays aimed at the scene from around it and from inside, besides the
 * shared random rays. */
static size_t compare_aimed(const tt_scene *scene, const tt_accel *a, const tt_accel *bf)
{
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    if (!(lo[0] <= hi[0])) lo[0] = lo[1] = lo[2] = -1.0f, hi[0] = hi[1] = hi[2] = 1.0f;
    tt_ray rays[400];
    size_t n = 0;
    uint32_t x = 7;
    for (int i = 0; i < 400; i++) {
        tt_ray *r = &rays[n++];
        for (int k = 0; k < 3; k++) {
            x = x * 1664525u + 1013904223u;
            float f = (float)(x >> 8) / 16777216.0f;
            float target = lo[k] + (hi[k] - lo[k]) * f;
            float e = hi[k] - lo[k] + 1.0f;
            x = x * 1664525u + 1013904223u;
            float g = (float)(x >> 8) / 16777216.0f;
            r->org[k] = (i & 1) ? lo[k] - e + 3.0f * e * g : target + (g - 0.5f) * 0.1f;
            r->dir[k] = target - r->org[k];
        }
        if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) r->dir[2] = 1.0f;
        r->tmin = 0.0f;
        r->tmax = (i % 3 == 0) ? 1.0f : INFINITY;
    }
    return tt_test_compare_rays(a, bf, rays, n);
}

static void all_configs(tt_context *ctx, const tt_scene *scene, const char *what)
{
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    for (int s = 0; s < 5; s++)
        for (int tr = 0; tr < 4; tr++)
            for (int mm = 0; mm < RT_MM_COUNT; mm += 3) { /* (2,4) and (4,16) */
                tt_build_options o = rt_options(s, tr, rt_mm_list[mm].m, rt_mm_list[mm].M);
                o.rtree.split = tr == 3 ? TT_RTREE_SPLIT_QUADRATIC : TT_RTREE_SPLIT_RSTAR;
                tt_accel *a = rt_build_checked(ctx, scene, &o);
                if (!a) continue;
                size_t bad = tt_test_compare_random(scene, a, bf, 300, 5u);
                bad += compare_aimed(scene, a, bf);
                CHECK_MSG(bad == 0, "%s, %s: %zu rays disagree", what, rt_describe(&o), bad);
                tt_accel_destroy(a);
            }
    tt_accel_destroy(bf);
}

static void small_counts(tt_context *ctx)
{
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    const uint32_t idx[] = {0, 1, 2, 1, 3, 4};
    for (size_t nt = 0; nt <= 2; nt++) {
        tt_scene *s = make_scene(ctx, v, 5, idx, nt);
        char what[32];
        snprintf(what, sizeof what, "%zu triangles", nt);
        all_configs(ctx, s, what);
        tt_scene_destroy(s);
    }
}

static void identical(tt_context *ctx)
{
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.5f};
    uint32_t idx[3 * 60];
    for (int i = 0; i < 60; i++) idx[3 * i] = 0, idx[3 * i + 1] = 1, idx[3 * i + 2] = 2;
    tt_scene *s = make_scene(ctx, v, 3, idx, 60);
    all_configs(ctx, s, "60 identical triangles");
    tt_scene_destroy(s);
}

static void zero_area(tt_context *ctx)
{
    /* points and segments as triangles, some with a real one in between */
    const float v[] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 0, 1, 0, 1, 0, 0, 3, 3, 3};
    const uint32_t idx[] = {0, 0, 0, 0, 1, 2, 0, 3, 4, 1, 1, 1, 5, 5, 2, 0, 1, 5};
    tt_scene *s = make_scene(ctx, v, 6, idx, 6);
    all_configs(ctx, s, "zero-area triangles");
    tt_scene_destroy(s);
}

static void planar_grid(tt_context *ctx)
{
    tt_scene *s = grid_scene(ctx, 16); /* 512 flat triangles */
    all_configs(ctx, s, "planar grid");
    /* sanity of the zero-volume builds: every strategy's SAH cost within a
     * small factor of min-surface's (without the surface fallback the
     * volume-based ones always pick the first entry and come out over twice
     * as costly here) */
    double sah[5];
    for (int st = 0; st < 5; st++) {
        tt_build_options o = rt_options(st, TT_RTREE_AUTO, 2, 4);
        tt_accel *a = rt_build_checked(ctx, s, &o);
        sah_get g = {0};
        if (a) tt_accel_statistics(a, get_sah, &g);
        sah[st] = g.sah;
        tt_accel_destroy(a);
    }
    for (int st = 0; st < 5; st++)
        CHECK_MSG(sah[st] > 0 && sah[st] < 1.5 * sah[TT_RTREE_MIN_SURFACE],
                  "planar grid: %s SAH cost %g vs min-surface %g", rt_strategy_names[st], sah[st],
                  sah[TT_RTREE_MIN_SURFACE]);
    tt_scene_destroy(s);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    small_counts(ctx);
    identical(ctx);
    zero_area(ctx);
    planar_grid(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
