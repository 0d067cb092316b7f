/* Public calls that had no direct test, checked without the shared scenes
 * (so they are covered where those are absent): tt_version,
 * tt_context_threads, tt_rtree_max_entries, tt_kdtree_dmin (and that a
 * built kd-tree reports the d_min it promises), tt_accel_build_seconds; and
 * tt_camera_rays with the batch calls (tt_intersect, tt_occluded and their
 * _arrays forms) on the hand-built scene, whose every pixel is known by
 * construction (known_scene.h). */
#include <math.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "known_scene.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void test_version(void)
{
    const char *v = tt_version();
    CHECK(v != NULL && strcmp(v, TT_VERSION_STRING) == 0);
    int a = -1, b = -1, c = -1, n = -1;
    CHECK(v && sscanf(v, "%d.%d.%d%n", &a, &b, &c, &n) == 3 && v[n] == '\0' && a >= 0 && b >= 0 &&
          c >= 0);
    CHECK(strcmp(TT_VERSION_STRING, "0.1.0") == 0); /* bump this with the header */
}

static void test_threads(void)
{
    static const int asked[] = {1, 2, 3, 7};
    for (size_t i = 0; i < sizeof asked / sizeof asked[0]; i++) {
        tt_context_options co;
        tt_context_options_default(&co);
        co.threads = asked[i];
        tt_context *ctx = NULL;
        REQUIRE_OK(NULL, tt_context_create(&co, &ctx));
        CHECK_MSG(tt_context_threads(ctx) == asked[i], "asked for %d threads, got %d", asked[i],
                  tt_context_threads(ctx));
        tt_context_destroy(ctx);
    }
    tt_context *ctx = tt_test_context(); /* 0: OpenMP's default, reported as 0 */
    CHECK(tt_context_threads(ctx) == 0);
    tt_context_destroy(ctx);
    CHECK(tt_context_threads(NULL) == 0);
}

static void test_max_entries(void)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    tt_rtree_options r = bo.rtree;
    CHECK(r.M == 0 && r.layout == TT_RTREE_LAYOUT_COMPACT);
    CHECK(tt_rtree_max_entries(&r) == 16);
    r.layout = TT_RTREE_LAYOUT_COMPLETE;
    CHECK(tt_rtree_max_entries(&r) == 4);
    for (int M = 4; M <= 16; M++) {
        r.M = M;
        CHECK(tt_rtree_max_entries(&r) == M);
    }
}

static void test_dmin(void)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    tt_kdtree_options k = bo.kdtree;
    CHECK(k.dmin == 0 && k.traversal == TT_KD_HTR);
    CHECK(tt_kdtree_dmin(&k) == -1);
    for (int t = TT_KD_BTR; t <= TT_KD_SEQ; t++) {
        k.traversal = (tt_kd_traversal)t;
        CHECK(tt_kdtree_dmin(&k) == TT_KD_DMIN_BOXES);
    }
    for (int d = -1; d <= 6; d++) {
        if (d == 0) continue;
        k.dmin = d;
        CHECK(tt_kdtree_dmin(&k) == d);
    }
}

static tt_scene *known_scene(tt_context *ctx)
{
    tt_scene *scene = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, tt_known_vertices, TT_KNOWN_VERTICES, tt_known_indices,
                                    TT_KNOWN_TRIANGLES, &scene));
    return scene;
}

/* Every structure: build seconds above 0 and within the call's wall time;
 * a kd-tree reports the d_min tt_kdtree_dmin promised. */
static void test_build_seconds(tt_context *ctx, const tt_scene *scene)
{
    CHECK(tt_accel_build_seconds(NULL) == 0.0);
    for (const char *const *name = tt_accel_names(); *name; name++) {
        tt_build_options bo;
        tt_build_options_default(&bo);
        bo.accel = *name;
        tt_accel *a = NULL;
        double t0 = now();
        REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &a));
        double wall = now() - t0;
        double s = tt_accel_build_seconds(a);
        CHECK_MSG(s > 0.0 && s <= wall, "%s: build seconds %g, call took %g", *name, s, wall);
        tt_accel_destroy(a);
    }
    for (int t = TT_KD_HTR; t <= TT_KD_SEQ; t++) {
        tt_build_options bo;
        tt_build_options_default(&bo);
        bo.accel = "kdtree";
        bo.kdtree.traversal = (tt_kd_traversal)t;
        tt_accel *a = NULL;
        REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &a));
        CHECK_MSG(tt_test_stat(a, "dmin") == (double)tt_kdtree_dmin(&bo.kdtree),
                  "traversal %d: built with dmin %g, tt_kdtree_dmin says %d", t,
                  tt_test_stat(a, "dmin"), tt_kdtree_dmin(&bo.kdtree));
        tt_accel_destroy(a);
    }
}

