/* Hard rays, for every registered structure and variant against bruteforce:
 * - the slab test itself (geometry/aabb.h) on rays lying in a box's face
 *   plane, flat boxes, boxes behind the origin: it must never cull a box the
 *   ray touches, or every structure misses what bruteforce hits;
 * - axis-parallel rays on a grid through the faces, edges and vertices of
 *   axis-aligned cubes (the planes every split candidate comes from), from
 *   outside and from exactly on the faces, with +0 and -0 components;
 * - the targeted families of hard_rays.h (origins on triangles, grazing rays,
 *   zero/tiny/huge direction components, exact interval ends) on the cubes
 *   and on a flat scene;
 * - NaN/Inf in the ray, a zero direction and a negative tmin (the ray
 *   contract, treetrace.h): TT_ERR_INVALID_ARGUMENT with a message, from
 *   every structure; empty intervals are legal misses;
 * - cameras with NaN/Inf or degenerate values: tt_camera_ray and tt_render
 *   refuse them. */
#include "core/context.h" /* tt_now */
#include "geometry/aabb.h"
#include "hard_rays.h"

/* ------------------------------------------------------------- slab test */

static int box_touched(const float org[3], const float dir[3], float tmin, float tmax,
                       const float lo[3], const float hi[3])
{
    tt_wray r;
    tt_wray_init(&r, org, dir, tmin, tmax);
    return tt_ray_box(&r, lo, hi, tmax) != INFINITY;
}

static void test_slab(void)
{
    static const float lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    /* rays lying in each face plane of the unit box, crossing the face, with
     * +0 and -0 in the component across the plane */
    for (int axis = 0; axis < 3; axis++)
        for (int side = 0; side < 2; side++)
            for (int neg = 0; neg < 2; neg++) {
                int u = (axis + 1) % 3;
                float org[3] = {0.5f, 0.5f, 0.5f}, dir[3] = {0, 0, 0};
                org[axis] = side ? 1.0f : 0.0f;
                org[u] = -1.0f;
                dir[u] = 1.0f;
                dir[axis] = neg ? -0.0f : 0.0f;
                CHECK_MSG(box_touched(org, dir, 0.0f, INFINITY, lo, hi),
                          "a ray in the %s face plane of axis %d (dir component %s0) is culled",
                          side ? "upper" : "lower", axis, neg ? "-" : "+");
                /* ... and along an edge of the box */
                int w = (axis + 2) % 3;
                org[w] = side ? 0.0f : 1.0f;
                CHECK_MSG(box_touched(org, dir, 0.0f, INFINITY, lo, hi),
                          "a ray along an edge (axes %d, %d) is culled", axis, w);
            }
    /* a flat box (zero extent on one axis) with the ray in its plane */
    static const float flo[3] = {0, 0, 0.5f}, fhi[3] = {1, 1, 0.5f};
    float org[3] = {-1.0f, 0.5f, 0.5f}, dir[3] = {1.0f, 0.0f, 0.0f};
    CHECK_MSG(box_touched(org, dir, 0.0f, INFINITY, flo, fhi), "a ray in a flat box's plane is culled");
    /* a flat box crossed behind the origin, found by a negative tmin */
    float org2[3] = {0.5f, 0.5f, 2.0f}, dir2[3] = {0.0f, 0.0f, 1.0f};
    CHECK_MSG(box_touched(org2, dir2, -10.0f, INFINITY, flo, fhi),
              "a flat box behind the origin (t = -1.5) is culled with tmin = -10");
    /* a box straddling t = 0 with a negative tmin */
    float org3[3] = {0.5f, 0.5f, 0.5f};
    CHECK(box_touched(org3, dir2, -10.0f, INFINITY, lo, hi));
    /* sanity: the test does cull boxes the ray misses */
    float org4[3] = {2.0f, 2.0f, 2.0f};
    CHECK(!box_touched(org4, dir2, 0.0f, INFINITY, lo, hi));
    float org5[3] = {0.5f, 0.5f, -2.0f};
    CHECK(!box_touched(org5, dir2, 0.0f, 1.0f, lo, hi)); /* ends before the box */
}

/* ------------------------------------------------ axis-parallel ray grid */

/* For each axis and direction, rays on a half-unit grid of the two other
 * coordinates (through cube faces, edges, vertices and gaps), starting
 * outside the scene and starting exactly on integer planes inside it. */
