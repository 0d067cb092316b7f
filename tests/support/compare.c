#include "compare.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#define MAX_REPORTS 5

/* Whether two floats have the same bits (so +0 and -0 differ, as do NaNs'
 * payloads): "the same answer" for the same triangle. */
static int same_bits(float a, float b)
{
    uint32_t x, y;
    memcpy(&x, &a, sizeof x);
    memcpy(&y, &b, sizeof y);
    return x == y;
}

/* Largest relative t difference seen between two different triangles that
 * agreed (TT_TEST_EDGE_LOG=1 prints it at exit; see compare.h). */
static float edge_seen;
static void edge_log(void) { fprintf(stderr, "edge rule: largest relative t difference %.3g\n", (double)edge_seen); }
static void edge_note(float rel)
{
    static int registered;
    if (!registered) {
        registered = 1;
        const char *e = getenv("TT_TEST_EDGE_LOG");
        if (e && *e == '1') atexit(edge_log);
    }
    if (rel > edge_seen) edge_seen = rel;
}

static int edge_agree(const tt_hit *a, const tt_hit *b, float tol)
{
    float scale = fmaxf(fabsf(a->t), fabsf(b->t));
    float diff = fabsf(a->t - b->t);
    if (!(diff <= tol * scale)) return 0;
    if (scale > 0.0f) edge_note(diff / scale);
    return 1;
}

int tt_test_hits_agree(const tt_hit *a, const tt_hit *b)
{
    int ma = a->prim == TT_INVALID_ID, mb = b->prim == TT_INVALID_ID;
    if (ma || mb) return ma && mb;
    if (a->prim == b->prim)
        return same_bits(a->t, b->t) && same_bits(a->u, b->u) && same_bits(a->v, b->v);
    return edge_agree(a, b, TT_TEST_EDGE_REL);
}

int tt_test_hits_agree_t(const tt_hit *a, const tt_hit *b)
{
    int ma = a->prim == TT_INVALID_ID, mb = b->prim == TT_INVALID_ID;
    if (ma || mb) return ma && mb;
    if (a->prim == b->prim) return same_bits(a->t, b->t);
    return edge_agree(a, b, TT_TEST_EDGE_REL);
}

int tt_test_hits_agree_foreign(const tt_hit *a, const tt_hit *b)
{
    int ma = a->prim == TT_INVALID_ID, mb = b->prim == TT_INVALID_ID;
    if (ma || mb) return ma && mb;
    float scale = fmaxf(fabsf(a->t), fabsf(b->t));
    return fabsf(a->t - b->t) <= TT_TEST_FOREIGN_REL * scale;
}

/* Embree intersects triangles with its own test: its t differs from ours
 * in the last bits, so it is held to the conventions' 1e-4 rule. Every
 * other structure shares the library's watertight test. */
static int foreign(const tt_accel *a) { return strcmp(tt_accel_name(a), "embree") == 0; }

typedef struct cmp_state {
    size_t bad;
    const char *what;
    int (*agree)(const tt_hit *, const tt_hit *);
} cmp_state;

static int (*rule_for(const tt_accel *test, const tt_accel *ref))(const tt_hit *, const tt_hit *)
{
    return foreign(test) || foreign(ref) ? tt_test_hits_agree_foreign : tt_test_hits_agree;
}

static void report(cmp_state *s, const char *kind, const tt_ray *r, const char *detail)
{
    if (s->bad++ < MAX_REPORTS)
        fprintf(stderr,
                "mismatch (%s, %s): org %.9g %.9g %.9g dir %.9g %.9g %.9g t [%g, %g): %s\n",
                s->what, kind, r->org[0], r->org[1], r->org[2], r->dir[0], r->dir[1], r->dir[2],
                r->tmin, r->tmax, detail);
}

/* Traces one ray both ways (fast and counting) with the structure under test
 * and compares with the reference hit h_ref; returns the test's end hint
 * through *end. */