static void put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

/* tt_camera_rays, then every structure through the batch calls: the hit
 * buffer made from their answers must be the construction's. */
static void test_camera_and_batches(tt_context *ctx, const tt_scene *scene)
{
    enum { W = TT_KNOWN_W, H = TT_KNOWN_H, N = W * H };
    tt_camera cam = tt_known_camera();
    static tt_ray rays[N], shadow[N];
    CHECK_OK(ctx, tt_camera_rays(&cam, W, H, rays));
    size_t differ = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            tt_ray r;
            CHECK_OK(ctx, tt_camera_ray(&cam, W, H, x, y, &r));
            differ += memcmp(&r, &rays[y * W + x], sizeof r) != 0;
        }
    CHECK_MSG(differ == 0, "%zu of %d tt_camera_rays rays differ from tt_camera_ray's", differ, N);
    /* every ray starts at the eye, looking into -z */
    CHECK(rays[0].dir[2] < 0.0f && rays[0].org[0] == 0.0f && rays[0].tmin == 0.0f);
    tt_camera bad = cam;
    bad.fov_deg = 0.0f;
    CHECK(tt_camera_rays(&bad, W, H, rays + N / 2) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_camera_rays(&cam, 0, H, rays) == TT_ERR_INVALID_ARGUMENT);
    CHECK_OK(ctx, tt_camera_rays(&cam, W, H, rays));

    for (const char *const *name = tt_accel_names(); *name; name++) {
        tt_accel *a = tt_test_build_default(ctx, scene, *name);
        static tt_hit hits[N];
        static uint8_t occ[N], occ_arr[N];
        static uint8_t buf[12 * N];
        static float t_arr[N];
        static uint32_t prim_arr[N];
        tt_batch_options bo;
        tt_batch_options_default(&bo);
        bo.image_width = W;
        CHECK_OK(ctx, tt_intersect(a, rays, N, hits, NULL, &bo));
        int n_shadow = 0;
        for (int i = 0; i < N; i++) {
            tt_ray s;
            memset(&s, 0, sizeof s);
            if (hits[i].prim != TT_INVALID_ID && tt_shadow_ray(scene, &cam, &rays[i], &hits[i], &s))
                n_shadow++;
            else /* a ray that can hit nothing: an empty interval */
                s = rays[i], s.tmax = s.tmin;
            shadow[i] = s;
        }
        CHECK_OK(ctx, tt_occluded(a, shadow, N, occ, NULL, NULL));
        for (int i = 0; i < N; i++) {
            put_u32(buf + 12 * i, hits[i].prim);
            uint32_t tb;
            memcpy(&tb, &hits[i].t, 4);
            put_u32(buf + 12 * i + 4, tb);
            put_u32(buf + 12 * i + 8, hits[i].prim != TT_INVALID_ID ? occ[i] : 0u);
        }
        char what[96];
        snprintf(what, sizeof what, "%s through tt_intersect/tt_occluded", *name);
        CHECK_MSG(tt_known_check_hits(what, buf, sizeof buf, 1) == 0, "%s", what);
        CHECK(n_shadow == N / 2);

        /* the _arrays forms over the same rays give the same answers */
        tt_ray_arrays ra;
        memset(&ra, 0, sizeof ra);
        for (int k = 0; k < 3; k++) {
            ra.org[k] = &rays[0].org[k];
            ra.dir[k] = &rays[0].dir[k];
        }
        ra.org_stride = ra.dir_stride = sizeof(tt_ray);
        tt_hit_arrays ha = {t_arr, sizeof(float), NULL, 0, NULL, 0, prim_arr, sizeof(uint32_t)};
        CHECK_OK(ctx, tt_intersect_arrays(a, &ra, N, &ha, NULL, NULL));
        CHECK_OK(ctx, tt_occluded_arrays(a, &ra, N, occ_arr, 1, NULL, NULL));
        size_t bad_arr = 0;
        for (int i = 0; i < N; i++)
            bad_arr += prim_arr[i] != hits[i].prim || memcmp(&t_arr[i], &hits[i].t, 4) != 0 ||
                       occ_arr[i] != (hits[i].prim != TT_INVALID_ID);
        CHECK_MSG(bad_arr == 0, "%s: %zu rays differ through the _arrays calls", *name, bad_arr);
        tt_accel_destroy(a);
    }
}

int main(void)
{
    test_version();
    test_threads();
    test_max_entries();
    test_dmin();
    tt_context *ctx = tt_test_context();
    tt_scene *scene = known_scene(ctx);
    test_build_seconds(ctx, scene);
    test_camera_and_batches(ctx, scene);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
