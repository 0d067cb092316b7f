/* A changing scene: build once, then edit and update frame by frame.
 * Loads a model, builds the default R-tree, and for a few frames moves
 * every vertex (a wave), removes a few triangles and adds others; one
 * tt_accel_update a frame brings the structure up to date (in place for
 * the R-tree), and a ray is traced after each. Errors end the program with
 * the library's message. usage: example_dynamic MODEL */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <treetrace/treetrace.h>

static int fail(tt_context *ctx, const char *what)
{
    fprintf(stderr, "%s: %s\n", what, tt_context_last_error(ctx));
    return 1;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: example_dynamic MODEL\n");
        return 2;
    }
    tt_context *ctx;
    if (tt_context_create(NULL, &ctx) != TT_OK) return 1;
    tt_scene *scene;
    if (tt_scene_load(ctx, argv[1], &scene) != TT_OK) return fail(ctx, "load");
    tt_accel *accel;
    if (tt_accel_build(ctx, scene, NULL, &accel) != TT_OK) return fail(ctx, "build");
    printf("%s, updates %s\n", tt_accel_name(accel),
           tt_accel_updates_in_place(accel) ? "in place" : "by rebuilding");

    const size_t V = tt_scene_vertex_count(scene);
    float *rest = malloc(V * 3 * sizeof(float)), *pos = malloc(V * 3 * sizeof(float));
    if (!rest || !pos) return 1;
    for (size_t v = 0; v < V; v++) tt_scene_vertex(scene, v, rest + 3 * v);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    const float size = hi[0] - lo[0];
    tt_camera cam;
    tt_camera_frame_scene(scene, &cam);
    tt_ray ray;
    tt_camera_ray(&cam, 64, 64, 32, 32, &ray);

    for (int frame = 1; frame <= 5; frame++) {
        /* every vertex moves: triangles sharing it follow */
        for (size_t v = 0; v < V; v++) {
            pos[3 * v] = rest[3 * v] + 0.01f * size * sinf((float)frame + 20.0f * rest[3 * v + 1] / size);
            pos[3 * v + 1] = rest[3 * v + 1];
            pos[3 * v + 2] = rest[3 * v + 2];
        }
        if (tt_scene_move_vertices(scene, NULL, pos, V) != TT_OK) return fail(ctx, "move");
        /* a triangle removed by id, one added (it reuses the freed id) */
        uint32_t gone = (uint32_t)frame * 11u, added;
        if (tt_scene_remove_triangles(scene, &gone, 1) != TT_OK) return fail(ctx, "remove");
        float tri[9] = {lo[0], lo[1], lo[2], hi[0], lo[1], lo[2], lo[0], hi[1], lo[2]};
        if (tt_scene_add_triangles(scene, tri, 1, &added) != TT_OK) return fail(ctx, "add");
        /* until this call, tracing through accel fails with TT_ERR_STALE */
        if (tt_accel_update(accel) != TT_OK) return fail(ctx, "update");
        tt_hit hit;
        if (tt_intersect1(accel, &ray, &hit) != TT_OK) return fail(ctx, "trace");
        printf("frame %d: removed %u, added %u, centre ray hits %d at t = %g\n", frame, gone,
               added, hit.prim == TT_INVALID_ID ? -1 : (int)hit.prim, (double)hit.t);
    }
    /* a bad id is an error and changes nothing */
    uint32_t bad = (uint32_t)tt_scene_triangle_count(scene) + 5;
    if (tt_scene_remove_triangles(scene, &bad, 1) == TT_OK) return 1;
    printf("bad id refused: %s\n", tt_context_last_error(ctx));
    if (tt_accel_check(accel) != TT_OK) return fail(ctx, "check");
    free(rest);
    free(pos);
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return 0;
}