static void compare_closest(cmp_state *s, const tt_accel *test, const tt_ray *r, uint32_t start,
                            tt_status e_ref, const tt_hit *h_ref, uint32_t *end)
{
    tt_hit h_fast, h_stats;
    tt_ray_stats st;
    memset(&st, 0, sizeof st);
    tt_trace_args a_fast = {start, TT_INVALID_ID, NULL};
    tt_trace_args a_stats = {start, TT_INVALID_ID, &st};
    tt_status e2 = tt_intersect1_ex(test, r, &h_fast, &a_fast);
    tt_status e3 = tt_intersect1_ex(test, r, &h_stats, &a_stats);
    char msg[384];
    if (e_ref || e2 || e3) {
        report(s, "closest", r, "a call failed");
    } else if (!s->agree(h_ref, &h_fast) || !s->agree(h_ref, &h_stats)) {
        snprintf(msg, sizeof msg,
                 "reference prim %u t %.9g u %.9g v %.9g, fast prim %u t %.9g u %.9g v %.9g, "
                 "stats prim %u t %.9g u %.9g v %.9g",
                 h_ref->prim, h_ref->t, h_ref->u, h_ref->v, h_fast.prim, h_fast.t, h_fast.u,
                 h_fast.v, h_stats.prim, h_stats.t, h_stats.u, h_stats.v);
        report(s, "closest", r, msg);
    } else if (st.rays != 1) {
        report(s, "closest", r, "the counting variant did not count exactly one ray");
    }
    if (end) *end = a_fast.end_hint;
}

static void check_closest(cmp_state *s, const tt_accel *test, const tt_accel *ref,
                          const tt_ray *r, uint32_t start, tt_hit *ref_hit, uint32_t *end)
{
    tt_hit h_ref;
    tt_status e1 = tt_intersect1(ref, r, &h_ref);
    compare_closest(s, test, r, start, e1, &h_ref, end);
    if (ref_hit) *ref_hit = h_ref;
}

static void compare_occluded(cmp_state *s, const tt_accel *test, const tt_ray *r, uint32_t start,
                             int o_ref)
{
    int o_fast = -2, o_stats = -3;
    tt_ray_stats st;
    memset(&st, 0, sizeof st);
    tt_trace_args a_fast = {start, TT_INVALID_ID, NULL};
    tt_trace_args a_stats = {start, TT_INVALID_ID, &st};
    tt_occluded1_ex(test, r, &o_fast, &a_fast);
    tt_occluded1_ex(test, r, &o_stats, &a_stats);
    if (o_ref != o_fast || o_ref != o_stats) {
        char msg[128];
        snprintf(msg, sizeof msg, "reference %d, fast %d, stats %d", o_ref, o_fast, o_stats);
        report(s, "occluded", r, msg);
    }
}

static void check_occluded(cmp_state *s, const tt_accel *test, const tt_accel *ref,
                           const tt_ray *r, uint32_t start)
{
    int o_ref = -1;
    tt_occluded1(ref, r, &o_ref);
    compare_occluded(s, test, r, start, o_ref);
}

size_t tt_test_compare_view(const tt_scene *scene, const tt_accel *test, const tt_accel *ref,
                            const tt_camera *camera, uint32_t width, uint32_t height)
{
    cmp_state s = {0, tt_accel_name(test), rule_for(test, ref)};
    uint32_t eye_hint = tt_accel_locate(test, camera->eye);
    for (uint32_t y = 0; y < height; y++) {
        for (uint32_t x = 0; x < width; x++) {
            tt_ray r, sr;
            tt_hit h;
            uint32_t end = TT_INVALID_ID;
            tt_camera_ray(camera, width, height, x, y, &r);
            check_closest(&s, test, ref, &r, eye_hint, &h, &end);
            if (tt_shadow_ray(scene, camera, &r, &h, &sr)) check_occluded(&s, test, ref, &sr, end);
        }
    }
    if (s.bad) fprintf(stderr, "%s: %zu of %u pixels disagree\n", s.what, s.bad, width * height);
    return s.bad;
}

/* xorshift32: a fixed, portable sequence. */
static uint32_t next(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}

static float unit(uint32_t *x) { return (float)(next(x) >> 8) * (1.0f / 16777216.0f); }

