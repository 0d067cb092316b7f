/* The usage example of include/treetrace/treetrace.h, as a program: the
 * tests build and run it (ctest examples/quickstart), so the header's
 * example cannot drift from the API. Usage: quickstart [SCENE]. */
#include <stdio.h>

#include "treetrace/treetrace.h"

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "data/bunny.ply";
    tt_context *ctx;
    if (tt_context_create(NULL, &ctx) != TT_OK) return 1;
    tt_scene *scene;
    if (tt_scene_load(ctx, path, &scene) != TT_OK) {
        fprintf(stderr, "%s\n", tt_context_last_error(ctx)); /* names file, line, cause */
        tt_context_destroy(ctx);
        return 1;
    }
    tt_build_options opt;
    tt_build_options_default(&opt); /* the R-tree engine: SAH bulk load, compact layout */
    opt.accel = "rtree";
    tt_accel *acc;
    if (tt_accel_build(ctx, scene, &opt, &acc) != TT_OK) {
        fprintf(stderr, "%s\n", tt_context_last_error(ctx));
        tt_scene_destroy(scene);
        tt_context_destroy(ctx);
        return 1;
    }
    /* a ray down the scene's vertical axis through the middle of its box */
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    tt_ray ray = {{(lo[0] + hi[0]) / 2, hi[1] + 1.0f, (lo[2] + hi[2]) / 2}, 0.0f,
                  {0.0f, -1.0f, 0.0f}, 1e30f};
    tt_hit hit;
    int occluded = 0;
    if (tt_intersect1(acc, &ray, &hit) != TT_OK || tt_occluded1(acc, &ray, &occluded) != TT_OK)
        return 1;
    printf("%s: %zu triangles, %s on %s; hit triangle %u at t = %g, occluded %d\n", path,
           tt_scene_triangle_count(scene), tt_accel_name(acc), tt_isa_name(tt_accel_isa(acc)),
           hit.prim, hit.t, occluded);
    /* the ray starts 1 above the box and ends below it: it must hit the
     * scene within the box (a structure that always misses fails here) */
    const int ok = hit.prim < tt_scene_triangle_count(scene) && occluded && hit.t >= 1.0f &&
                   hit.t <= hi[1] - lo[1] + 1.0f;
    tt_accel_destroy(acc);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return ok ? 0 : 1;
}
