/* `treetrace render`: load, build, trace K times, report timings and
 * counts, write the image, hit buffer and heatmap on request. */
#include <string.h>

#include "accel_args.h"
#include "accel_file.h"
#include "args.h"
#include "common.h"
#include "emit.h"
#include "mpi/mpi.h"
#include "render_args.h"
#include "render_frames.h"

#define MAX_SIZE 16384

static const char *const heat_metrics[] = {"nodes", "interior", "leaves", "triangles", "boxes"};
static const char *const devices[] = {"cpu", "gpu"};
/* indexed by TT_PACKETS_AUTO, _OFF, _ON */
static const char *const packet_modes[] = {"auto", "off", "on"};
static const char *const mpi_splits[] = {"queue", "interleave"};

void cmd_render_help(FILE *out)
{
    fprintf(out,
            "usage: treetrace render [SCENE] [options]\n"
            "\n"
            "Traces primary rays and shadow rays of every pixel and reports the timings.\n"
            "SCENE is an OBJ or PLY file; without it, the bundled data/bunny.ply.\n"
            "\n"
            "camera (default: framing the whole scene, light above left):\n"
            "  --view SCENE:VIEW        a view from views.tsv beside the scene file, e.g.\n"
            "                           conference:main\n"
            "  --views FILE             read --view from FILE instead\n"
            "  --eye x,y,z --look x,y,z an explicit camera (both needed)\n"
            "  --up x,y,z               up vector (default 0,1,0)\n"
            "  --fov DEG                vertical field of view in (0, 180) (default 45)\n"
            "  --light x,y,z            point light (an explicit camera has none unless given)\n"
            "\n"
            "tracing:\n"
            "  --size WxH               image size (default 1024x1024)\n"
            "  --threads N              OpenMP threads, 0 = OpenMP's default (default 0)\n"
            "  --repeat K               trace K times, report the minimum and the median\n"
            "  --stats                  one more pass counting nodes, leaves, boxes and\n"
            "                           triangles per ray (the timed passes never count)\n"
            "  --no-shadows             primary rays only\n"
            "  --packets auto|on|off    trace each tile's rays as one packet where the\n"
            "                           structure has packet traversal: auto (default) for\n"
            "                           primary rays and coherent shadow rays, on always,\n"
            "                           off never (ray by ray); the results are the same\n"
            "  --device cpu|gpu         where to trace (default cpu); the GPU (CUDA) traces\n"
            "                           rtree (auto, stackless, ordered) and kdtree (sltr,\n"
            "                           htr), reports upload_s and download_s apart and\n"
            "                           times the kernels with CUDA events\n"
            "\n"
            "output (results go to stdout as `key: value` lines):\n"
            "  --json                   one JSON object instead\n"
            "  --png FILE               the shaded image\n"
            "  --hits FILE              the hit buffer: 12 bytes a pixel, little-endian uint32\n"
            "                           triangle id (0xFFFFFFFF: miss), float32 t (+inf: miss),\n"
            "                           uint32 shadow flag\n"
            "  --heatmap FILE           per-pixel counts of the primary ray in false colour\n"
            "  --heatmap-metric NAME    nodes|interior|leaves|triangles|boxes (default nodes)\n"
            "\n");
    cli_accel_args_help(out);
    fprintf(out,
            "  --accel-file FILE        the structure saved by `treetrace build` (mapped, not\n"
            "                           built); it fixes the structure and its options\n"
            "\n"
            "several frames, several processes:\n"
            "  --frames N               N frames orbiting the look point about the up axis\n"
            "                           (frame 0: the camera); files FILE_0000.png ...\n"
            "  mpirun -np N treetrace render ...   (a build with MPI) every rank loads the\n"
            "                           scene and builds or maps (--accel-file) the structure;\n"
            "                           the frame's tiles are shared out, rank 0 gathers and\n"
            "                           writes the same image and hit buffer as one process;\n"
            "                           --frames N spreads whole frames over the ranks\n"
            "  --mpi-split queue|interleave   tiles by a queue on rank 0 (default) or\n"
            "                           every N-th tile per rank\n");
    fprintf(out,
            "\n"
            "examples:\n"
            "  treetrace render --size 512x512 --png bunny.png\n"
            "  treetrace render scenes/conference.ply --view conference:main --accel kdtree \\\n"
            "      --traversal sltr --repeat 5 --stats --json\n"
            "  treetrace render scene.obj --eye 0,1,5 --look 0,1,0 --light 2,4,3 --hits out.hits\n"
            "\n"
            "exit status: 0 success, 1 run-time error (unreadable scene ...), 2 usage error\n");
}

