/* The renderer's start hints (the eye's located node for primary rays, the
 * primary ray's end node or the last caster's node for shadow rays) must not
 * change any result: for every structure of the build, every traversal and
 * the kd-tree's caster hint, tt_render's hit buffer of shared views agrees
 * pixel by pixel with bruteforce's (the conventions' rule), at 1 and 2
 * threads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

#define N 40

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static int disagreements(const uint8_t *a, const uint8_t *b, size_t pixels)
{
    int bad = 0;
    for (size_t i = 0; i < pixels; i++) {
        const uint8_t *p = a + 12 * i, *q = b + 12 * i;
        uint32_t pa = get_u32(p), pb = get_u32(q), ua = get_u32(p + 4), ub = get_u32(q + 4);
        float ta, tb;
        memcpy(&ta, &ua, 4);
        memcpy(&tb, &ub, 4);
        int same = (pa == TT_INVALID_ID && pb == TT_INVALID_ID) ||
                   (pa != TT_INVALID_ID && pb != TT_INVALID_ID &&
                    (pa == pb || fabsf(ta - tb) <= 1e-4f * fmaxf(ta, tb)));
        bad += !same || get_u32(p + 8) != get_u32(q + 8);
    }
    return bad;
}

static uint8_t *render_hits(tt_context *ctx, const tt_scene *scene, const tt_build_options *bo,
                            const tt_camera *cam)
{
    tt_accel *accel;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, bo, &accel));
    tt_render_options o;
    tt_render_options_default(&o);
    o.width = o.height = N;
    o.keep_hits = 1;
    tt_render_result *r;
    REQUIRE_OK(ctx, tt_render(ctx, scene, accel, cam, &o, &r));
    size_t size;
    const uint8_t *hits = tt_render_hits(r, &size);
    uint8_t *copy = malloc(size);
    memcpy(copy, hits, size);
    tt_render_result_destroy(r);
    tt_accel_destroy(accel);
    return copy;
}

static void check_variant(tt_context *ctx, const tt_scene *scene, const tt_camera *cam,
                          const uint8_t *reference, const tt_build_options *bo, const char *what)
{
    uint8_t *hits = render_hits(ctx, scene, bo, cam);
    int bad = disagreements(hits, reference, N * N);
    CHECK_MSG(bad == 0, "%s: %d of %d pixels disagree with bruteforce", what, bad, N * N);
    free(hits);
}

static void check_view(int threads, const char *file, const char *view)
{
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = threads;
    tt_context *ctx;
    REQUIRE_OK(NULL, tt_context_create(&co, &ctx));
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    uint8_t *reference = render_hits(ctx, scene, &bo, &cam);
    char what[128];
    for (const char *const *n = tt_accel_names(); *n; n++) {
        tt_build_options_default(&bo);
        bo.accel = *n;
        if (strcmp(*n, "rtree") == 0) {
            for (int t = TT_RTREE_AUTO; t <= TT_RTREE_STACK; t++) {
                bo.rtree.traversal = (tt_rtree_traversal)t;
                snprintf(what, sizeof what, "%s %s rtree traversal %d, %d threads", file, view, t,
                         threads);
                check_variant(ctx, scene, &cam, reference, &bo, what);
            }
        } else if (strcmp(*n, "kdtree") == 0) {
            for (int t = TT_KD_HTR; t <= TT_KD_SEQ; t++) {
                /* htr keeps no boxes to start from: no caster hint */
                for (int caster = 0; caster <= (t != TT_KD_HTR); caster++) {
                    bo.kdtree.traversal = (tt_kd_traversal)t;
                    bo.kdtree.shadow_caster_hint = caster;
                    snprintf(what, sizeof what, "%s %s kdtree traversal %d caster %d, %d threads",
                             file, view, t, caster, threads);
                    check_variant(ctx, scene, &cam, reference, &bo, what);
                }
            }
        } else if (strcmp(*n, "bruteforce") != 0) {
            snprintf(what, sizeof what, "%s %s %s, %d threads", file, view, *n, threads);
            check_variant(ctx, scene, &cam, reference, &bo, what);
        }
    }
    free(reference);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
}

int main(void)
{
    int others = 0;
    for (const char *const *n = tt_accel_names(); *n; n++) others += strcmp(*n, "bruteforce") != 0;
    if (!others) {
        printf("skipped: no structure but bruteforce in this build\n");
        return 77;
    }
    check_view(1, "bun_zipper_res4.ply", "bunny_res4:main");
    check_view(2, "bun_zipper_res4.ply", "bunny_res4:main");
    check_view(2, "cornell_box.obj", "cornell:main");
    return tt_test_finish();
}
