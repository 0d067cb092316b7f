/* The GPU against the CPU on the shared views (bunny, Sibenik, conference
 * at 128 x 128): for every structure and traversal the GPU traces, the hit
 * buffers agree pixel by pixel (compare.h's rule: both miss, the same
 * triangle with bit-identical t (the same code, --fmad=false) or another
 * triangle with t within TT_TEST_EDGE_REL, and the same shadow flag), the
 * counting passes give the same totals and the same per-pixel counts (the
 * GPU runs the CPU's traversal code on bit-identical rays), the image
 * shaded on the GPU equals the CPU's wherever the hit buffers are
 * byte-identical, and the summary carries the GPU's timings. Needs a build with CUDA and a usable
 * GPU; otherwise it says why and exits 77 (skipped), or fails where a GPU is
 * required (/dev/nvidia0 exists or TT_REQUIRE_GPU=1: tt_test_no_gpu). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "compare.h"

#define SIZE 128

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Pixels that disagree per the conventions; *inexact counts those that
 * agree without being byte-identical (reported, not a failure). */
static size_t disagreements(const uint8_t *a, const uint8_t *b, size_t pixels, size_t *inexact,
                            const char *what)
{
    size_t bad = 0;
    *inexact = 0;
    for (size_t i = 0; i < pixels; i++) {
        const uint8_t *p = a + 12 * i, *q = b + 12 * i;
        uint32_t pa = get_u32(p), pb = get_u32(q), ua = get_u32(p + 4), ub = get_u32(q + 4);
        float ta, tb;
        memcpy(&ta, &ua, 4);
        memcpy(&tb, &ub, 4);
        tt_hit ha = {ta, 0.0f, 0.0f, pa}, hb = {tb, 0.0f, 0.0f, pb};
        int same = tt_test_hits_agree_t(&ha, &hb);
        same = same && get_u32(p + 8) == get_u32(q + 8);
        if (!same && bad++ < 5)
            fprintf(stderr, "%s: pixel (%zu, %zu): GPU prim %u t %.9g shadow %u, CPU prim %u t %.9g "
                            "shadow %u\n",
                    what, i % SIZE, i / SIZE, pa, ta, get_u32(p + 8), pb, tb, get_u32(q + 8));
        if (same && memcmp(p, q, 12) != 0) ++*inexact;
    }
    return bad;
}

static int stats_equal(const tt_ray_stats *a, const tt_ray_stats *b)
{
    return a->rays == b->rays && a->nodes == b->nodes && a->interior == b->interior &&
           a->leaves == b->leaves && a->boxes == b->boxes && a->triangles == b->triangles;
}

static tt_render_result *render(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                                const tt_camera *cam, tt_device device)
{
    tt_render_options o;
    tt_render_options_default(&o);
    o.width = o.height = SIZE;
    o.keep_hits = 1;
    o.stats = 1;
    o.keep_pixel_stats = 1;
    o.keep_image = 1;
    o.repeat = 2;
    o.device = device;
    tt_render_result *r = NULL;
    REQUIRE_OK(ctx, tt_render(ctx, scene, accel, cam, &o, &r));
    return r;
}