static int path_value(cli_args *a, const char *opt, const char **out)
{
    const char *v = cli_value(a, opt);
    if (!v) return CLI_USAGE;
    if (!*v) return cli_usage_error(a->cmd, "option %s: empty file name", opt);
    *out = v;
    return CLI_OK;
}

static int vec_value(cli_args *a, const char *opt, float out[3], int *given)
{
    const char *v = cli_value(a, opt);
    if (!v) return CLI_USAGE;
    *given = 1;
    return cli_parse_vec3(a->cmd, opt, v, out);
}

/* One option (or the scene); returns CLI_OK, CLI_USAGE, or -1 for --help. */
static int parse_one(cli_args *a, render_args *r)
{
    const char *arg = a->argv[a->i];
    const char *v;
    int taken, st = cli_accel_args_parse(a, &r->accel, &taken);
    if (st != CLI_OK || taken) return st;
    if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) return -1;
    if (strcmp(arg, "--stats") == 0) r->stats = 1;
    else if (strcmp(arg, "--no-shadows") == 0) r->no_shadows = 1;
    else if (strcmp(arg, "--json") == 0) r->json = 1;
    else if (cli_is(a, "--view")) return path_value(a, "--view", &r->view);
    else if (cli_is(a, "--views")) return path_value(a, "--views", &r->views);
    else if (cli_is(a, "--png")) return path_value(a, "--png", &r->png);
    else if (cli_is(a, "--accel-file")) return path_value(a, "--accel-file", &r->accel_file);
    else if (cli_is(a, "--mpi-split")) {
        r->mpi_split_given = 1;
        return (v = cli_value(a, "--mpi-split"))
                   ? cli_parse_choice(a->cmd, "--mpi-split", v, mpi_splits, 2, &r->mpi_split)
                   : CLI_USAGE;
    } else if (cli_is(a, "--frames")) {
        return (v = cli_value(a, "--frames")) ? cli_parse_int(a->cmd, "--frames", v, 1, 100000, &r->frames)
                                              : CLI_USAGE;
    }
    else if (cli_is(a, "--hits")) return path_value(a, "--hits", &r->hits);
    else if (cli_is(a, "--heatmap")) return path_value(a, "--heatmap", &r->heatmap);
    else if (cli_is(a, "--eye")) return vec_value(a, "--eye", r->eye, &r->has_eye);
    else if (cli_is(a, "--look")) return vec_value(a, "--look", r->look, &r->has_look);
    else if (cli_is(a, "--up")) return vec_value(a, "--up", r->up, &r->has_up);
    else if (cli_is(a, "--light")) return vec_value(a, "--light", r->light, &r->has_light);
    else if (cli_is(a, "--fov")) {
        r->has_fov = 1;
        return (v = cli_value(a, "--fov")) ? cli_parse_float(a->cmd, "--fov", v, 0.0, 1, 180.0, 1, &r->fov)
                                           : CLI_USAGE;
    } else if (cli_is(a, "--size")) {
        return (v = cli_value(a, "--size"))
                   ? cli_parse_size(a->cmd, "--size", v, MAX_SIZE, &r->width, &r->height)
                   : CLI_USAGE;
    } else if (cli_is(a, "--threads")) {
        return (v = cli_value(a, "--threads")) ? cli_parse_int(a->cmd, "--threads", v, 0, 1024, &r->threads)
                                               : CLI_USAGE;
    } else if (cli_is(a, "--repeat")) {
        return (v = cli_value(a, "--repeat")) ? cli_parse_int(a->cmd, "--repeat", v, 1, 100000, &r->repeat)
                                              : CLI_USAGE;
    } else if (cli_is(a, "--packets")) {
        return (v = cli_value(a, "--packets"))
                   ? cli_parse_choice(a->cmd, "--packets", v, packet_modes, 3, &r->packets)
                   : CLI_USAGE;
    } else if (cli_is(a, "--device")) {
        return (v = cli_value(a, "--device"))
                   ? cli_parse_choice(a->cmd, "--device", v, devices, 2, &r->device)
                   : CLI_USAGE;
    } else if (cli_is(a, "--heatmap-metric")) {
        r->heat_metric_given = 1;
        return (v = cli_value(a, "--heatmap-metric"))
                   ? cli_parse_choice(a->cmd, "--heatmap-metric", v, heat_metrics, 5, &r->heat_metric)
                   : CLI_USAGE;
    } else {
        return cli_scene_arg(a, &r->scene);
    }
    return CLI_OK;
}

