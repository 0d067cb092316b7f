/* The engine table's ray batches and answer checks (cli/bench/bench_yard_rays.c,
 * bench_yard_check.c), compiled into this program:
 *  - AO rays: hits x samples of them, from the offset origin on the side the
 *    primary ray came from, unit directions in that hemisphere with the
 *    cosine density (mean cos = 2/3, uniform azimuth), [0, 0.1 diagonal),
 *    the same rays on every call; none from a miss;
 *  - shadow rays: one per hit, compacted;
 *  - the rays bruteforce retraces: sorted, unique, the even sample plus the
 *    disagreeing ones; the agreement counters. */
#include <math.h>
#include <string.h>

#include "bench/bench_yard_check.c"
#include "bench/bench_yard_rays.c"
#include "check.h"

/* A 2 x 2 square in z = 0 (two triangles), seen from above or below. */
static tt_scene *square(tt_context *ctx)
{
    const float v[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    tt_scene *s = NULL;
    CHECK_OK(ctx, tt_scene_create(ctx, v, 4, idx, 2, &s));
    return s;
}

/* n rays straight down (or up) onto the square, a few past its edge. */
static void rays_at(tt_ray *r, size_t n, float z)
{
    for (size_t i = 0; i < n; i++) {
        const float x = -1.2f + 2.4f * (float)(i % 37) / 36.0f;
        const float y = -0.9f + 1.8f * (float)(i / 37 % 29) / 28.0f;
        r[i] = (tt_ray){{x, y, z}, 0.0f, {0.0f, 0.0f, z > 0 ? -1.0f : 1.0f}, INFINITY};
    }
}

static void test_ao(tt_context *ctx, tt_scene *s, const tt_accel *bf, float z)
{
    enum { N = 37 * 29, SAMPLES = 8 };
    static tt_ray prim[N], ao[N * SAMPLES], again[N * SAMPLES];
    static tt_hit hits[N];
    rays_at(prim, N, z);
    CHECK_OK(ctx, tt_intersect(bf, prim, N, hits, NULL, NULL));
    size_t nh = 0;
    for (size_t i = 0; i < N; i++) nh += hits[i].prim != TT_INVALID_ID;
    CHECK(nh > N / 2 && nh < N); /* some rays pass the edge */
    const size_t m = yard_ao_rays(s, prim, hits, N, SAMPLES, ao);
    CHECK_MSG(m == nh * SAMPLES, "%zu AO rays for %zu hits", m, nh);
    CHECK(yard_ao_rays(s, prim, hits, N, SAMPLES, again) == m);
    CHECK(memcmp(ao, again, m * sizeof *ao) == 0);
    const float diag = sqrtf(8.0f), side = z > 0 ? 1.0f : -1.0f;
    double mean_cos = 0.0, mean_x = 0.0, mean_y = 0.0, upper = 0.0;
    int bad_dir = 0, bad_org = 0, bad_t = 0;
    size_t j = 0;
    for (size_t i = 0; i < N; i++) {
        if (hits[i].prim == TT_INVALID_ID) continue;
        for (int k = 0; k < SAMPLES; k++, j++) {
            const tt_ray *r = &ao[j];
            const float len = sqrtf(r->dir[0] * r->dir[0] + r->dir[1] * r->dir[1] +
                                    r->dir[2] * r->dir[2]);
            const float c = r->dir[2] * side; /* cosine to the normal facing the eye */
            bad_dir += fabsf(len - 1.0f) > 1e-5f || !(c > 0.0f);
            bad_org += fabsf(r->org[0] - prim[i].org[0]) > 1e-6f ||
                       fabsf(r->org[1] - prim[i].org[1]) > 1e-6f ||
                       /* eps off the surface, up to the hit's own rounding */
                       fabsf(r->org[2] - side * 1e-4f * diag) > 2e-6f;
            bad_t += r->tmin != 0.0f || fabsf(r->tmax - 0.1f * diag) > 1e-6f;
            mean_cos += c;
            mean_x += r->dir[0];
            mean_y += r->dir[1];
            upper += c * c > 0.5f; /* half of a cosine density lies above 45 degrees */
        }
    }
    CHECK_MSG(bad_dir == 0 && bad_org == 0 && bad_t == 0, "%d bad directions, %d origins, %d intervals", bad_dir, bad_org, bad_t);
    mean_cos /= (double)m, mean_x /= (double)m, mean_y /= (double)m, upper /= (double)m;
    CHECK_MSG(fabs(mean_cos - 2.0 / 3.0) < 0.015, "mean cosine %.4f, expected 2/3", mean_cos);
    CHECK_MSG(fabs(mean_x) < 0.02 && fabs(mean_y) < 0.02, "mean direction %.4f %.4f", mean_x, mean_y);
    CHECK_MSG(fabs(upper - 0.5) < 0.02, "%.4f above 45 degrees, expected 0.5", upper);

    /* shadow rays: one per hit, in order, towards the light */
    tt_camera cam = {{0, 0, 5 * side}, {0, 0, 0}, {0, 1, 0}, 40.0f, {0.5f, 0.5f, 3 * side}, 1};
    static tt_ray sh[N];
    const size_t ns = yard_shadow_rays(s, &cam, prim, hits, N, sh);
    CHECK(ns == nh);
    CHECK(sh[0].dir[2] * side > 0.0f && sh[0].tmax > 0.0f);
}

static void test_pick(void)
{
    enum { N = 1000 };
    static uint8_t dis[N];
    static size_t idx[300];
    memset(dis, 0, sizeof dis);
    dis[3] = dis[500] = dis[999] = 1;
    size_t m = yard_pick_rays(N, dis, idx, 300);
    CHECK(m > YARD_BRUTEFORCE_SAMPLE && m <= YARD_BRUTEFORCE_SAMPLE + 3);
    int sorted = 1, has3 = 0, has999 = 0;
    for (size_t i = 0; i < m; i++) {
        if (i && idx[i] <= idx[i - 1]) sorted = 0;
        has3 |= idx[i] == 3;
        has999 |= idx[i] == 999;
        CHECK(idx[i] < N);
    }
    CHECK(sorted && has3 && has999);
    /* a small batch: every ray once */
    m = yard_pick_rays(10, NULL, idx, 300);
    CHECK(m == 10 && idx[0] == 0 && idx[9] == 9);
    /* more disagreements than the cap: the cap holds */
    memset(dis, 1, sizeof dis);
    m = yard_pick_rays(N, dis, idx, 300);
    CHECK(m <= YARD_BRUTEFORCE_SAMPLE + YARD_BRUTEFORCE_DISAGREE);
}

static void test_agree(void)
{
    tt_hit a[3] = {{1.0f, 0.1f, 0.2f, 4}, {INFINITY, 0, 0, TT_INVALID_ID}, {2.0f, 0.3f, 0.3f, 7}};
    tt_hit b[3] = {a[0], a[1], a[2]};
    CHECK(yard_same_hits(a, b, 3) == 3 && yard_agree_hits(a, b, 3) == 3);
    b[0].u = nextafterf(b[0].u, 1.0f); /* the same triangle, u one ulp off */
    b[2].prim = 8;
    CHECK(yard_same_hits(a, b, 3) == 1 && yard_agree_hits(a, b, 3) == 2);
    const uint8_t f1[4] = {0, 1, 1, 0}, f2[4] = {0, 1, 0, 0};
    CHECK(yard_agree_flags(f1, f2, 4) == 3);
}

int main(void)
{
    tt_context *ctx = NULL;
    CHECK_OK(ctx, tt_context_create(NULL, &ctx));
    tt_scene *s = square(ctx);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *bf = NULL;
    CHECK_OK(ctx, tt_accel_build(ctx, s, &bo, &bf));
    test_ao(ctx, s, bf, 3.0f);  /* from above: the normal +z */
    test_ao(ctx, s, bf, -3.0f); /* from below: flipped to -z */
    test_pick();
    test_agree();
    tt_accel_destroy(bf);
    tt_scene_destroy(s);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
