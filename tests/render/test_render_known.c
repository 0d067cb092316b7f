/* End-to-end renders of the scene of support/known_scene.h, whose every
 * pixel is known by construction: prim ids, t values and shadow flags, the
 * hit buffer byte by byte, the summary counts, per-pixel statistics and the
 * shaded image, for every structure of the build and through every option of
 * tt_render; and every way tt_render can fail. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "known_scene.h"

#define W TT_KNOWN_W
#define H TT_KNOWN_H
#define verts tt_known_vertices
#define indices tt_known_indices

static tt_camera camera(void) { return tt_known_camera(); }

static int check_buffer(const char *what, const uint8_t *hits, size_t size, int with_shadows)
{
    int bad = tt_known_check_hits(what, hits, size, with_shadows);
    CHECK_MSG(bad == 0, "%s: %d pixels differ from the construction", what, bad);
    return bad;
}

static tt_render_result *render(tt_context *ctx, const tt_scene *s, const tt_accel *a,
                                const tt_camera *c, const tt_render_options *o)
{
    tt_render_result *r = NULL;
    CHECK_OK(ctx, tt_render(ctx, s, a, c, o, &r));
    return r;
}

static void test_structure(tt_context *ctx, const tt_scene *scene, const char *name)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = name;
    tt_accel *accel;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &accel));
    tt_camera cam = camera();
    tt_render_options o;
    tt_render_options_default(&o);
    o.width = W;
    o.height = H;
    o.keep_hits = 1;

    /* the plain render, with summary counts known by construction */
    tt_render_result *r = render(ctx, scene, accel, &cam, &o);
    if (!r) return;
    size_t size;
    const uint8_t *hits = tt_render_hits(r, &size);
    check_buffer(name, hits, size, 1);
    uint8_t *first = malloc(size);
    memcpy(first, hits, size);
    const tt_render_summary *s = tt_render_get_summary(r);
    CHECK(s->width == W && s->height == H);
    CHECK(s->primary_rays == W * H);
    CHECK(s->primary_hits == W * H / 2);
    CHECK(s->shadow_rays == W * H / 2);
    CHECK(s->shadow_occluded == W * H / 4);
    CHECK(s->threads >= 1);
    CHECK(s->trace_s >= 0 && s->trace_median_s >= s->trace_s);
    CHECK(s->primary_s <= s->trace_s && s->shadow_s <= s->trace_s);
    CHECK(!s->has_stats);
    CHECK(tt_render_image(r) == NULL);
    CHECK(tt_render_pixel_stats(r, TT_HEAT_NODES) == NULL);
    tt_render_result_destroy(r);

    /* threads and repeats change nothing in the result */
    tt_context_options co;
    tt_context_options_default(&co);
    for (int threads = 1; threads <= 3; threads++) {
        tt_context *c2;
        co.threads = threads;
        REQUIRE_OK(NULL, tt_context_create(&co, &c2));
        o.repeat = threads;
        r = render(c2, scene, accel, &cam, &o);
        if (r) {
            hits = tt_render_hits(r, &size);
            CHECK_MSG(memcmp(hits, first, size) == 0, "%s: %d threads give another buffer", name,
                      threads);
            CHECK(tt_render_get_summary(r)->threads == threads);
            CHECK(tt_render_get_summary(r)->trace_median_s >= tt_render_get_summary(r)->trace_s);
        }
        tt_render_result_destroy(r);
        tt_context_destroy(c2);
    }
    o.repeat = 1;

    /* statistics, per-pixel counts and the image do not change the hits */
    o.stats = 1;
    o.keep_pixel_stats = 1;
    o.keep_image = 1;
    r = render(ctx, scene, accel, &cam, &o);
    if (r) {
        hits = tt_render_hits(r, &size);
        CHECK_MSG(memcmp(hits, first, size) == 0, "%s: the counting pass changed the hits", name);
        s = tt_render_get_summary(r);
        CHECK(s->has_stats);
        CHECK(s->primary_stats.rays == W * H);
        CHECK(s->shadow_stats.rays == W * H / 2);
        const uint32_t *tri = tt_render_pixel_stats(r, TT_HEAT_TRIANGLES);
        const uint32_t *nodes = tt_render_pixel_stats(r, TT_HEAT_NODES);
        CHECK(tri && nodes && tt_render_pixel_stats(r, TT_HEAT_BOXES) &&
              tt_render_pixel_stats(r, TT_HEAT_LEAVES) &&
              tt_render_pixel_stats(r, TT_HEAT_INTERIOR));
        CHECK(tt_render_pixel_stats(r, (tt_heat_metric)5) == NULL);
        uint64_t sum_tri = 0, sum_nodes = 0;
        for (size_t i = 0; tri && nodes && i < (size_t)W * H; i++) {
            sum_tri += tri[i];
            sum_nodes += nodes[i];
        }
        /* the per-pixel counts are the primary rays' counts, pixel by pixel */
        CHECK(sum_tri == s->primary_stats.triangles);
        CHECK(sum_nodes == s->primary_stats.nodes);
        if (strcmp(name, "bruteforce") == 0) {
            /* bruteforce tests every triangle on every closest-hit ray */
            CHECK(s->primary_stats.triangles == 4 * W * H);
            for (size_t i = 0; tri && i < (size_t)W * H; i++) CHECK(tri[i] == 4);
        }
        /* the image: background where rays miss, lit rows brighter than
         * shadowed rows on the quad */
        const uint8_t *img = tt_render_image(r);
        CHECK(img != NULL);
        if (img) {
            const uint8_t *bg = img + 3 * (W - 1);
            const uint8_t *shadowed = img + 3 * (2 * W + 4), *lit = img + 3 * (9 * W + 4);
            CHECK(memcmp(img + 3 * ((H - 1) * W + W - 2), bg, 3) == 0);
            CHECK_MSG(lit[0] > shadowed[0] + 20, "lit %d, shadowed %d", lit[0], shadowed[0]);
            CHECK(shadowed[0] > bg[0]);
        }
        tt_render_result_destroy(r);
    }
    o.stats = o.keep_pixel_stats = o.keep_image = 0;

    /* no shadow rays: flags all 0, nothing counted */
    o.shadows = 0;
    r = render(ctx, scene, accel, &cam, &o);
    if (r) {
        hits = tt_render_hits(r, &size);
        check_buffer(name, hits, size, 0);
        CHECK(tt_render_get_summary(r)->shadow_rays == 0);
        CHECK(tt_render_get_summary(r)->shadow_occluded == 0);
        CHECK(tt_render_get_summary(r)->shadow_mrays_per_s == 0.0);
    }
    tt_render_result_destroy(r);
    o.shadows = 1;

    /* a camera without a light: no shadow rays either */
    cam.has_light = 0;
    r = render(ctx, scene, accel, &cam, &o);
    if (r) {
        hits = tt_render_hits(r, &size);
        check_buffer(name, hits, size, 0);
        CHECK(tt_render_get_summary(r)->shadow_rays == 0);
    }
    tt_render_result_destroy(r);

    free(first);
    tt_accel_destroy(accel);
}