/* Checks that need the whole command line. */
static int check_combination(render_args *r)
{
    const char *cmd = "render";
    if (r->view && (r->has_eye || r->has_look))
        return cli_usage_error(cmd, "--view %s cannot be combined with --eye/--look", r->view);
    if (r->has_eye != r->has_look)
        return cli_usage_error(cmd, "option %s needs %s too", r->has_eye ? "--eye" : "--look",
                               r->has_eye ? "--look" : "--eye");
    if (r->views && !r->view) return cli_usage_error(cmd, "option --views %s needs --view", r->views);
    if (r->heat_metric_given && !r->heatmap)
        return cli_usage_error(cmd, "option --heatmap-metric needs --heatmap FILE");
    if (r->has_eye && r->eye[0] == r->look[0] && r->eye[1] == r->look[1] && r->eye[2] == r->look[2])
        return cli_usage_error(cmd, "--eye and --look are the same point");
    if (r->has_up && r->up[0] == 0.0f && r->up[1] == 0.0f && r->up[2] == 0.0f)
        return cli_usage_error(cmd, "option --up: the zero vector has no direction");
    if (r->frames && (r->device != 0 || r->stats))
        return cli_usage_error(cmd, "option --frames renders on the CPU without --stats");
    int st = cli_accel_file_check(cmd, r->accel_file, &r->accel);
    if (st != CLI_OK) return st;
    return cli_accel_args_finish(cmd, &r->accel);
}

static int parse(int argc, char **argv, render_args *r)
{
    memset(r, 0, sizeof *r);
    r->width = r->height = 1024;
    r->repeat = 1;
    cli_accel_args_init(&r->accel);
    cli_args a = {"render", argc, argv, 1};
    for (; a.i < argc; a.i++) {
        int st = parse_one(&a, r);
        if (st != CLI_OK) return st;
    }
    return check_combination(r);
}

int render_make_camera(tt_context *ctx, const render_args *r, const tt_scene *scene,
                       tt_camera *cam)
{
    if (r->view) {
        char beside[4096];
        cli_views_beside(r->scene, beside, sizeof beside);
        if (tt_view_find(ctx, r->views ? r->views : beside, r->view, cam) != TT_OK)
            return cli_runtime_error("render", ctx);
    } else if (r->has_eye) {
        memset(cam, 0, sizeof *cam);
        memcpy(cam->eye, r->eye, sizeof cam->eye);
        memcpy(cam->look, r->look, sizeof cam->look);
        cam->up[1] = 1.0f;
        cam->fov_deg = 45.0f;
    } else {
        tt_camera_frame_scene(scene, cam);
    }
    if (r->has_up) memcpy(cam->up, r->up, sizeof cam->up);
    if (r->has_fov) cam->fov_deg = r->fov;
    if (r->has_light) {
        memcpy(cam->light, r->light, sizeof cam->light);
        cam->has_light = 1;
    }
    return CLI_OK;
}

int render_write_outputs(tt_context *ctx, const render_args *r, const tt_render_result *res)
{
    const tt_render_summary *s = tt_render_get_summary(res);
    size_t size;
    if (r->png && tt_write_png(ctx, r->png, tt_render_image(res), s->width, s->height) != TT_OK)
        return cli_runtime_error("render", ctx);
    const uint8_t *hits = tt_render_hits(res, &size);
    if (r->hits && tt_write_file(ctx, r->hits, hits, size) != TT_OK)
        return cli_runtime_error("render", ctx);
    if (r->heatmap &&
        tt_write_heatmap_png(ctx, r->heatmap,
                             tt_render_pixel_stats(res, (tt_heat_metric)r->heat_metric), s->width,
                             s->height) != TT_OK)
        return cli_runtime_error("render", ctx);
    return CLI_OK;
}

