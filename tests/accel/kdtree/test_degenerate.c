/* Degenerate inputs: no triangle, one triangle, all triangles coplanar, all
 * identical, a soup with collinear and point triangles, and that soup at
 * coordinates near the float range. The exact builders agree, the check
 * passes on their trees and the binned builder's, and every traversal on
 * both agrees with bruteforce on random rays (and on rays lying in the
 * common plane). */
#include <math.h>

#include "compare.h"
#include "io/scene.h"
#include "kd_scenes.h"
#include "kd_testing.h"

/* The scene's triangles, centred on 0 and scaled by f. */
static tt_scene *scaled(tt_context *ctx, const tt_scene *s, float f)
{
    const size_t n = tt_scene_triangle_count(s);
    float *v = malloc(9 * n * sizeof *v);
    uint32_t *ix = malloc(3 * n * sizeof *ix);
    if (!v || !ix) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    for (size_t i = 0; i < 9 * n; i++) v[i] = (s->tri[i] - 0.5f) * f;
    for (size_t i = 0; i < 3 * n; i++) ix[i] = (uint32_t)i;
    tt_scene *out = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 3 * n, ix, n, &out));
    free(v);
    free(ix);
    return out;
}

static void exercise(tt_context *ctx, tt_scene *scene, const char *what)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));
    const int dmins[] = {1, -1};
    for (int d = 0; d < 2; d++) {
        tt_accel *a = kd_build_with(ctx, scene, TT_KD_NLOGN, dmins[d], TT_KD_HTR);
        tt_accel *b = kd_build_with(ctx, scene, TT_KD_NLOG2N, dmins[d], TT_KD_HTR);
        CHECK_MSG(kd_same_tree(tt_kdtree_of(a), tt_kdtree_of(b)), "%s: builders differ", what);
        CHECK_OK(ctx, tt_accel_check(a));
        CHECK_OK(ctx, tt_accel_check(b));
        tt_accel views[4];
        kd_traversal_views(a, views);
        for (int tr = 0; tr < 4; tr++) {
            size_t bad = tt_test_compare_random(scene, &views[tr], ref, 600, 3);
            CHECK_MSG(bad == 0, "%s, %s, dmin %d: %zu random rays disagree", what,
                      kd_traversal_names[tr], dmins[d], bad);
        }
        tt_accel_destroy(a);
        tt_accel_destroy(b);
        /* The binned builder: its own tree, as exact for every ray. */
        tt_accel *c = kd_build_with(ctx, scene, TT_KD_BINNED, dmins[d], TT_KD_HTR);
        CHECK_OK(ctx, tt_accel_check(c));
        kd_traversal_views(c, views);
        for (int tr = 0; tr < 4; tr++) {
            size_t bad = tt_test_compare_random(scene, &views[tr], ref, 600, 5);
            CHECK_MSG(bad == 0, "%s, binned, %s, dmin %d: %zu random rays disagree", what,
                      kd_traversal_names[tr], dmins[d], bad);
        }
        tt_accel_destroy(c);
    }
    tt_accel_destroy(ref);
}

int main(void)
{
    tt_context *ctx = tt_test_context();

    /* No triangle: one empty leaf, every ray misses, locate finds nothing. */
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, NULL, 0, NULL, 0, &s));
    exercise(ctx, s, "empty");
    tt_accel *a = kd_build_with(ctx, s, TT_KD_NLOGN, 4, TT_KD_SLTR);
    const tt_kdtree *t = tt_kdtree_of(a);
    CHECK(t->nodes_total == 1 && t->leaves == 1 && t->ref_count == 0);
    tt_ray r = {{0, 0, 0}, 0.0f, {0, 0, 1}, INFINITY};
    tt_hit h;
    CHECK_OK(ctx, tt_intersect1(a, &r, &h));
    CHECK(h.prim == TT_INVALID_ID && isinf(h.t));
    float origin[3] = {0, 0, 0};
    CHECK(tt_accel_locate(a, origin) == TT_INVALID_ID);
    tt_accel_destroy(a);
    tt_scene_destroy(s);

    /* One triangle. */
    const float v1[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t i1[3] = {0, 1, 2};
    REQUIRE_OK(ctx, tt_scene_create(ctx, v1, 3, i1, 1, &s));
    exercise(ctx, s, "one");
    a = kd_build_with(ctx, s, TT_KD_NLOGN, 4, TT_KD_BTR);
    tt_ray down = {{0.25f, 0.25f, 1.0f}, 0.0f, {0, 0, -1}, INFINITY};
    CHECK_OK(ctx, tt_intersect1(a, &down, &h));
    CHECK(h.prim == 0 && h.t == 1.0f);
    tt_accel_destroy(a);
    tt_scene_destroy(s);

    /* Coplanar: the scene box is flat; rays lying in the plane never hit. */
    s = kd_scene_coplanar(ctx, 200, 9);
    exercise(ctx, s, "coplanar");
    a = kd_build_with(ctx, s, TT_KD_NLOGN, 2, TT_KD_HTR);
    CHECK(tt_kdtree_of(a)->interior > 0); /* split along x and y */
    tt_ray in_plane = {{-1.0f, 2.0f, 0.25f}, 0.0f, {1, 0.1f, 0}, INFINITY};
    tt_accel views[4];
    kd_traversal_views(a, views);
    for (int tr = 0; tr < 4; tr++) {
        CHECK_OK(ctx, tt_intersect1(&views[tr], &in_plane, &h));
        CHECK(h.prim == TT_INVALID_ID);
    }
    tt_accel_destroy(a);
    tt_scene_destroy(s);

    /* Identical triangles: nothing to split, one leaf with all of them. */
    s = kd_scene_identical(ctx, 64);
    exercise(ctx, s, "identical");
    a = kd_build_with(ctx, s, TT_KD_NLOGN, 1, TT_KD_HTR);
    CHECK(tt_kdtree_of(a)->leaves >= 1 && tt_kdtree_of(a)->ref_count >= 64);
    tt_accel_destroy(a);
    tt_scene_destroy(s);

    /* A soup with collinear and point triangles (never hit). */
    s = kd_scene_soup(ctx, 300, 17);
    exercise(ctx, s, "soup");
    tt_scene_destroy(s);

    /* Huge coordinates: the soup scaled to 1e30, and (the binned builder
     * only) to where differences of coordinates overflow float, as its
     * bin arithmetic does in float. */
    s = kd_scene_soup(ctx, 300, 23);
    tt_scene *huge = scaled(ctx, s, 1e30f);
    exercise(ctx, huge, "huge");
    tt_scene_destroy(huge);
    huge = scaled(ctx, s, 3e38f);
    a = kd_build_with(ctx, huge, TT_KD_BINNED, 1, TT_KD_HTR);
    CHECK_OK(ctx, tt_accel_check(a));
    tt_accel_destroy(a);
    tt_scene_destroy(huge);
    tt_scene_destroy(s);

    tt_context_destroy(ctx);
    return tt_test_finish();
}