static void add_axis_grid(hard_rays *s, int extent)
{
    for (int axis = 0; axis < 3; axis++) {
        int u = (axis + 1) % 3, w = (axis + 2) % 3;
        for (int i = -1; i <= 2 * extent + 1; i++)
            for (int j = -1; j <= 2 * extent + 1; j++)
                for (int sign = -1; sign <= 1; sign += 2) {
                    float o[3], d[3] = {0, 0, 0}, nd[3] = {-0.0f, -0.0f, -0.0f};
                    o[u] = 0.5f * (float)i;
                    o[w] = 0.5f * (float)j;
                    o[axis] = sign > 0 ? -1.5f : (float)extent + 1.5f;
                    d[axis] = nd[axis] = (float)sign;
                    hard_rays_add(s, "axis grid from outside", o, d, 0.0f, INFINITY);
                    if (((i + j) & 3) == 0)
                        hard_rays_add(s, "axis grid from outside, -0 components", o, nd, 0.0f, INFINITY);
                    /* from a plane inside: integer coordinate along the axis */
                    o[axis] = (float)((i + j + 2 * extent) % (extent + 1));
                    hard_rays_add(s, "axis grid from an integer plane", o, d, 0.0f, INFINITY);
                }
    }
}

/* ------------------------------------------------------------ bad input */

static void expect_invalid(tt_context *ctx, const tt_accel *acc, const tt_ray *r, const char *what,
                           const char *needle)
{
    tt_hit h;
    int occ = 7;
    tt_ray_stats st;
    memset(&st, 0, sizeof st);
    tt_trace_args args = {TT_INVALID_ID, TT_INVALID_ID, &st};
    tt_status a = tt_intersect1(acc, r, &h);
    CHECK_MSG(a == TT_ERR_INVALID_ARGUMENT, "%s: %s intersect1 gave %s", tt_accel_name(acc), what,
              tt_strerror(a));
    CHECK_MSG(strstr(tt_context_last_error(ctx), needle) != NULL, "%s: %s: message \"%s\"",
              tt_accel_name(acc), what, tt_context_last_error(ctx));
    tt_status b = tt_occluded1(acc, r, &occ);
    CHECK_MSG(b == TT_ERR_INVALID_ARGUMENT, "%s: %s occluded1 gave %s", tt_accel_name(acc), what,
              tt_strerror(b));
    tt_status c = tt_intersect1_ex(acc, r, &h, &args);
    tt_status d = tt_occluded1_ex(acc, r, &occ, &args);
    CHECK_MSG(c == TT_ERR_INVALID_ARGUMENT && d == TT_ERR_INVALID_ARGUMENT, "%s: %s _ex calls",
              tt_accel_name(acc), what);
    CHECK_MSG(st.rays == 0, "%s: %s was counted", tt_accel_name(acc), what);
}

