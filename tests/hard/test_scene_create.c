/* tt_scene_create and tt_context_create with bad and borderline input:
 * non-finite coordinates and indices out of range are invalid arguments
 * (named in the message, nothing allocated, no scene back); a scene of zero
 * triangles is a valid empty scene that every structure builds, checks and
 * misses with every ray, and that renders to an all-miss image; an
 * allocator with only some of its three hooks set is refused. */
#include <math.h>
#include <string.h>

#include "check.h"

static const float quad[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const uint32_t quad_idx[6] = {0, 1, 2, 0, 2, 3};

static size_t allocations;
static void *count_alloc(void *u, size_t n) { (void)u; allocations++; return malloc(n); }
static void *count_realloc(void *u, void *p, size_t n) { (void)u; allocations++; return realloc(p, n); }
static void count_free(void *u, void *p) { (void)u; free(p); }

static tt_context *counting_context(void)
{
    tt_context_options o;
    tt_context_options_default(&o);
    o.allocator.alloc = count_alloc;
    o.allocator.realloc = count_realloc;
    o.allocator.free = count_free;
    tt_context *ctx = NULL;
    REQUIRE_OK(ctx, tt_context_create(&o, &ctx));
    return ctx;
}

static void expect_refused(tt_context *ctx, const float *v, size_t nv, const uint32_t *idx, size_t nt,
                           const char *what, const char *needle)
{
    tt_scene *s = (tt_scene *)&allocations;
    size_t before = allocations;
    tt_status st = tt_scene_create(ctx, v, nv, idx, nt, &s);
    CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT, "%s: %s: %s", what, tt_strerror(st),
              tt_context_last_error(ctx));
    CHECK_MSG(s == NULL, "%s: a scene came back", what);
    CHECK_MSG(strstr(tt_context_last_error(ctx), needle) != NULL, "%s: message \"%s\" lacks \"%s\"",
              what, tt_context_last_error(ctx), needle);
    CHECK_MSG(allocations == before, "%s: %zu allocations for a refused input", what,
              allocations - before);
    if (st == TT_OK) tt_scene_destroy(s);
}

static void bad_scenes(tt_context *ctx)
{
    const float bad[3] = {NAN, INFINITY, -INFINITY};
    for (int b = 0; b < 3; b++)
        for (int k = 0; k < 12; k++) {
            float v[12];
            memcpy(v, quad, sizeof v);
            v[k] = bad[b];
            char what[64];
            snprintf(what, sizeof what, "coordinate %d = %g", k, bad[b]);
            char needle[64];
            snprintf(needle, sizeof needle, "vertex %d has a non-finite coordinate", k / 3);
            expect_refused(ctx, v, 4, quad_idx, 2, what, needle);
        }
    /* a non-finite vertex that no triangle uses is refused too */
    float v5[15];
    memcpy(v5, quad, sizeof quad);
    v5[12] = 0, v5[13] = NAN, v5[14] = 0;
    expect_refused(ctx, v5, 5, quad_idx, 2, "an unused NaN vertex", "vertex 4");
    static const uint32_t out_of_range[3][6] = {
        {0, 1, 2, 0, 2, 4}, {0, 1, 2, 0xFFFFFFFFu, 2, 3}, {0, 1, 2, 0, 0x80000000u, 3}};
    for (int i = 0; i < 3; i++)
        expect_refused(ctx, quad, 4, out_of_range[i], 2, "an index out of range", "triangle 1 refers to vertex");
    expect_refused(ctx, quad, 0, quad_idx, 2, "indices with no vertices", "only 0 vertices");
    expect_refused(ctx, NULL, 4, quad_idx, 2, "NULL vertices", "NULL");
    expect_refused(ctx, quad, 4, NULL, 2, "NULL indices", "NULL");
    expect_refused(ctx, quad, SIZE_MAX / 4, quad_idx, 2, "a vertex count overflowing the byte size",
                   "more than");
    expect_refused(ctx, quad, 4, quad_idx, (size_t)0xFFFFFFFFu, "2^32 - 1 triangles (ids are uint32)",
                   "more than");
    CHECK(tt_scene_create(ctx, quad, 4, quad_idx, 2, NULL) == TT_ERR_INVALID_ARGUMENT);
    tt_scene *s = (tt_scene *)&allocations;
    CHECK(tt_scene_create(NULL, quad, 4, quad_idx, 2, &s) == TT_ERR_INVALID_ARGUMENT && s == NULL);
    /* degenerate triangles are fine (they are never hit) */
    static const uint32_t degenerate[6] = {0, 0, 1, 2, 2, 2};
    CHECK_OK(ctx, tt_scene_create(ctx, quad, 4, degenerate, 2, &s));
    CHECK(tt_scene_triangle_count(s) == 2);
    tt_scene_destroy(s);
}

