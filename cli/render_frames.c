#include "render_frames.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accel_file.h"
#include "cli.h"
#include "common.h"
#include "core/context.h" /* tt_now */

void render_frame_camera(const tt_camera *base, int k, int n, tt_camera *out)
{
    *out = *base;
    if (k == 0) return;
    /* Rodrigues' rotation of eye - look about the unit up axis */
    double u[3] = {base->up[0], base->up[1], base->up[2]};
    double len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int i = 0; i < 3; i++) u[i] /= len;
    double v[3] = {base->eye[0] - base->look[0], base->eye[1] - base->look[1],
                   base->eye[2] - base->look[2]};
    double a = 2.0 * 3.14159265358979323846 * k / n, c = cos(a), s = sin(a);
    double d = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    for (int i = 0; i < 3; i++)
        out->eye[i] = (float)(base->look[i] + v[i] * c + x[i] * s + u[i] * d * (1.0 - c));
}

/* FILE.ext -> FILE_0007.ext */
static void frame_name(const char *path, int k, char *out, size_t size)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash)) dot = path + strlen(path);
    snprintf(out, size, "%.*s_%04d%s", (int)(dot - path), path, k, dot);
}

int render_frames_run(tt_context *ctx, const render_args *r, const tt_scene *scene,
                      const tt_accel *accel, const tt_camera *base, int first, int step, int rank,
                      frame_row *rows)
{
    for (int k = first; k < r->frames; k += step) {
        tt_camera cam;
        render_frame_camera(base, k, r->frames, &cam);
        tt_render_options ro;
        tt_render_options_default(&ro);
        ro.width = r->width;
        ro.height = r->height;
        ro.shadows = !r->no_shadows;
        ro.repeat = r->repeat;
        ro.keep_hits = r->hits != NULL;
        ro.keep_image = r->png != NULL;
        ro.keep_pixel_stats = r->heatmap != NULL;
        tt_render_result *res = NULL;
        if (tt_render(ctx, scene, accel, &cam, &ro, &res) != TT_OK) {
            fprintf(stderr, "treetrace render: frame %d: %s\n", k, tt_context_last_error(ctx));
            return CLI_RUNTIME;
        }
        render_args fr = *r;
        char png[4096], hits[4096], heat[4096];
        if (r->png) frame_name(r->png, k, png, sizeof png), fr.png = png;
        if (r->hits) frame_name(r->hits, k, hits, sizeof hits), fr.hits = hits;
        if (r->heatmap) frame_name(r->heatmap, k, heat, sizeof heat), fr.heatmap = heat;
        int st = render_write_outputs(ctx, &fr, res);
        const tt_render_summary *s = tt_render_get_summary(res);
        rows[k] = (frame_row){s->trace_s, (double)s->primary_hits, (double)s->shadow_occluded,
                              rank};
        tt_render_result_destroy(res);
        if (st != CLI_OK) return st;
    }
    return CLI_OK;
}

void render_frames_emit(const render_args *r, const tt_accel *accel, const frame_row *rows,
                        double wall_s, int ranks)
{
    cli_emit e;
    emit_begin(&e, stdout, r->json);
    emit_str(&e, "scene", r->scene);
    emit_str(&e, "accel", tt_accel_name(accel));
    cli_accel_file_emit(&e, accel, r->accel_file, &r->accel.build);
    emit_int(&e, "frames", r->frames);
    emit_int(&e, "ranks", ranks);
    emit_u64(&e, "width", r->width);
    emit_u64(&e, "height", r->height);
    emit_num(&e, "wall_s", wall_s);
    char key[64];
    for (int k = 0; k < r->frames; k++) {
        snprintf(key, sizeof key, "frame_%04d", k);
        emit_group_begin(&e, key);
        emit_int(&e, "rank", (int)rows[k].rank);
        emit_num(&e, "trace_s", rows[k].trace_s);
        emit_u64(&e, "primary_hits", (uint64_t)rows[k].primary_hits);
        emit_u64(&e, "shadow_occluded", (uint64_t)rows[k].shadow_occluded);
        emit_group_end(&e);
    }
    emit_end(&e);
}

int render_frames_single(render_args *r)
{
    tt_context_options copt;
    tt_context_options_default(&copt);
    copt.threads = r->threads;
    tt_context *ctx = NULL;
    if (tt_context_create(&copt, &ctx) != TT_OK) return CLI_RUNTIME;
    tt_scene *scene = NULL;
    tt_accel *accel = NULL;
    double load_s;
    tt_camera cam;
    int st = cli_load_and_get_accel("render", ctx, r->scene, r->accel_file, &r->accel.build,
                                    &scene, &load_s, &accel);
    if (st == CLI_OK) st = render_make_camera(ctx, r, scene, &cam);
    frame_row *rows = calloc((size_t)r->frames, sizeof *rows);
    double t0 = tt_now();
    if (st == CLI_OK && rows) st = render_frames_run(ctx, r, scene, accel, &cam, 0, 1, 0, rows);
    if (st == CLI_OK && rows) render_frames_emit(r, accel, rows, tt_now() - t0, 1);
    free(rows);
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return st;
}