static void visit_invalid(void *user, const char *label, const tt_accel *acc)
{
    tt_context *ctx = user;
    (void)label;
    const float nan = NAN, inf = INFINITY;
    for (int k = 0; k < 3; k++) {
        float bad[3] = {nan, inf, -inf};
        for (int b = 0; b < 3; b++) {
            tt_ray r = {{0.5f, 0.5f, -3.0f}, 0.0f, {0.1f, 0.2f, 1.0f}, inf};
            r.org[k] = bad[b];
            expect_invalid(ctx, acc, &r, "a non-finite origin", "non-finite");
            r.org[k] = 0.5f;
            r.dir[k] = bad[b];
            expect_invalid(ctx, acc, &r, "a non-finite direction", "non-finite");
        }
    }
    tt_ray z = {{0.5f, 0.5f, -3.0f}, 0.0f, {0.0f, -0.0f, 0.0f}, inf};
    expect_invalid(ctx, acc, &z, "a zero direction", "zero direction");
    /* the largest component below 2^-80: 1/d and the watertight test's terms
     * leave float range; 2^-80 itself is accepted (the other tests trace it) */
    tt_ray sh = {{0.5f, 0.5f, -3.0f}, 0.0f, {1e-30f, -0x1.fffffep-81f, 1e-45f}, inf};
    expect_invalid(ctx, acc, &sh, "a too short direction", "direction too short");
    tt_ray n1 = {{0.5f, 0.5f, -3.0f}, nan, {0.0f, 0.0f, 1.0f}, inf};
    expect_invalid(ctx, acc, &n1, "a NaN tmin", "NaN");
    tt_ray n2 = {{0.5f, 0.5f, -3.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, nan};
    expect_invalid(ctx, acc, &n2, "a NaN tmax", "NaN");
    /* the ray contract: rays start at their origin, tmin >= 0; a negative
     * tmin, -inf included, is refused */
    tt_ray back = {{0.5f, 0.5f, 3.0f}, -10.0f, {0.0f, 0.0f, 1.0f}, inf};
    expect_invalid(ctx, acc, &back, "a negative tmin", "negative tmin");
    back.tmin = -inf;
    expect_invalid(ctx, acc, &back, "tmin = -inf", "negative tmin");
    back.tmin = -1e-45f;
    expect_invalid(ctx, acc, &back, "tmin = -1e-45", "negative tmin");
    /* legal: tmin = -0 (zero), tmax = +inf, and empty intervals (tmin >=
     * tmax, tmin = +inf, tmax = -inf): misses, not occluded */
    tt_hit h;
    int occ = -1;
    tt_ray up = {{0.5f, 0.5f, -3.0f}, -0.0f, {0.0f, 0.0f, 1.0f}, inf};
    CHECK_OK(ctx, tt_intersect1(acc, &up, &h));
    CHECK_MSG(h.prim != TT_INVALID_ID, "%s: the ray up the cubes' column missed", tt_accel_name(acc));
    const float empty[3][2] = {{inf, inf}, {0.0f, -inf}, {2.0f, 1.0f}};
    for (int k = 0; k < 3; k++) {
        up.tmin = empty[k][0];
        up.tmax = empty[k][1];
        CHECK_OK(ctx, tt_intersect1(acc, &up, &h));
        CHECK_OK(ctx, tt_occluded1(acc, &up, &occ));
        CHECK_MSG(h.prim == TT_INVALID_ID && h.t == inf && occ == 0,
                  "%s: the empty interval [%g, %g) gave prim %u occluded %d", tt_accel_name(acc),
                  up.tmin, up.tmax, h.prim, occ);
    }
}

/* ---------------------------------------------------------------- camera */

/* The scene and structure tt_render is tried with. */
static tt_context *cam_ctx;
static const tt_scene *cam_scene;
static const tt_accel *cam_accel;

/* ray_too: tt_camera_ray must refuse it as well (it does not use the
 * light, so a bad light is only tt_render's business). */
static void expect_refused(const tt_camera *c, const char *what, int ray_too)
{
    tt_ray r;
    memset(&r, 0, sizeof r);
    tt_status st = ray_too ? tt_camera_ray(c, 4, 3, 1, 1, &r) : TT_ERR_INVALID_ARGUMENT;
    CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT, "tt_camera_ray with %s: %s (dir %g %g %g)", what,
              tt_strerror(st), r.dir[0], r.dir[1], r.dir[2]);
    tt_render_options o;
    tt_render_options_default(&o);
    o.width = 4, o.height = 3;
    tt_render_result *res = (tt_render_result *)&o;
    st = tt_render(cam_ctx, cam_scene, cam_accel, c, &o, &res);
    CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT && res == NULL, "tt_render with %s: %s", what,
              tt_strerror(st));
    if (st == TT_OK) tt_render_result_destroy(res);
    else CHECK_MSG(strstr(tt_context_last_error(cam_ctx), "camera") != NULL,
                   "tt_render with %s: the message \"%s\" does not say it is the camera", what,
                   tt_context_last_error(cam_ctx));
}

static void expect_camera_refused(const tt_camera *c, const char *what) { expect_refused(c, what, 1); }