static void compare(tt_context *ctx, const tt_scene *scene, const tt_camera *cam,
                    const tt_build_options *bo, const char *what)
{
    tt_accel *accel = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, bo, &accel));
    tt_render_result *gpu = render(ctx, scene, accel, cam, TT_DEVICE_GPU);
    tt_render_result *cpu = render(ctx, scene, accel, cam, TT_DEVICE_CPU);
    size_t gs, cs, inexact = 0;
    const uint8_t *gh = tt_render_hits(gpu, &gs), *ch = tt_render_hits(cpu, &cs);
    CHECK(gs == cs && gs == (size_t)SIZE * SIZE * 12);
    size_t bad = disagreements(gh, ch, (size_t)SIZE * SIZE, &inexact, what);
    CHECK_MSG(bad == 0, "%s: %zu of %d pixels disagree", what, bad, SIZE * SIZE);
    const tt_render_summary *g = tt_render_get_summary(gpu), *c = tt_render_get_summary(cpu);
    CHECK(g->device == TT_DEVICE_GPU && g->device_name[0] != '\0');
    CHECK(g->primary_s > 0.0 && g->trace_s >= g->primary_s && g->upload_s > 0.0 &&
          g->download_s > 0.0 && g->trace_median_s >= g->trace_s && g->mrays_per_s > 0.0);
    CHECK(g->primary_hits == c->primary_hits && g->shadow_occluded == c->shadow_occluded);
    CHECK(g->has_stats && c->has_stats);
    CHECK_MSG(stats_equal(&g->primary_stats, &c->primary_stats) &&
                  stats_equal(&g->shadow_stats, &c->shadow_stats),
              "%s: the GPU's counts differ from the CPU's (primary boxes %llu vs %llu, shadow "
              "boxes %llu vs %llu)",
              what, (unsigned long long)g->primary_stats.boxes,
              (unsigned long long)c->primary_stats.boxes,
              (unsigned long long)g->shadow_stats.boxes, (unsigned long long)c->shadow_stats.boxes);
    const uint8_t *gi = tt_render_image(gpu), *ci = tt_render_image(cpu);
    size_t image_bad = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++)
        image_bad += memcmp(gh + 12 * i, ch + 12 * i, 12) == 0 && memcmp(gi + 3 * i, ci + 3 * i, 3) != 0;
    CHECK_MSG(image_bad == 0, "%s: %zu pixels with identical hits are shaded differently", what,
              image_bad);
    for (int m = TT_HEAT_NODES; m <= TT_HEAT_BOXES; m++) {
        const uint32_t *gp = tt_render_pixel_stats(gpu, (tt_heat_metric)m);
        const uint32_t *cp = tt_render_pixel_stats(cpu, (tt_heat_metric)m);
        CHECK_MSG(gp && cp && memcmp(gp, cp, (size_t)SIZE * SIZE * 4) == 0,
                  "%s: per-pixel counts (metric %d) differ", what, m);
    }
    printf("%-40s %zu pixels not byte-identical (agreeing); GPU %s: upload %.4f s, primary %.5f s, "
           "shadow %.5f s, %.1f Mrays/s; CPU %.1f Mrays/s\n",
           what, inexact, g->device_name, g->upload_s, g->primary_s, g->shadow_s, g->mrays_per_s,
           c->mrays_per_s);
    tt_render_result_destroy(gpu);
    tt_render_result_destroy(cpu);
    tt_accel_destroy(accel);
}

static void check_view(tt_context *ctx, const char *file, const char *view)
{
    static const struct {
        const char *accel;
        int traversal;
        const char *name;
    } configs[] = {
        {"rtree", TT_RTREE_AUTO, "auto"},       {"rtree", TT_RTREE_STACKLESS, "stackless"},
        {"rtree", TT_RTREE_ORDERED, "ordered"}, {"kdtree", TT_KD_SLTR, "sltr"},
        {"kdtree", TT_KD_HTR, "htr"},
    };
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; i++) {
        tt_build_options bo;
        tt_build_options_default(&bo);
        bo.accel = configs[i].accel;
        if (strcmp(bo.accel, "rtree") == 0) bo.rtree.traversal = (tt_rtree_traversal)configs[i].traversal;
        else bo.kdtree.traversal = (tt_kd_traversal)configs[i].traversal;
        char what[96];
        snprintf(what, sizeof what, "%s %s %s", view, configs[i].accel, configs[i].name);
        compare(ctx, scene, &cam, &bo, what);
    }
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_status st = tt_device_check(ctx, TT_DEVICE_GPU);
    if (st != TT_OK) {
        char why[512];
        snprintf(why, sizeof why, "%s", tt_context_last_error(ctx));
        tt_context_destroy(ctx); /* nothing left for LeakSanitizer to report */
        tt_test_no_gpu(st, why);
    }
    check_view(ctx, "bun_zipper.ply", "bunny:main");
    check_view(ctx, "sibenik.obj", "sibenik:main");
    check_view(ctx, "conference.ply", "conference:main");
    tt_context_destroy(ctx);
    return tt_test_finish();
}