/* Every bad argument is refused with a message, and *out is NULL. */
static void test_errors(tt_context *ctx, const tt_scene *scene)
{
    tt_accel *accel;
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &accel));
    tt_camera cam = camera();
    tt_render_options o;
    tt_render_options_default(&o);
    CHECK(o.width == 1024 && o.height == 1024 && o.shadows == 1 && o.repeat == 1);
    o.width = o.height = 8;
    tt_render_result *r = (tt_render_result *)&r;

    CHECK(tt_render(ctx, NULL, accel, &cam, &o, &r) == TT_ERR_INVALID_ARGUMENT && r == NULL);
    CHECK(tt_render(ctx, scene, NULL, &cam, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_render(ctx, scene, accel, NULL, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_render(NULL, scene, accel, &cam, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_render(ctx, scene, accel, &cam, &o, NULL) == TT_ERR_INVALID_ARGUMENT);

    o.width = 0;
    CHECK(tt_render(ctx, scene, accel, &cam, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "0x8") != NULL);
    o.width = 8;
    o.repeat = 0;
    CHECK(tt_render(ctx, scene, accel, &cam, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "repeat") != NULL);
    o.repeat = 1;

    tt_camera bad = cam;
    bad.fov_deg = 180.0f;
    CHECK(tt_render(ctx, scene, accel, &bad, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "field of view") != NULL);
    bad = cam;
    bad.eye[1] = NAN;
    CHECK(tt_render(ctx, scene, accel, &bad, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    bad = cam;
    memcpy(bad.look, bad.eye, sizeof bad.look);
    CHECK(tt_render(ctx, scene, accel, &bad, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    bad = cam;
    bad.up[1] = 0.0f;
    bad.up[2] = 1.0f; /* parallel to the view direction */
    CHECK(tt_render(ctx, scene, accel, &bad, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    bad = cam;
    bad.light[0] = INFINITY;
    CHECK(tt_render(ctx, scene, accel, &bad, &o, &r) == TT_ERR_INVALID_ARGUMENT);

    /* a structure built on another scene */
    tt_scene *other;
    REQUIRE_OK(ctx, tt_scene_create(ctx, verts, 8, indices, 4, &other));
    CHECK(tt_render(ctx, other, accel, &cam, &o, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(r == NULL);
    tt_scene_destroy(other);

    /* NULL options mean the defaults */
    o = (tt_render_options){0};
    CHECK(tt_render(ctx, scene, accel, &cam, NULL, &r) == TT_OK);
    if (r) CHECK(tt_render_get_summary(r)->width == 1024);
    tt_render_result_destroy(r);
    tt_render_result_destroy(NULL);
    CHECK(tt_render_get_summary(NULL) == NULL && tt_render_hits(NULL, NULL) == NULL);
    tt_accel_destroy(accel);
}

/* An allocator that fails the n-th allocation: every failure inside
 * tt_render must come back as TT_ERR_OUT_OF_MEMORY (ASan: without leaks). */
typedef struct failing {
    int countdown;
} failing;

static void *f_alloc(void *user, size_t size)
{
    failing *f = user;
    if (f->countdown >= 0 && f->countdown-- == 0) return NULL;
    return malloc(size);
}
static void *f_realloc(void *user, void *p, size_t size)
{
    failing *f = user;
    if (f->countdown >= 0 && f->countdown-- == 0) return NULL;
    return realloc(p, size);
}
static void f_free(void *user, void *p)
{
    (void)user;
    free(p);
}

static void test_out_of_memory(void)
{
    failing f = {-1};
    tt_context_options co;
    tt_context_options_default(&co);
    co.allocator.alloc = f_alloc;
    co.allocator.realloc = f_realloc;
    co.allocator.free = f_free;
    co.allocator.user = &f;
    tt_context *ctx;
    REQUIRE_OK(NULL, tt_context_create(&co, &ctx));
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, verts, 8, indices, 4, &scene));
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *accel;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &accel));
    tt_camera cam = camera();
    tt_render_options o;
    tt_render_options_default(&o);
    o.width = W;
    o.height = H;
    o.keep_hits = o.keep_image = o.keep_pixel_stats = o.stats = 1;
    o.repeat = 2;
    int failures = 0, n;
    for (n = 0; n < 100; n++) {
        tt_render_result *r = NULL;
        f.countdown = n;
        tt_status st = tt_render(ctx, scene, accel, &cam, &o, &r);
        f.countdown = -1;
        if (st == TT_OK) {
            tt_render_result_destroy(r);
            break;
        }
        failures++;
        CHECK_MSG(st == TT_ERR_OUT_OF_MEMORY && r == NULL, "allocation %d: status %d", n, st);
    }
    CHECK(failures >= 5 && n < 100);
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, verts, 8, indices, 4, &scene));
    for (const char *const *n = tt_accel_names(); *n; n++) test_structure(ctx, scene, *n);
    test_errors(ctx, scene);
    test_out_of_memory();
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
