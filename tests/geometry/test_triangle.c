/* tt_intersect_triangle, the one ray-triangle test of the project: hits and
 * misses, both facings, barycentrics, the half-open [tmin, tmax) interval,
 * and degenerate triangles that must never be hit. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "geometry/triangle.h"

static int hit(const float *org, const float *dir, float tmin, float tmax, const float *a,
               const float *b, const float *c, float *t, float *u, float *v)
{
    tt_wray r;
    tt_wray_init(&r, org, dir, tmin, tmax);
    return tt_intersect_triangle(&r, a, b, c, tmax, t, u, v);
}

static const float A[3] = {0, 0, -2}, B[3] = {1, 0, -2}, C[3] = {0, 1, -2};

static void test_hits_and_barycentrics(void)
{
    float t, u, v;
    const float down[3] = {0, 0, -1};
    const float o1[3] = {0.25f, 0.25f, 0};
    CHECK(hit(o1, down, 0, INFINITY, A, B, C, &t, &u, &v));
    CHECK(t == 2.0f);
    CHECK(fabsf(u - 0.25f) < 1e-6f && fabsf(v - 0.25f) < 1e-6f);
    /* u belongs to B, v to C */
    const float o2[3] = {0.6f, 0.1f, 5};
    CHECK(hit(o2, down, 0, INFINITY, A, B, C, &t, &u, &v));
    CHECK(fabsf(t - 7.0f) < 1e-5f && fabsf(u - 0.6f) < 1e-6f && fabsf(v - 0.1f) < 1e-6f);
    /* back face: from below, going up */
    const float up[3] = {0, 0, 1}, o3[3] = {0.25f, 0.25f, -4};
    CHECK(hit(o3, up, 0, INFINITY, A, B, C, &t, &u, &v));
    CHECK(t == 2.0f);
    /* oblique, unnormalized direction: t is in units of dir, and the point
     * rebuilt from the barycentrics is the point on the ray */
    const float o4[3] = {-1, -2, 3}, target[3] = {0.3f, 0.45f, -2};
    float d[3] = {2 * (target[0] - o4[0]), 2 * (target[1] - o4[1]), 2 * (target[2] - o4[2])};
    CHECK(hit(o4, d, 0, INFINITY, A, B, C, &t, &u, &v));
    CHECK(fabsf(t - 0.5f) < 1e-6f);
    for (int k = 0; k < 3; k++) {
        float p = (1 - u - v) * A[k] + u * B[k] + v * C[k];
        CHECK(fabsf(p - (o4[k] + t * d[k])) < 1e-5f);
        CHECK(fabsf(p - target[k]) < 1e-5f);
    }
}

static void test_misses(void)
{
    float t = -1, u, v;
    const float down[3] = {0, 0, -1}, up[3] = {0, 0, 1}, side[3] = {1, 0, 0};
    const float outside[3] = {0.75f, 0.75f, 0}; /* beyond the hypotenuse */
    CHECK(!hit(outside, down, 0, INFINITY, A, B, C, &t, &u, &v));
    const float left[3] = {-0.01f, 0.5f, 0};
    CHECK(!hit(left, down, 0, INFINITY, A, B, C, &t, &u, &v));
    /* the triangle is behind the origin */
    const float below[3] = {0.25f, 0.25f, -5};
    CHECK(!hit(below, down, 0, INFINITY, A, B, C, &t, &u, &v));
    const float above[3] = {0.25f, 0.25f, 0};
    CHECK(!hit(above, up, 0, INFINITY, A, B, C, &t, &u, &v));
    /* a ray in the triangle's plane, through its interior */
    const float in_plane[3] = {-1, 0.25f, -2};
    CHECK(!hit(in_plane, side, 0, INFINITY, A, B, C, &t, &u, &v));
    CHECK(t == -1); /* outputs untouched on a miss */
}