/* The box random rays start in: the scene's, or [-1, 1]^3 for an empty
 * scene (whose bounds are empty). */
static void ray_box(const tt_scene *scene, float lo[3], float hi[3])
{
    tt_scene_bounds(scene, lo, hi);
    if (!(lo[0] <= hi[0])) lo[0] = lo[1] = lo[2] = -1.0f, hi[0] = hi[1] = hi[2] = 1.0f;
}

size_t tt_test_compare_random(const tt_scene *scene, const tt_accel *test, const tt_accel *ref,
                              uint32_t n, uint32_t seed)
{
    cmp_state s = {0, tt_accel_name(test), rule_for(test, ref)};
    float lo[3], hi[3];
    ray_box(scene, lo, hi);
    uint32_t x = seed ? seed : 1;
    for (uint32_t i = 0; i < n; i++) {
        tt_ray r;
        int kind = (int)(next(&x) % 4);
        for (int k = 0; k < 3; k++) {
            float e = hi[k] - lo[k];
            /* kind 0: outside-ish origins over twice the box; else inside */
            float spread = kind == 0 ? 2.0f : 1.0f;
            r.org[k] = lo[k] + e * (0.5f + spread * (unit(&x) - 0.5f));
            r.dir[k] = unit(&x) * 2.0f - 1.0f;
        }
        if (kind == 2) { /* axis-parallel */
            int axis = (int)(next(&x) % 3);
            r.dir[0] = r.dir[1] = r.dir[2] = 0.0f;
            r.dir[axis] = (next(&x) & 1) ? 1.0f : -1.0f;
        } else if (kind == 3) { /* one zero component */
            r.dir[next(&x) % 3] = 0.0f;
        }
        if (r.dir[0] == 0.0f && r.dir[1] == 0.0f && r.dir[2] == 0.0f) r.dir[0] = 1.0f;
        r.tmin = 0.0f;
        r.tmax = INFINITY;
        check_closest(&s, test, ref, &r, TT_INVALID_ID, NULL, NULL);
        float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]));
        r.tmax = unit(&x) * diag;
        check_occluded(&s, test, ref, &r, TT_INVALID_ID);
    }
    if (s.bad) fprintf(stderr, "%s: %zu of %u random rays disagree\n", s.what, s.bad, n);
    return s.bad;
}

int tt_test_refused(const tt_accel *test, const tt_accel *ref, const tt_ray *r)
{
    tt_hit h;
    int o;
    tt_ray_stats st;
    memset(&st, 0, sizeof st);
    tt_trace_args a_stats = {TT_INVALID_ID, TT_INVALID_ID, &st};
    return tt_intersect1(ref, r, &h) == TT_ERR_INVALID_ARGUMENT &&
           tt_occluded1(ref, r, &o) == TT_ERR_INVALID_ARGUMENT &&
           tt_intersect1(test, r, &h) == TT_ERR_INVALID_ARGUMENT &&
           tt_occluded1(test, r, &o) == TT_ERR_INVALID_ARGUMENT &&
           tt_intersect1_ex(test, r, &h, &a_stats) == TT_ERR_INVALID_ARGUMENT &&
           tt_occluded1_ex(test, r, &o, &a_stats) == TT_ERR_INVALID_ARGUMENT;
}

static void check_refused(cmp_state *s, const tt_accel *test, const tt_accel *ref,
                          const tt_ray *r)
{
    if (!tt_test_refused(test, ref, r)) report(s, "refused", r, "a direction below 2^-80 was traced");
}