static void test_camera(tt_context *ctx)
{
    hard_mesh m = {0};
    hard_gen_cubes(&m, 2);
    tt_scene *scene = hard_scene(ctx, &m);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *acc = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &acc));
    cam_ctx = ctx, cam_scene = scene, cam_accel = acc;

    const tt_camera good = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45.0f, {1, 2, 3}, 1};
    tt_ray r;
    CHECK(tt_camera_ray(&good, 4, 3, 1, 1, &r) == TT_OK);
    const float bad[3] = {NAN, INFINITY, -INFINITY};
    static const char *const bad_name[3] = {"NaN", "+inf", "-inf"};
    char what[96];
    for (int b = 0; b < 3; b++)
        for (int k = 0; k < 3; k++) {
            tt_camera c = good;
            c.eye[k] = bad[b];
            snprintf(what, sizeof what, "eye[%d] = %s", k, bad_name[b]);
            expect_camera_refused(&c, what);
            c = good;
            c.look[k] = bad[b];
            snprintf(what, sizeof what, "look[%d] = %s", k, bad_name[b]);
            expect_camera_refused(&c, what);
            c = good;
            c.up[k] = bad[b];
            snprintf(what, sizeof what, "up[%d] = %s", k, bad_name[b]);
            expect_camera_refused(&c, what);
        }
    tt_camera c = good;
    c.fov_deg = NAN;
    expect_camera_refused(&c, "fov NaN");
    c.fov_deg = 0.0f;
    expect_camera_refused(&c, "fov 0");
    c.fov_deg = 180.0f;
    expect_camera_refused(&c, "fov 180");
    c.fov_deg = -30.0f;
    expect_camera_refused(&c, "fov -30");
    c = good;
    memcpy(c.look, c.eye, sizeof c.look);
    expect_camera_refused(&c, "eye == look");
    c = good;
    c.up[0] = 0, c.up[1] = 0, c.up[2] = -2.0f; /* parallel to look - eye */
    expect_camera_refused(&c, "up parallel to the view direction");
    c = good;
    c.up[0] = c.up[1] = c.up[2] = 0.0f;
    expect_camera_refused(&c, "a zero up vector");
    c = good;
    c.eye[0] = 3e38f, c.look[0] = -3e38f; /* look - eye overflows */
    expect_camera_refused(&c, "look - eye overflowing float");
    c = good;
    c.light[1] = NAN;
    expect_refused(&c, "a NaN light", 0);
    tt_accel_destroy(acc);
    tt_scene_destroy(scene);
    hard_mesh_free(&m);
}

/* --------------------------------------------------------------- driver */

static void run(tt_context *ctx, hard_mesh *m, int grid_extent)
{
    double t0 = tt_now();
    tt_scene *scene = hard_scene(ctx, m);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));
    hard_rays rays = {0}, intervals = {0};
    if (grid_extent) add_axis_grid(&rays, grid_extent);
    hard_rays_targeted(&rays, scene, 50, 4242u);
    hard_rays_reference(&rays, ref);
    hard_geom g;
    hard_geom_init(&g, scene);
    hard_rays_intervals(&intervals, &rays, g.diag, 80);
    for (size_t i = 0; i < intervals.n; i++)
        hard_rays_add(&rays, intervals.kind[i], intervals.ray[i].org, intervals.ray[i].dir,
                      intervals.ray[i].tmin, intervals.ray[i].tmax);
    hard_rays_reference(&rays, ref);
    size_t built = hard_each_structure(ctx, m->name, scene, &rays, 0);
    printf("%-12s %5zu triangles, %5zu rays, %3zu structure variants, %.2fs\n", m->name, m->nt,
           rays.n, built, tt_now() - t0);
    hard_rays_free(&rays);
    hard_rays_free(&intervals);
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
    hard_mesh_free(m);
}

/* The invalid-input checks need one build of each structure (defaults). */
static void run_invalid(tt_context *ctx)
{
    hard_mesh m = {0};
    hard_gen_cubes(&m, 2);
    tt_scene *scene = hard_scene(ctx, &m);
    for (const char *const *name = tt_accel_names(); *name; name++) {
        tt_build_options o;
        tt_build_options_default(&o);
        o.accel = *name;
        tt_accel *acc = NULL;
        tt_status st = tt_accel_build(ctx, scene, &o, &acc);
        CHECK_MSG(st == TT_OK, "%s: %s", *name, tt_context_last_error(ctx));
        if (st != TT_OK) continue;
        visit_invalid(ctx, *name, acc);
        tt_accel_destroy(acc);
    }
    tt_scene_destroy(scene);
    hard_mesh_free(&m);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    test_slab();

    hard_mesh m = {0};
    hard_gen_cubes(&m, 4);
    run(ctx, &m, 8);
    hard_gen_coplanar(&m, 1, 8, 100, 99u);
    run(ctx, &m, 0);
    hard_gen_soup(&m, "soup", 600, 0.1f, 98u);
    run(ctx, &m, 0);

    /* after the forked runs: these use OpenMP (tt_render, the builders) in
     * this process, and a child forked after that could not */
    test_camera(ctx);
    run_invalid(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
