/* A program built against an installed treetrace (find_package or
 * pkg-config): a unit square of two triangles at z = 0, a batch of rays
 * down the z axis, the hits checked. Exits 0 only when every answer is
 * right. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <treetrace/treetrace.h>

int main(void)
{
    tt_context *ctx;
    if (tt_context_create(NULL, &ctx) != TT_OK) return 1;
    const float vertices[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t indices[] = {0, 1, 2, 0, 2, 3};
    tt_scene *scene;
    if (tt_scene_create(ctx, vertices, 4, indices, 2, &scene) != TT_OK) return 1;
    tt_build_options opt;
    tt_build_options_default(&opt);
    opt.accel = "kdtree";
    tt_accel *accel;
    if (tt_accel_build(ctx, scene, &opt, &accel) != TT_OK) {
        fprintf(stderr, "%s\n", tt_context_last_error(ctx));
        return 1;
    }
    tt_ray rays[3] = {
        {{0.75f, 0.25f, 2.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY}, /* triangle 0 at t 2 */
        {{0.25f, 0.75f, 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY}, /* triangle 1 at t 1 */
        {{2.0f, 2.0f, 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY},   /* a miss          */
    };
    tt_hit hits[3];
    uint8_t occluded[3];
    if (tt_intersect(accel, rays, 3, hits, NULL, NULL) != TT_OK) return 1;
    if (tt_occluded(accel, rays, 3, occluded, NULL, NULL) != TT_OK) return 1;
    int ok = hits[0].prim == 0 && hits[0].t == 2.0f && hits[1].prim == 1 && hits[1].t == 1.0f &&
             hits[2].prim == TT_INVALID_ID && occluded[0] && occluded[1] && !occluded[2];
    /* a bad ray is named by index */
    rays[1].tmin = -1.0f;
    ok = ok && tt_intersect(accel, rays, 3, hits, NULL, NULL) == TT_ERR_INVALID_ARGUMENT &&
         strstr(tt_context_last_error(ctx), "ray 1 of 3") != NULL;
    /* the installed library is the one whose header this was built with */
    ok = ok && strcmp(tt_version(), TT_VERSION_STRING) == 0;
    printf("treetrace %s (header %s): %s\n", tt_version(), TT_VERSION_STRING, ok ? "ok" : "WRONG");
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return ok ? 0 : 1;
}
