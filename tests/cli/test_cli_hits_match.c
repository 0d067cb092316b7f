/* The CLI's hit buffer for bunny:main at 32x32 (bruteforce) is byte for byte
 * the one built ray by ray through the public API: tt_camera_ray,
 * tt_intersect1, tt_shadow_ray, tt_occluded1 (so the renderer's tiles,
 * threads and direct dispatch change nothing). With every other structure
 * of the build, the CLI's buffer agrees with it by the conventions' rule. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "cli_run.h"

#define N 32

static void put_u32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; k++) p[k] = (uint8_t)(v >> (8 * k));
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint8_t *api_buffer(tt_context *ctx, const tt_scene *scene, const tt_camera *cam)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *accel;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &accel));
    uint8_t *buf = calloc(N * N, 12);
    for (uint32_t y = 0; y < N; y++) {
        for (uint32_t x = 0; x < N; x++) {
            tt_ray r, s;
            tt_hit h;
            int occluded = 0;
            REQUIRE_OK(ctx, tt_camera_ray(cam, N, N, x, y, &r));
            REQUIRE_OK(ctx, tt_intersect1(accel, &r, &h));
            if (tt_shadow_ray(scene, cam, &r, &h, &s)) REQUIRE_OK(ctx, tt_occluded1(accel, &s, &occluded));
            uint8_t *p = buf + 12 * (y * N + x);
            float t = h.prim == TT_INVALID_ID ? INFINITY : h.t;
            uint32_t tbits;
            memcpy(&tbits, &t, 4);
            put_u32(p, h.prim);
            put_u32(p + 4, tbits);
            put_u32(p + 8, (uint32_t)occluded);
        }
    }
    tt_accel_destroy(accel);
    return buf;
}

/* The conventions' agreement rule, pixel by pixel. */
static int disagreements(const uint8_t *a, const uint8_t *b)
{
    int bad = 0;
    for (int i = 0; i < N * N; i++) {
        const uint8_t *p = a + 12 * i, *q = b + 12 * i;
        uint32_t pa = get_u32(p), pb = get_u32(q);
        float ta, tb;
        uint32_t ua = get_u32(p + 4), ub = get_u32(q + 4);
        memcpy(&ta, &ua, 4);
        memcpy(&tb, &ub, 4);
        int same_hit = (pa == TT_INVALID_ID && pb == TT_INVALID_ID) ||
                       (pa != TT_INVALID_ID && pb != TT_INVALID_ID &&
                        (pa == pb || fabsf(ta - tb) <= 1e-4f * fmaxf(ta, tb)));
        bad += !same_hit || get_u32(p + 8) != get_u32(q + 8);
    }
    return bad;
}

int main(void)
{
    const char *scene_path = tt_test_scene_path("bun_zipper.ply");
    const char *views = tt_test_scene_path("views.tsv");
    tt_context *ctx = tt_test_context();
    tt_scene *scene = tt_test_load_scene(ctx, "bun_zipper.ply");
    tt_camera cam;
    tt_test_view(ctx, "bunny:main", &cam);
    uint8_t *expected = api_buffer(ctx, scene, &cam);
    int hits = 0, occluded = 0;
    for (int i = 0; i < N * N; i++) {
        hits += get_u32(expected + 12 * i) != TT_INVALID_ID;
        occluded += get_u32(expected + 12 * i + 8) != 0;
    }
    CHECK(hits > N * N / 4 && occluded > 0 && occluded < hits); /* a meaningful view */

    const char *out = tt_cli_tmp("bunny.hits");
    for (const char *const *name = tt_accel_names(); *name; name++) {
        tt_cli_result r;
        tt_cli_run(&r, "render '%s' --views '%s' --view bunny:main --size %dx%d --accel %s --hits '%s'",
                   scene_path, views, N, N, *name, out);
        CHECK_MSG(r.status == 0, "%s: exit %d: %s", *name, r.status, r.err);
        long size = 0;
        uint8_t *got = tt_test_read_file(out, &size);
        CHECK_MSG(got && size == N * N * 12, "%s: hit buffer of %ld bytes", *name, size);
        if (got && size == N * N * 12) {
            if (strcmp(*name, "bruteforce") == 0)
                CHECK_MSG(memcmp(got, expected, N * N * 12) == 0,
                          "bruteforce: the CLI's buffer differs from the API's");
            int bad = disagreements(got, expected);
            CHECK_MSG(bad == 0, "%s: %d pixels disagree with the API's bruteforce buffer", *name, bad);
        }
        free(got);
        remove(out);
        tt_cli_result_free(&r);
    }
    free(expected);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
