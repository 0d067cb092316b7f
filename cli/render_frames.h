/* `render --frames N`: N frames of a camera orbit (frame k: the camera's
 * eye turned by 360 k / N degrees about the up axis through the look
 * point; frame 0 the camera itself), outputs named FILE_0000.png etc. One
 * process renders them all (render_frames_single), or MPI ranks share them
 * (cli/mpi/: frame k on rank k mod N); either way each frame's files are
 * the same bytes. */
#ifndef TT_CLI_RENDER_FRAMES_H
#define TT_CLI_RENDER_FRAMES_H

#include "render_args.h"

typedef struct frame_row {
    double trace_s, primary_hits, shadow_occluded, rank;
} frame_row;

/* Camera of frame k of n. */
void render_frame_camera(const tt_camera *base, int k, int n, tt_camera *out);
/* Renders frames first, first + step, ... (< r->frames) into rows[k] and
 * writes their files; returns CLI_OK or prints the error. */
int render_frames_run(tt_context *ctx, const render_args *r, const tt_scene *scene,
                      const tt_accel *accel, const tt_camera *base, int first, int step, int rank,
                      frame_row *rows);
/* Emits the per-frame table (rank 0 / the single process). */
void render_frames_emit(const render_args *r, const tt_accel *accel, const frame_row *rows,
                        double wall_s, int ranks);
/* The whole single-process run of `render --frames`. */
int render_frames_single(render_args *r);

#endif