size_t tt_test_compare_tiny_dirs(const tt_scene *scene, const tt_accel *test, const tt_accel *ref,
                                 uint32_t n, uint32_t seed)
{
    /* 1/x = inf for x below ~2.9e-39; 1e-30 is where tt_safe_inv clamps */
    static const float tiny[] = {0.0f, 1e-45f, 1e-40f, 1e-39f, 2.5e-39f, 1e-30f, 3e-25f};
    const uint32_t n_tiny = (uint32_t)(sizeof tiny / sizeof tiny[0]);
    cmp_state s = {0, tt_accel_name(test), rule_for(test, ref)};
    float lo[3], hi[3];
    ray_box(scene, lo, hi);
    uint32_t x = seed ? seed : 1;
    for (uint32_t i = 0; i < n; i++) {
        tt_ray r;
        for (int k = 0; k < 3; k++) {
            r.org[k] = lo[k] + (hi[k] - lo[k]) * (0.2f + 0.6f * unit(&x));
            uint32_t b = next(&x);
            r.dir[k] = tiny[b % n_tiny] * ((b >> 8) & 1 ? -1.0f : 1.0f);
        }
        r.tmin = 0.0f;
        r.tmax = INFINITY;
        if (i % 4 == 0) {
            check_refused(&s, test, ref, &r);
            continue;
        }
        uint32_t b = next(&x);
        const float m = ldexpf(1.0f + unit(&x), -80 + (int)(b % 8));
        r.dir[i % 3] = (b >> 8) & 1 ? -m : m;
        check_closest(&s, test, ref, &r, TT_INVALID_ID, NULL, NULL);
        r.tmax = 1e30f;
        check_occluded(&s, test, ref, &r, TT_INVALID_ID);
    }
    if (s.bad) fprintf(stderr, "%s: %zu of %u tiny-direction rays disagree\n", s.what, s.bad, n);
    return s.bad;
}

size_t tt_test_compare_rays(const tt_accel *test, const tt_accel *ref, const tt_ray *rays,
                            size_t n)
{
    cmp_state s = {0, tt_accel_name(test), rule_for(test, ref)};
    for (size_t i = 0; i < n; i++) {
        check_closest(&s, test, ref, &rays[i], TT_INVALID_ID, NULL, NULL);
        check_occluded(&s, test, ref, &rays[i], TT_INVALID_ID);
    }
    return s.bad;
}

size_t tt_test_compare_view_multi(const tt_scene *scene, const tt_accel *const *tests, size_t n_tests,
                                  const tt_accel *ref, const tt_camera *camera, uint32_t width,
                                  uint32_t height)
{
    cmp_state *states = calloc(n_tests, sizeof *states);
    uint32_t *eye_hints = calloc(n_tests, sizeof *eye_hints);
    if (!states || !eye_hints) {
        free(states);
        free(eye_hints);
        fprintf(stderr, "tt_test_compare_view_multi: out of memory\n");
        return 1;
    }
    for (size_t i = 0; i < n_tests; i++) {
        states[i].what = tt_accel_name(tests[i]);
        states[i].agree = rule_for(tests[i], ref);
        eye_hints[i] = tt_accel_locate(tests[i], camera->eye);
    }
    for (uint32_t y = 0; y < height; y++) {
        for (uint32_t x = 0; x < width; x++) {
            tt_ray r, sr;
            tt_hit h;
            tt_camera_ray(camera, width, height, x, y, &r);
            tt_status e = tt_intersect1(ref, &r, &h);
            int has_shadow = tt_shadow_ray(scene, camera, &r, &h, &sr);
            int o_ref = -1;
            if (has_shadow) tt_occluded1(ref, &sr, &o_ref);
            for (size_t i = 0; i < n_tests; i++) {
                uint32_t end = TT_INVALID_ID;
                size_t before = states[i].bad;
                compare_closest(&states[i], tests[i], &r, eye_hints[i], e, &h, &end);
                if (has_shadow) compare_occluded(&states[i], tests[i], &sr, end, o_ref);
                if (states[i].bad != before && before < MAX_REPORTS)
                    fprintf(stderr, "  (structure %zu of %zu, pixel %u %u)\n", i, n_tests, x, y);
            }
        }
    }
    size_t bad = 0;
    for (size_t i = 0; i < n_tests; i++) {
        if (states[i].bad)
            fprintf(stderr, "structure %zu (%s): %zu of %u pixels disagree\n", i, states[i].what,
                    states[i].bad, width * height);
        bad += states[i].bad;
    }
    free(states);
    free(eye_hints);
    return bad;
}
