/* Rays lying exactly in the face planes of the R-tree's boxes, through every
 * traversal, compared ray by ray with bruteforce (closest hit and occlusion,
 * fast and counting variants). The scenes have all their vertices on integer
 * coordinates, so every box of the tree has its faces on integer planes; the
 * rays run in the integer planes x = c, y = c or z = c with a zero direction
 * component of either sign, and meet the geometry on its edges (the
 * watertight triangle test hits them there). With the finite 1e30 stand-in
 * for 1/0 the box test dropped rays in a box's upper face plane (lower for
 * -0), e.g. the grid ray from (1, 0.5, 1) going (0, 0, -1): bruteforce hit
 * the grid's edge x = 1 and the R-tree missed it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"
#include "rtree_test.h"

/* A g x g grid of unit quads in the plane z = 0. */
static tt_scene *grid_scene(tt_context *ctx, int g)
{
    size_t nv = (size_t)(g + 1) * (g + 1), nt = (size_t)g * g * 2;
    float *v = malloc(nv * 3 * sizeof *v);
    uint32_t *idx = malloc(nt * 3 * sizeof *idx);
    if (!v || !idx) exit(1);
    for (int y = 0; y <= g; y++)
        for (int x = 0; x <= g; x++) {
            float *p = v + 3 * ((size_t)y * (g + 1) + x);
            p[0] = (float)x, p[1] = (float)y, p[2] = 0.0f;
        }
    size_t t = 0;
    for (int y = 0; y < g; y++)
        for (int x = 0; x < g; x++) {
            uint32_t a = (uint32_t)(y * (g + 1) + x), b = a + 1, c = a + (uint32_t)g + 1, d = c + 1;
            uint32_t q[6] = {a, b, d, a, d, c};
            memcpy(idx + 3 * t, q, sizeof q);
            t += 2;
        }
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, nv, idx, nt, &s));
    free(v);
    free(idx);
    return s;
}

/* Unit cubes (12 triangles each) on a g^3 lattice, every cell whose
 * coordinates sum to an even number: a 3D checkerboard whose boxes have
 * faces on integer planes in all three axes. */
static tt_scene *cubes_scene(tt_context *ctx, int g)
{
    static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                     {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    static const uint32_t face[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                         {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                         {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    size_t cells = (size_t)g * g * g;
    float *v = malloc(cells * 8 * 3 * sizeof *v);
    uint32_t *idx = malloc(cells * 12 * 3 * sizeof *idx);
    if (!v || !idx) exit(1);
    size_t nv = 0, nt = 0;
    for (int z = 0; z < g; z++)
        for (int y = 0; y < g; y++)
            for (int x = 0; x < g; x++) {
                if ((x + y + z) & 1) continue;
                for (int c = 0; c < 12; c++)
                    for (int i = 0; i < 3; i++) idx[3 * nt + 3 * (size_t)c + i] = (uint32_t)nv + face[c][i];
                nt += 12;
                for (int c = 0; c < 8; c++, nv++) {
                    v[3 * nv] = (float)(x + corner[c][0]);
                    v[3 * nv + 1] = (float)(y + corner[c][1]);
                    v[3 * nv + 2] = (float)(z + corner[c][2]);
                }
            }
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, nv, idx, nt, &s));
    free(v);
    free(idx);
    return s;
}

/* Rays in the planes {axis k = c}, c = -1 .. g + 1, dir[k] = +0 or -0,
 * travelling along j != k (both ways) from outside the scene, the third
 * axis m held at integers and half-integers or slanted. */
static size_t face_plane_rays(int g, tt_ray *rays, size_t cap)
{
    static const float slope[3] = {0.0f, 0.375f, -0.625f};
    static const float moff[4] = {0.0f, 0.5f, 1.0f, 2.5f};
    size_t n = 0;
    for (int k = 0; k < 3; k++)
        for (int c = -1; c <= g + 1; c++)
            for (int zs = 0; zs < 2; zs++)
                for (int j = 0; j < 3; j++)
                    for (int js = 0; js < 2; js++)
                        for (int mi = 0; mi < 4; mi++)
                            for (int si = 0; si < 3; si++) {
                                if (j == k) continue;
                                const int m = 3 - j - k;
                                if (n == cap) return n;
                                tt_ray *r = &rays[n++];
                                r->org[k] = (float)c;
                                r->dir[k] = zs ? -0.0f : 0.0f;
                                r->org[j] = js ? (float)g + 1.5f : -1.5f;
                                r->dir[j] = js ? -1.0f : 1.0f;
                                r->org[m] = moff[mi] + (float)(c & 1);
                                r->dir[m] = slope[si];
                                r->tmin = 0.0f;
                                /* a short tmax on some rays: occlusion ends inside the scene */
                                r->tmax = (si == 2 && mi == 1) ? 0.5f * (float)g + 1.5f : INFINITY;
                            }
    return n;
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    static tt_ray rays[8192];
    tt_scene *scenes[2] = {grid_scene(ctx, 8), cubes_scene(ctx, 4)};
    const char *names[2] = {"grid 8x8", "cubes 4^3"};
    const int g[2] = {8, 4};

    /* the brief's repro, checked explicitly */
    {
        tt_accel *bf = tt_test_build_default(ctx, scenes[0], "bruteforce");
        tt_ray r = {{1, 0.5f, 1}, 0.0f, {0, 0, -1}, INFINITY};
        for (int tr = 1; tr < 4; tr++) {
            tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, tr, 2, 4);
            tt_accel *a = rt_build_checked(ctx, scenes[0], &o);
            if (!a) continue;
            tt_hit h, hb;
            int occ = 0;
            CHECK_OK(ctx, tt_intersect1(a, &r, &h));
            CHECK_OK(ctx, tt_intersect1(bf, &r, &hb));
            CHECK_OK(ctx, tt_occluded1(a, &r, &occ));
            CHECK_MSG(hb.prim != TT_INVALID_ID && h.prim != TT_INVALID_ID && h.t == 1.0f,
                      "%s: ray (1, 0.5, 1) down on the grid: t %g (bruteforce %g)",
                      rt_describe(&o), (double)h.t, (double)hb.t);
            CHECK(occ == 1);
            tt_accel_destroy(a);
        }
        tt_accel_destroy(bf);
    }

    for (int s = 0; s < 2; s++) {
        tt_accel *bf = tt_test_build_default(ctx, scenes[s], "bruteforce");
        const size_t n = face_plane_rays(g[s], rays, sizeof rays / sizeof rays[0]);
        for (int tr = 0; tr < 4; tr++)
            for (int mm = 0; mm < RT_MM_COUNT; mm++) {
                tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, tr, rt_mm_list[mm].m,
                                                rt_mm_list[mm].M);
                tt_accel *a = rt_build_checked(ctx, scenes[s], &o);
                if (!a) continue;
                const size_t bad = tt_test_compare_rays(a, bf, rays, n);
                CHECK_MSG(bad == 0, "%s, %s: %zu of %zu face-plane rays disagree", names[s],
                          rt_describe(&o), bad, n);
                tt_accel_destroy(a);
            }
        tt_accel_destroy(bf);
        tt_scene_destroy(scenes[s]);
    }
    tt_context_destroy(ctx);
    return tt_test_finish();
}
