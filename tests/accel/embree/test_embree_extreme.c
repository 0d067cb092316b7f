/* The embree structure on legal rays that libembree itself cannot take:
 * direction components beyond its FLT_LARGE (1.844e18), tiny directions,
 * origins beyond 1e18. libembree asserts ray.valid() and the packaged build
 * aborts the process on such rays, so before this fix any of them killed the
 * caller. Now every one must come back, and with the bruteforce answer:
 * - the crash rays found by tests/hard, on their scenes;
 * - random rays on a soup whose directions are scaled by powers of two from
 *   2^-140 to 2^120 (and by 1e20, 7e19, 1e-20); those below the ray
 *   contract's 2^-80 must be refused by both, the others must get the answer
 *   bruteforce gives on the same scaled ray whenever Embree agreed on the
 *   unscaled one (Embree's own edge test is not held to exactness; see
 *   src/accel/embree/embree.c), and in every case a valid answer (a miss, or
 *   a triangle id in range with t in [tmin, tmax));
 * - intervals whose ends would over- or underflow under the rescaling and
 *   directions whose components span more than float's range (answered by
 *   bruteforce inside the structure: must be bit-identical);
 * - origins at 2e18 and 3e38 (bruteforce inside the structure as well).
 * Skips (77) when the build has no Embree. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "compare.h"
#include "../../hard/hard_scenes.h"

/* A miss, or a triangle in range with t inside the ray's interval. */
static int valid_hit(const tt_scene *s, const tt_ray *r, const tt_hit *h)
{
    if (h->prim == TT_INVALID_ID) return h->t == INFINITY;
    return h->prim < tt_scene_triangle_count(s) && h->t >= r->tmin && h->t < r->tmax;
}

/* Both calls, both variants: TT_OK and a valid answer. Returns 1 if so and
 * fills the fast variant's hit and occlusion. */
static int trace_valid(tt_context *ctx, const tt_scene *s, const tt_accel *e, const tt_ray *r,
                       tt_hit *h, int *occ, const char *what)
{
    tt_hit hc;
    int oc = -1;
    tt_ray_stats st;
    memset(&st, 0, sizeof st);
    tt_trace_args args = {TT_INVALID_ID, TT_INVALID_ID, &st};
    *occ = -1;
    tt_status a = tt_intersect1(e, r, h), b = tt_occluded1(e, r, occ);
    tt_status c = tt_intersect1_ex(e, r, &hc, &args), d = tt_occluded1_ex(e, r, &oc, &args);
    int ok = a == TT_OK && b == TT_OK && c == TT_OK && d == TT_OK && valid_hit(s, r, h) &&
             valid_hit(s, r, &hc) && (*occ == 0 || *occ == 1) && oc == *occ && st.rays == 2 &&
             hc.prim == h->prim && hc.t == h->t;
    CHECK_MSG(ok,
              "%s: org %.9g %.9g %.9g dir %.9g %.9g %.9g t [%g, %g): status %d %d %d %d, prim %u "
              "t %.9g occluded %d (counting: prim %u t %.9g occluded %d): %s",
              what, r->org[0], r->org[1], r->org[2], r->dir[0], r->dir[1], r->dir[2], r->tmin,
              r->tmax, a, b, c, d, h->prim, h->t, *occ, hc.prim, hc.t, oc,
              a || b ? tt_context_last_error(ctx) : "");
    return ok;
}

/* The ray must come back valid and equal bruteforce exactly (prim, t, u, v
 * bits and occlusion): for rays the structure answers with the bruteforce
 * template, or where Embree's test is not in doubt. */
static void expect_bruteforce(tt_context *ctx, const tt_scene *s, const tt_accel *e,
                              const tt_accel *bf, const tt_ray *r, const char *what)
{
    tt_hit h, want;
    int occ, want_occ = -1;
    if (!trace_valid(ctx, s, e, r, &h, &occ, what)) return;
    REQUIRE_OK(ctx, tt_intersect1(bf, r, &want));
    REQUIRE_OK(ctx, tt_occluded1(bf, r, &want_occ));
    CHECK_MSG(h.prim == want.prim && memcmp(&h.t, &want.t, sizeof h.t) == 0 && occ == want_occ,
              "%s: embree prim %u t %.9g occluded %d, bruteforce prim %u t %.9g occluded %d", what,
              h.prim, h.t, occ, want.prim, want.t, want_occ);
}

/* A direction whose largest component is below 2^-80 (the ray contract's
 * TT_RAY_DIR_MIN): both structures refuse it, fast and counting calls. */
static int too_short(const tt_ray *r)
{
    return fmaxf(fabsf(r->dir[0]), fmaxf(fabsf(r->dir[1]), fabsf(r->dir[2]))) < 0x1p-80f;
}

static void expect_refused(const tt_accel *e, const tt_accel *bf, const tt_ray *r, const char *what)
{
    CHECK_MSG(tt_test_refused(e, bf, r), "%s: a direction below 2^-80 was traced", what);
}

