/* tt_scene_copy_arrays: the arrays equal what the per-element calls give
 * (vertices and indices as created, triangles as tt_scene_triangle), NULL
 * skips an array, and a capacity too small is refused before any write;
 * tt_scene_normals: unit normals by the right-hand rule, zeros for a miss
 * and a degenerate triangle, an id out of range refused. */
#include <string.h>

#include "io_util.h"

int main(void)
{
    tt_context *ctx = NULL;
    REQUIRE_OK(ctx, tt_context_create(NULL, &ctx));
    const float v[15] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 2};
    const uint32_t idx[9] = {0, 1, 2, 0, 2, 3, 4, 1, 0};
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 5, idx, 3, &s));

    float vo[15], tri[27];
    uint32_t io[9];
    CHECK_OK(ctx, tt_scene_copy_arrays(s, vo, 5, io, tri, 3));
    CHECK(memcmp(vo, v, sizeof v) == 0);
    CHECK(memcmp(io, idx, sizeof idx) == 0);
    for (size_t t = 0; t < 3; t++) {
        float one[9];
        CHECK_OK(ctx, tt_scene_triangle(s, t, one));
        CHECK(memcmp(one, tri + 9 * t, sizeof one) == 0);
    }

    /* NULL skips an array (and its capacity does not matter then) */
    memset(io, 0xAB, sizeof io);
    CHECK_OK(ctx, tt_scene_copy_arrays(s, NULL, 0, io, NULL, 3));
    CHECK(memcmp(io, idx, sizeof idx) == 0);
    CHECK_OK(ctx, tt_scene_copy_arrays(s, vo, 5, NULL, NULL, 0));
    CHECK_OK(ctx, tt_scene_copy_arrays(s, NULL, 0, NULL, NULL, 0));

    /* too small: refused, named, nothing written */
    memset(vo, 0, sizeof vo);
    memset(io, 0, sizeof io);
    EXPECT_ERR(ctx, tt_scene_copy_arrays(s, vo, 4, io, NULL, 3), TT_ERR_INVALID_ARGUMENT,
               "tt_scene_copy_arrays", "room for 4 vertices", "has 5");
    EXPECT_ERR(ctx, tt_scene_copy_arrays(s, vo, 5, io, NULL, 2), TT_ERR_INVALID_ARGUMENT,
               "room for 2 triangles", "has 3");
    EXPECT_ERR(ctx, tt_scene_copy_arrays(s, NULL, 0, NULL, tri, 2), TT_ERR_INVALID_ARGUMENT,
               "room for 2 triangles");
    float zero[15] = {0};
    uint32_t zeroi[9] = {0};
    CHECK(memcmp(vo, zero, sizeof vo) == 0 && memcmp(io, zeroi, sizeof io) == 0);
    CHECK(tt_scene_copy_arrays(NULL, vo, 5, io, tri, 3) == TT_ERR_INVALID_ARGUMENT);

    /* an empty scene copies nothing and succeeds */
    tt_scene *e = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, NULL, 0, NULL, 0, &e));
    CHECK_OK(ctx, tt_scene_copy_arrays(e, NULL, 0, NULL, NULL, 0));
    CHECK_OK(ctx, tt_scene_copy_arrays(e, vo, 0, io, tri, 0));
    tt_scene_destroy(e);

    /* normals: triangle 0 and 1 lie in z = 0, counter-clockwise seen from +z */
    tt_scene *d = NULL;
    const float dv[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0}; /* a degenerate (collinear) triangle */
    const uint32_t di[3] = {0, 1, 2};
    REQUIRE_OK(ctx, tt_scene_create(ctx, dv, 3, di, 1, &d));
    uint32_t prims[4] = {0, TT_INVALID_ID, 2, 1};
    float n[12];
    memset(n, 0xAB, sizeof n);
    CHECK_OK(ctx, tt_scene_normals(s, prims, 4, n));
    CHECK(n[0] == 0 && n[1] == 0 && n[2] == 1);
    CHECK(n[3] == 0 && n[4] == 0 && n[5] == 0);
    CHECK(n[9] == 0 && n[10] == 0 && n[11] == 1);
    /* triangle 2: (0.5,0.5,2), (1,0,0), (0,0,0): unit length, the right-hand rule */
    float e1[3] = {0.5f, -0.5f, -2}, e2[3] = {-0.5f, -0.5f, -2};
    float c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                  e1[0] * e2[1] - e1[1] * e2[0]};
    float dot = c[0] * n[6] + c[1] * n[7] + c[2] * n[8];
    float len = n[6] * n[6] + n[7] * n[7] + n[8] * n[8];
    CHECK(dot > 0 && len > 0.9999f && len < 1.0001f);
    CHECK_OK(ctx, tt_scene_normals(d, di, 1, n));
    CHECK(n[0] == 0 && n[1] == 0 && n[2] == 0);
    uint32_t bad[2] = {1, 3};
    EXPECT_ERR(ctx, tt_scene_normals(s, bad, 2, n), TT_ERR_INVALID_ARGUMENT, "prims[1] = 3",
               "3 triangles");
    CHECK_OK(ctx, tt_scene_normals(s, NULL, 0, NULL));
    CHECK(tt_scene_normals(NULL, prims, 1, n) == TT_ERR_INVALID_ARGUMENT);
    tt_scene_destroy(d);

    tt_scene_destroy(s);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