static double per_ray(uint64_t count, uint64_t rays) { return rays ? (double)count / (double)rays : 0.0; }

/* Why packets win or lose: how many, nodes a packet visits, rays active
 * at a visited node, rays finished one by one. */
static void emit_packets(cli_emit *e, const char *prefix, const tt_packet_counts *c)
{
    char key[64];
    snprintf(key, sizeof key, "%s_packets", prefix);
    emit_u64(e, key, c->packets);
    snprintf(key, sizeof key, "%s_nodes_per_packet", prefix);
    emit_num(e, key, per_ray(c->node_visits, c->packets));
    snprintf(key, sizeof key, "%s_active_rays_per_node", prefix);
    emit_num(e, key, per_ray(c->active_lanes, c->node_visits));
    snprintf(key, sizeof key, "%s_fallback_rays", prefix);
    emit_u64(e, key, c->fallback_rays);
}

static void emit_stats(cli_emit *e, const char *prefix, const tt_ray_stats *st)
{
    char key[64];
    struct { const char *name; uint64_t value; } fields[] = {
        {"nodes", st->nodes},   {"interior", st->interior},   {"leaves", st->leaves},
        {"boxes", st->boxes}, {"triangles", st->triangles},
    };
    for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++) {
        snprintf(key, sizeof key, "%s_%s_per_ray", prefix, fields[k].name);
        emit_num(e, key, per_ray(fields[k].value, st->rays));
    }
}

void render_emit_results(const render_args *r, const char *scene_path, const tt_scene *scene,
                         double load_s, const tt_accel *accel, const tt_camera *cam,
                         const tt_render_result *res, render_emit_extra extra, void *user)
{
    const tt_render_summary *s = tt_render_get_summary(res);
    cli_emit e;
    emit_begin(&e, stdout, r->json);
    emit_str(&e, "scene", scene_path);
    emit_u64(&e, "triangles", tt_scene_triangle_count(scene));
    emit_u64(&e, "vertices", tt_scene_vertex_count(scene));
    emit_num(&e, "load_s", load_s);
    emit_str(&e, "accel", tt_accel_name(accel));
    emit_str(&e, "isa", tt_isa_name(tt_accel_isa(accel)));
    cli_accel_file_emit(&e, accel, r->accel_file, &r->accel.build);
    emit_num(&e, r->accel_file ? "accel_load_s" : "build_s", tt_accel_build_seconds(accel));
    emit_u64(&e, "accel_bytes", tt_accel_memory_bytes(accel));
    emit_str(&e, "view", r->view ? r->view : (r->has_eye ? "explicit" : "framed"));
    emit_vec3(&e, "eye", cam->eye);
    emit_vec3(&e, "look", cam->look);
    emit_vec3(&e, "up", cam->up);
    emit_num(&e, "fov", cam->fov_deg);
    if (cam->has_light) emit_vec3(&e, "light", cam->light);
    else emit_str(&e, "light", "none");
    emit_str(&e, "device", devices[s->device]);
    if (s->device == TT_DEVICE_GPU) {
        emit_str(&e, "device_name", s->device_name);
        emit_num(&e, "upload_s", s->upload_s);
        emit_num(&e, "download_s", s->download_s);
    }
    emit_int(&e, "threads", s->threads);
    emit_u64(&e, "width", s->width);
    emit_u64(&e, "height", s->height);
    emit_int(&e, "repeat", r->repeat);
    emit_str(&e, "packets", s->packets ? packet_modes[r->packets] : "off");
    emit_bool(&e, "shadows", !r->no_shadows);
    emit_u64(&e, "primary_rays", s->primary_rays);
    emit_u64(&e, "primary_hits", s->primary_hits);
    emit_u64(&e, "shadow_rays", s->shadow_rays);
    emit_u64(&e, "shadow_occluded", s->shadow_occluded);
    emit_num(&e, "primary_s", s->primary_s);
    emit_num(&e, "shadow_s", s->shadow_s);
    emit_num(&e, "trace_s", s->trace_s);
    emit_num(&e, "trace_median_s", s->trace_median_s);
    emit_num(&e, "mrays_per_s", s->mrays_per_s);
    emit_num(&e, "primary_mrays_per_s", s->primary_mrays_per_s);
    emit_num(&e, "shadow_mrays_per_s", s->shadow_mrays_per_s);
    if (s->has_stats) {
        tt_ray_stats all = s->primary_stats;
        all.rays += s->shadow_stats.rays;
        all.nodes += s->shadow_stats.nodes;
        all.interior += s->shadow_stats.interior;
        all.leaves += s->shadow_stats.leaves;
        all.boxes += s->shadow_stats.boxes;
        all.triangles += s->shadow_stats.triangles;
        emit_stats(&e, "primary", &s->primary_stats);
        emit_stats(&e, "shadow", &s->shadow_stats);
        emit_stats(&e, "all", &all);
        if (s->packets) {
            emit_packets(&e, "primary", &s->primary_packets);
            emit_packets(&e, "shadow", &s->shadow_packets);
        }
    }
    if (r->png) emit_str(&e, "png", r->png);
    if (r->hits) emit_str(&e, "hits", r->hits);
    if (r->heatmap) {
        emit_str(&e, "heatmap", r->heatmap);
        emit_str(&e, "heatmap_metric", heat_metrics[r->heat_metric]);
    }
    if (extra) extra(&e, user);
    emit_num(&e, "peak_rss_mb", cli_peak_rss_mb());
    emit_end(&e);
}