static void test_crash_rays(tt_context *ctx)
{
    /* from tests/hard/test_hard_cases.c: direction components of 7e19 */
    hard_mesh m = {0};
    hard_gen_identical(&m, 1);
    tt_scene *s = hard_scene(ctx, &m);
    tt_accel *e = tt_test_build_default(ctx, s, "embree"), *bf = tt_test_build_default(ctx, s, "bruteforce");
    tt_ray huge = {{0.67672205f, -0.0608524084f, 0.392681003f}, 0.0f,
                   {7.39144933e+19f, -0.0f, -3.94822619e+19f}, INFINITY};
    expect_bruteforce(ctx, s, e, bf, &huge, "direction components of 7e19");
    /* ... aimed at the triangle's centroid, so that it hits */
    float c[3] = {(0.1f + 1.3f + 0.4f) / 3, (0.2f + 0.1f + 1.1f) / 3, (0.3f + 0.7f - 0.2f) / 3};
    tt_ray at = {{0.5f, 0.5f, 5.0f}, 0.0f, {0, 0, 0}, INFINITY};
    for (int k = 0; k < 3; k++) at.dir[k] = (c[k] - at.org[k]) * 0x1p70f;
    expect_bruteforce(ctx, s, e, bf, &at, "aimed at the centroid, direction * 2^70");
    tt_hit h;
    REQUIRE_OK(ctx, tt_intersect1(e, &at, &h));
    CHECK_MSG(h.prim == 0, "the 2^70 ray aimed at the centroid missed");
    tt_accel_destroy(e);
    tt_accel_destroy(bf);
    tt_scene_destroy(s);
    hard_mesh_free(&m);

    /* the tiny direction (1e-40, 6.3e-21, 6.5e-22) on the flat scene */
    hard_gen_coplanar(&m, 1, 8, 100, 99u);
    s = hard_scene(ctx, &m);
    e = tt_test_build_default(ctx, s, "embree");
    bf = tt_test_build_default(ctx, s, "bruteforce");
    tt_ray tiny = {{1.93726909f, -2.96994305f, 1.13657498f}, 0.0f,
                   {9.9999461e-41f, 6.32239305e-21f, 6.54464957e-22f}, INFINITY};
    expect_bruteforce(ctx, s, e, bf, &tiny, "a tiny direction (1e-40, 6.3e-21, 6.5e-22)");
    REQUIRE_OK(ctx, tt_intersect1(bf, &tiny, &h));
    CHECK_MSG(h.prim != TT_INVALID_ID, "the tiny-direction ray should hit the plane y = 0.5");
    tt_accel_destroy(e);
    tt_accel_destroy(bf);
    tt_scene_destroy(s);
    hard_mesh_free(&m);
}

/* Random rays from around a soup, aimed at points in it, with the direction
 * scaled by 2^k (exact: the same points at t / 2^k) and by non-powers of two. */
