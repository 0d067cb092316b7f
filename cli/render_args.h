/* `treetrace render`'s parsed command line and the steps of cmd_render.c
 * that the MPI renderer (cli/mpi/) shares with it. */
#ifndef TT_CLI_RENDER_ARGS_H
#define TT_CLI_RENDER_ARGS_H

#include "accel_args.h"
#include "emit.h"
#include "treetrace/treetrace.h"

typedef struct render_args {
    const char *scene, *view, *views;
    float eye[3], look[3], up[3], light[3], fov;
    int has_eye, has_look, has_up, has_light, has_fov;
    uint32_t width, height;
    int threads, repeat, stats, no_shadows, json;
    const char *png, *hits, *heatmap;
    int heat_metric, heat_metric_given;
    int device; /* index into devices[] = tt_device */
    int packets; /* TT_PACKETS_* (cmd_render.c's packet_modes[]) */
    cli_accel_args accel;
    const char *accel_file; /* --accel-file: a saved structure (accel_file.h) */
    /* across MPI ranks (cli/mpi/): the tile split, given or the default
     * queue; frames of a camera orbit (0: one frame, the camera itself) */
    int mpi_split, mpi_split_given;
    int frames;
} render_args;

int render_make_camera(tt_context *ctx, const render_args *r, const tt_scene *scene,
                       tt_camera *cam);
int render_write_outputs(tt_context *ctx, const render_args *r, const tt_render_result *res);
/* Emits the results; `extra` (may be NULL) adds keys before the last one. */
typedef void (*render_emit_extra)(cli_emit *e, void *user);
void render_emit_results(const render_args *r, const char *scene_path, const tt_scene *scene,
                         double load_s, const tt_accel *accel, const tt_camera *cam,
                         const tt_render_result *res, render_emit_extra extra, void *user);

#endif