int cmd_render(int argc, char **argv)
{
    render_args r;
    int st = parse(argc, argv, &r);
    if (st == -1) {
        cmd_render_help(stdout);
        return CLI_OK;
    }
    if (st != CLI_OK) return st;
    /* under mpirun (or with an MPI option) the MPI renderer (cli/mpi/) */
    char default_scene[4096];
    if (!r.scene) {
        if (cli_default_scene("render", default_scene, sizeof default_scene) != 0)
            return CLI_RUNTIME;
        r.scene = default_scene;
    }
    if (cli_mpi_wanted(r.mpi_split_given)) return cli_mpi_render(&r);
    if (r.frames > 0) return render_frames_single(&r);
    tt_context_options copt;
    tt_context_options_default(&copt);
    copt.threads = r.threads;
    tt_context *ctx = NULL;
    if (tt_context_create(&copt, &ctx) != TT_OK) {
        fprintf(stderr, "treetrace render: cannot create a context\n");
        return CLI_RUNTIME;
    }
    /* before loading and building: a missing GPU is known at once */
    if (tt_device_check(ctx, (tt_device)r.device) != TT_OK) {
        st = cli_runtime_error("render", ctx);
        tt_context_destroy(ctx);
        return st;
    }
    tt_scene *scene = NULL;
    tt_accel *accel = NULL;
    tt_render_result *res = NULL;
    double load_s = 0.0;
    tt_camera cam;
    st = cli_load_and_get_accel("render", ctx, r.scene, r.accel_file, &r.accel.build, &scene,
                                &load_s, &accel);
    if (st == CLI_OK) st = render_make_camera(ctx, &r, scene, &cam);
    if (st == CLI_OK) {
        tt_render_options ro;
        tt_render_options_default(&ro);
        ro.width = r.width;
        ro.height = r.height;
        ro.shadows = !r.no_shadows;
        ro.repeat = r.repeat;
        ro.stats = r.stats;
        ro.keep_hits = r.hits != NULL;
        ro.keep_image = r.png != NULL;
        ro.keep_pixel_stats = r.heatmap != NULL;
        ro.device = (tt_device)r.device;
        ro.packets = (uint32_t)r.packets;
        if (tt_render(ctx, scene, accel, &cam, &ro, &res) != TT_OK)
            st = cli_runtime_error("render", ctx);
    }
    if (st == CLI_OK) st = render_write_outputs(ctx, &r, res);
    if (st == CLI_OK) render_emit_results(&r, r.scene, scene, load_s, accel, &cam, res, NULL, NULL);
    tt_render_result_destroy(res);
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return st;
}