static void test_scaled_directions(tt_context *ctx)
{
    hard_mesh m = {0};
    hard_gen_soup(&m, "soup", 400, 0.1f, 7u);
    tt_scene *s = hard_scene(ctx, &m);
    tt_accel *e = tt_test_build_default(ctx, s, "embree"), *bf = tt_test_build_default(ctx, s, "bruteforce");
    static const int exps[] = {-140, -126, -100, -70, -64, -21, -20, 0, 20, 21, 60, 64, 66, 100, 120};
    static const float odd[] = {1e20f, 7.39e19f, 1e-20f, 1e37f};
    /* Directions so tiny that the hits would lie near FLT_MAX: the watertight
     * test itself overflows there (its 1 / dir[kz] is ~3e38), so the ray
     * contract refuses them (below 2^-80), as it does 2^-140 .. 2^-100 above. */
    static const float beyond[] = {3e-39f, 1e-42f, 0x1p-149f};
    uint32_t x = 12345u;
    size_t compared = 0, hits = 0;
    for (int i = 0; i < 150; i++) {
        tt_ray base;
        float target[3];
        for (int k = 0; k < 3; k++) {
            base.org[k] = 0.5f + 2.0f * hard_sym(&x);
            target[k] = hard_unit(&x);
            base.dir[k] = target[k] - base.org[k];
        }
        base.tmin = 0.0f;
        base.tmax = INFINITY;
        /* does Embree agree with bruteforce on the plain ray? */
        tt_hit he, hb;
        int oe, ob;
        REQUIRE_OK(ctx, tt_intersect1(e, &base, &he));
        REQUIRE_OK(ctx, tt_intersect1(bf, &base, &hb));
        REQUIRE_OK(ctx, tt_occluded1(e, &base, &oe));
        REQUIRE_OK(ctx, tt_occluded1(bf, &base, &ob));
        int generic = he.prim == hb.prim && he.t == hb.t && oe == ob;
        hits += hb.prim != TT_INVALID_ID;
        char what[96];
        for (size_t j = 0; j < sizeof exps / sizeof exps[0] + sizeof odd / sizeof odd[0]; j++) {
            tt_ray r = base;
            float f = j < sizeof exps / sizeof exps[0] ? ldexpf(1.0f, exps[j])
                                                      : odd[j - sizeof exps / sizeof exps[0]];
            for (int k = 0; k < 3; k++) r.dir[k] = base.dir[k] * f;
            if (r.dir[0] == 0.0f && r.dir[1] == 0.0f && r.dir[2] == 0.0f) continue;
            if (!isfinite(r.dir[0] + r.dir[1] + r.dir[2])) continue;
            snprintf(what, sizeof what, "random ray %d, direction * %g", i, f);
            if (too_short(&r)) {
                expect_refused(e, bf, &r, what);
                continue;
            }
            if (generic) {
                expect_bruteforce(ctx, s, e, bf, &r, what);
                compared++;
            } else {
                tt_hit h;
                int occ;
                trace_valid(ctx, s, e, &r, &h, &occ, what);
            }
            /* a finite tmax half way to the target: its scaled value must
             * stay exact too (or the ray goes to bruteforce) */
            r.tmax = 0.5f / f;
            if (isfinite(r.tmax) && r.tmax > 0.0f && generic) {
                expect_bruteforce(ctx, s, e, bf, &r, what);
                compared++;
            }
        }
        for (size_t j = 0; j < sizeof beyond / sizeof beyond[0]; j++) {
            tt_ray r = base;
            for (int k = 0; k < 3; k++) r.dir[k] = base.dir[k] * beyond[j];
            if (r.dir[0] == 0.0f && r.dir[1] == 0.0f && r.dir[2] == 0.0f) continue;
            snprintf(what, sizeof what, "random ray %d, direction * %g", i, beyond[j]);
            expect_refused(e, bf, &r, what);
        }
    }
    CHECK_MSG(compared > 1500, "only %zu scaled rays compared exactly", compared);
    CHECK_MSG(hits > 30, "only %zu of the random rays hit the soup", hits);
    printf("scaled directions: %zu rays compared with bruteforce (%zu of 150 base rays hit)\n",
           compared, hits);
    tt_accel_destroy(e);
    tt_accel_destroy(bf);
    tt_scene_destroy(s);
    hard_mesh_free(&m);
}

/* Rays Embree never sees: the structure answers them with the bruteforce
 * template, so the answer is bit-identical. */
static void test_bruteforce_fallback(tt_context *ctx)
{
    hard_mesh m = {0};
    hard_gen_soup(&m, "soup", 300, 0.1f, 8u);
    tt_scene *s = hard_scene(ctx, &m);
    tt_accel *e = tt_test_build_default(ctx, s, "embree"), *bf = tt_test_build_default(ctx, s, "bruteforce");
    uint32_t x = 99u;
    for (int i = 0; i < 40; i++) {
        float p[3];
        for (int k = 0; k < 3; k++) p[k] = hard_unit(&x);
        /* origins beyond Embree's range, aimed back at the scene */
        tt_ray far = {{2e18f, p[1], p[2]}, 0.0f, {-1.0f, 0.0f, 0.0f}, INFINITY};
        expect_bruteforce(ctx, s, e, bf, &far, "origin at x = 2e18");
        tt_ray farthest = {{p[0], -3e38f, p[2]}, 0.0f, {0.0f, 1e38f, 0.0f}, INFINITY};
        expect_bruteforce(ctx, s, e, bf, &farthest, "origin at y = -3e38");
        /* a direction just above the contract's 2^-80 with a finite tmax
         * that the rescaling (by 2^-80) would underflow, and one whose
         * components span more than float's range */
        tt_ray under = {{p[0], p[1], -1.0f}, 0.0f, {1e-25f, 2e-25f, 1e-24f}, 1e-30f};
        expect_bruteforce(ctx, s, e, bf, &under, "short direction, tmax 1e-30");
        under.tmax = 1e22f; /* reaches z = -0.99: not the soup */
        expect_bruteforce(ctx, s, e, bf, &under, "short direction, tmax 1e22");
        /* below 2^-80 the contract refuses the ray */
        tt_ray tiny = {{p[0], p[1], -1.0f}, 0.0f, {1e-41f, 2e-41f, 1e-40f}, 1e-30f};
        expect_refused(e, bf, &tiny, "tiny direction, tmax 1e-30");
        tt_ray span = {{p[0], p[1], -1.0f}, 0.0f, {1e-44f * hard_sym(&x), 1e-44f, 1e30f}, INFINITY};
        expect_bruteforce(ctx, s, e, bf, &span, "direction components from 1e-44 to 1e30");
    }
    tt_accel_destroy(e);
    tt_accel_destroy(bf);
    tt_scene_destroy(s);
    hard_mesh_free(&m);
}

int main(void)
{
    if (!tt_test_has_accel("embree")) {
        printf("no embree in this build: skipped\n");
        return 77;
    }
    tt_context *ctx = tt_test_context();
    test_crash_rays(ctx);
    test_scaled_directions(ctx);
    test_bruteforce_fallback(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