/* [tmin, tmax): a hit exactly at tmin counts, one exactly at tmax does not. */
static void test_interval(void)
{
    const float o[3] = {0.2f, 0.3f, 1.7f}, d[3] = {0.1f, -0.05f, -1.3f};
    float t0, t, u, v;
    CHECK(hit(o, d, 0, INFINITY, A, B, C, &t0, &u, &v));
    CHECK(hit(o, d, t0, INFINITY, A, B, C, &t, &u, &v) && t == t0);
    CHECK(!hit(o, d, nextafterf(t0, INFINITY), INFINITY, A, B, C, &t, &u, &v));
    CHECK(!hit(o, d, 0, t0, A, B, C, &t, &u, &v));
    CHECK(hit(o, d, 0, nextafterf(t0, INFINITY), A, B, C, &t, &u, &v) && t == t0);
    /* the tmax argument, not the ray's, bounds the test (closest-hit search
     * shrinks it as hits are found) */
    tt_wray r;
    tt_wray_init(&r, o, d, 0, INFINITY);
    CHECK(!tt_intersect_triangle(&r, A, B, C, t0, &t, &u, &v));
    CHECK(tt_intersect_triangle(&r, A, B, C, nextafterf(t0, INFINITY), &t, &u, &v));
}

/* Zero-area triangles (collinear or coincident vertices) are never hit, not
 * even by rays aimed exactly at their points from many directions. */
static void test_degenerate(void)
{
    const float P0[3] = {0, 0, -2}, P1[3] = {1, 1, -2}, P2[3] = {2, 2, -2}, P3[3] = {0.5f, 0.5f, -2};
    const float *tris[][3] = {{P0, P1, P2}, {P0, P0, P1}, {P1, P1, P1}, {P0, P2, P3}};
    const float targets[][3] = {{0, 0, -2}, {1, 1, -2}, {0.5f, 0.5f, -2}, {1.5f, 1.5f, -2}};
    int hits = 0, tried = 0;
    for (int k = 0; k < 4; k++) {
        for (int g = 0; g < 4; g++) {
            for (int i = 0; i < 26; i++) {
                /* origins on a cube of directions around the target */
                float o[3] = {targets[g][0] + (float)(i % 3 - 1) * 3.0f,
                              targets[g][1] + (float)(i / 3 % 3 - 1) * 3.0f,
                              targets[g][2] + (float)(i / 9 - 1) * 3.0f + 0.7f};
                float d[3] = {targets[g][0] - o[0], targets[g][1] - o[1], targets[g][2] - o[2]};
                if (d[0] == 0 && d[1] == 0 && d[2] == 0) continue;
                float t, u, v;
                tried++;
                hits += hit(o, d, 0, INFINITY, tris[k][0], tris[k][1], tris[k][2], &t, &u, &v);
            }
        }
    }
    CHECK(tried > 300);
    CHECK_MSG(hits == 0, "%d of %d rays hit a degenerate triangle", hits, tried);
}

/* Two triangles sharing an edge: a ray through any point of the edge hits
 * at least one of them, whatever the order of the vertices. */
static void test_shared_edge(void)
{
    const float a[3] = {0, 0, 0}, b[3] = {1.1f, 0.3f, 0.2f}, c[3] = {0.2f, 1.3f, -0.1f},
                d[3] = {1.4f, 1.1f, 0.4f};
    int misses = 0, rays = 0;
    /* interior points only: at the edge's end points the two triangles do
     * not cover a whole neighbourhood, and the rounded direction may pass
     * just beside the vertex */
    for (int i = 1; i < 64; i++) {
        float s = (float)i / 64.0f;
        float p[3]; /* the point s along the shared edge b-c */
        for (int k = 0; k < 3; k++) p[k] = b[k] + s * (c[k] - b[k]);
        for (int j = 0; j < 16; j++) {
            float ang = (float)j * 0.39f;
            float o[3] = {p[0] + 0.3f * cosf(ang), p[1] + 0.3f * sinf(ang), p[2] + 2.0f};
            float dir[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
            float t, u, v;
            int h1 = hit(o, dir, 0, INFINITY, a, b, c, &t, &u, &v);
            int h2 = hit(o, dir, 0, INFINITY, c, b, d, &t, &u, &v);
            rays++;
            misses += !(h1 || h2);
        }
    }
    CHECK_MSG(misses == 0, "%d of %d rays slipped through the shared edge", misses, rays);
}

int main(void)
{
    test_hits_and_barycentrics();
    test_misses();
    test_interval();
    test_degenerate();
    test_shared_edge();
    return tt_test_finish();
}