/* The empty scene: 0 triangles (with or without vertices). */
static void empty_scene(tt_context *ctx)
{
    for (int with_vertices = 0; with_vertices < 2; with_vertices++) {
        tt_scene *s = NULL;
        CHECK_OK(ctx, tt_scene_create(ctx, with_vertices ? quad : NULL, with_vertices ? 4 : 0, NULL, 0, &s));
        if (!s) continue;
        CHECK(tt_scene_triangle_count(s) == 0);
        float lo[3], hi[3], t[9];
        tt_scene_bounds(s, lo, hi);
        CHECK(!(lo[0] <= hi[0])); /* empty bounds */
        CHECK(tt_scene_triangle(s, 0, t) == TT_ERR_INVALID_ARGUMENT);
        tt_camera cam;
        tt_camera_frame_scene(s, &cam);
        for (const char *const *name = tt_accel_names(); *name; name++) {
            tt_build_options o;
            tt_build_options_default(&o);
            o.accel = *name;
            tt_accel *acc = NULL;
            tt_status st = tt_accel_build(ctx, s, &o, &acc);
            CHECK_MSG(st == TT_OK, "%s on the empty scene: %s", *name, tt_context_last_error(ctx));
            if (st != TT_OK) continue;
            CHECK_OK(ctx, tt_accel_check(acc));
            tt_ray r = {{0, 0, -5}, 0.0f, {0.1f, 0.2f, 1.0f}, INFINITY};
            tt_hit h;
            int occ = 1;
            CHECK_OK(ctx, tt_intersect1(acc, &r, &h));
            CHECK_MSG(h.prim == TT_INVALID_ID && isinf(h.t), "%s: a hit in the empty scene", *name);
            CHECK_OK(ctx, tt_occluded1(acc, &r, &occ));
            CHECK(occ == 0);
            uint32_t hint = tt_accel_locate(acc, cam.eye);
            tt_trace_args args = {hint, TT_INVALID_ID, NULL};
            CHECK_OK(ctx, tt_intersect1_ex(acc, &r, &h, &args));
            CHECK(h.prim == TT_INVALID_ID);
            tt_render_options ro;
            tt_render_options_default(&ro);
            ro.width = 8, ro.height = 6, ro.keep_hits = 1, ro.stats = 1;
            tt_render_result *res = NULL;
            st = tt_render(ctx, s, acc, &cam, &ro, &res);
            CHECK_MSG(st == TT_OK, "%s: render of the empty scene: %s", *name, tt_context_last_error(ctx));
            if (st == TT_OK) {
                const tt_render_summary *sum = tt_render_get_summary(res);
                CHECK(sum->primary_rays == 48 && sum->primary_hits == 0 && sum->shadow_rays == 0);
                size_t size = 0;
                const uint8_t *hits = tt_render_hits(res, &size);
                CHECK(hits && size == 48 * 12);
                for (size_t i = 0; hits && i < 48; i++) {
                    uint32_t prim;
                    memcpy(&prim, hits + 12 * i, 4);
                    CHECK(prim == TT_INVALID_ID);
                }
                tt_render_result_destroy(res);
            }
            tt_accel_destroy(acc);
        }
        tt_scene_destroy(s);
    }
    /* and the getters on no scene at all */
    float lo[3], hi[3];
    tt_scene_bounds(NULL, lo, hi);
    CHECK(!(lo[0] <= hi[0]));
    CHECK(tt_scene_triangle_count(NULL) == 0 && tt_scene_vertex_count(NULL) == 0);
}

static void partial_allocators(void)
{
    for (int mask = 1; mask < 7; mask++) { /* 7 (all) and 0 (none) are valid */
        tt_context_options o;
        tt_context_options_default(&o);
        if (mask & 1) o.allocator.alloc = count_alloc;
        if (mask & 2) o.allocator.realloc = count_realloc;
        if (mask & 4) o.allocator.free = count_free;
        tt_context *ctx = (tt_context *)&allocations;
        tt_status st = tt_context_create(&o, &ctx);
        CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT && ctx == NULL,
                  "an allocator with hooks %d of 7: %s", mask, tt_strerror(st));
        if (st == TT_OK) tt_context_destroy(ctx);
    }
    tt_context_options o;
    tt_context_options_default(&o);
    o.threads = -1;
    tt_context *ctx = (tt_context *)&allocations;
    CHECK(tt_context_create(&o, &ctx) == TT_ERR_INVALID_ARGUMENT && ctx == NULL);
    CHECK(tt_context_create(NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_context_create(NULL, &ctx) == TT_OK && ctx != NULL);
    tt_context_destroy(ctx);
    tt_context_destroy(NULL);
}

int main(void)
{
    tt_context *ctx = counting_context();
    bad_scenes(ctx);
    empty_scene(ctx);
    partial_allocators();
    tt_context_destroy(ctx);
    return tt_test_finish();
}
