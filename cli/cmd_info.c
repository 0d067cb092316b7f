/* `treetrace info`: what a scene is and what a structure built on it looks
 * like (every statistic the structure reports), plus its invariant check. */
#include <string.h>

#include "accel_args.h"
#include "accel_file.h"
#include "args.h"
#include "common.h"
#include "emit.h"

typedef struct info_args {
    const char *scene;
    int json;
    cli_accel_args accel;
    const char *accel_file; /* --accel-file: a saved structure */
} info_args;

void cmd_info_help(FILE *out)
{
    fprintf(out,
            "usage: treetrace info SCENE [options]\n"
            "\n"
            "Loads SCENE (OBJ or PLY), builds a structure on it and prints the counts, the\n"
            "bounding box, load and build times, memory, every statistic of the structure\n"
            "(under statistics.) and the result of its invariant check. Exits 1 if the\n"
            "check fails.\n"
            "\n"
            "  --json                   one JSON object instead of `key: value` lines\n"
            "  --accel-file FILE        the structure saved by `treetrace build` instead of\n"
            "                           a build (its statistics as saved, checked here)\n"
            "\n");
    cli_accel_args_help(out);
    fprintf(out,
            "\n"
            "example:\n"
            "  treetrace info scenes/sibenik.obj --accel rtree --strategy rstar --M 8 --m 3\n");
}

static int parse(int argc, char **argv, info_args *r)
{
    memset(r, 0, sizeof *r);
    cli_accel_args_init(&r->accel);
    cli_args a = {"info", argc, argv, 1};
    for (; a.i < argc; a.i++) {
        const char *arg = argv[a.i];
        int taken, st = cli_accel_args_parse(&a, &r->accel, &taken);
        if (st != CLI_OK) return st;
        if (taken) continue;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) return -1;
        if (strcmp(arg, "--json") == 0) r->json = 1;
        else if (cli_is(&a, "--accel-file")) {
            if (!(r->accel_file = cli_value(&a, "--accel-file"))) return CLI_USAGE;
        } else if ((st = cli_scene_arg(&a, &r->scene)) != CLI_OK)
            return st;
    }
    if (!r->scene) return cli_usage_error("info", "no SCENE given");
    int st = cli_accel_file_check("info", r->accel_file, &r->accel);
    if (st != CLI_OK) return st;
    return cli_accel_args_finish("info", &r->accel);
}

static void emit_stat(void *user, const char *key, double value)
{
    emit_num(user, key, value);
}

int cmd_info(int argc, char **argv)
{
    info_args r;
    int st = parse(argc, argv, &r);
    if (st == -1) {
        cmd_info_help(stdout);
        return CLI_OK;
    }
    if (st != CLI_OK) return st;
    tt_context *ctx = NULL;
    if (tt_context_create(NULL, &ctx) != TT_OK) {
        fprintf(stderr, "treetrace info: cannot create a context\n");
        return CLI_RUNTIME;
    }
    tt_scene *scene = NULL;
    tt_accel *accel = NULL;
    double load_s = 0.0;
    st = cli_load_and_get_accel("info", ctx, r.scene, r.accel_file, &r.accel.build, &scene,
                                &load_s, &accel);
    if (st != CLI_OK) {
        tt_context_destroy(ctx);
        return st;
    }
    tt_status check = tt_accel_check(accel);
    char check_error[1024] = "";
    if (check != TT_OK) snprintf(check_error, sizeof check_error, "%s", tt_context_last_error(ctx));

    size_t tris = tt_scene_triangle_count(scene), verts = tt_scene_vertex_count(scene);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    cli_emit e;
    emit_begin(&e, stdout, r.json);
    emit_str(&e, "scene", r.scene);
    emit_u64(&e, "triangles", tris);
    emit_u64(&e, "vertices", verts);
    emit_vec3(&e, "bbox_min", lo);
    emit_vec3(&e, "bbox_max", hi);
    /* vertices, index triples and the flat 9-float copy of every triangle */
    emit_u64(&e, "scene_bytes", verts * 12 + tris * 12 + tris * 36);
    emit_num(&e, "load_s", load_s);
    emit_str(&e, "accel", tt_accel_name(accel));
    emit_str(&e, "isa", tt_isa_name(tt_accel_isa(accel)));
    cli_accel_file_emit(&e, accel, r.accel_file, &r.accel.build);
    emit_num(&e, r.accel_file ? "accel_load_s" : "build_s", tt_accel_build_seconds(accel));
    emit_u64(&e, "accel_bytes", tt_accel_memory_bytes(accel));
    /* how tt_accel_update answers a scene edit (dynamic scenes) */
    emit_str(&e, "update", tt_accel_updates_in_place(accel) ? "in place" : "rebuild");
    emit_group_begin(&e, "statistics");
    tt_accel_statistics(accel, emit_stat, &e);
    emit_group_end(&e);
    emit_str(&e, "check", check == TT_OK ? "ok" : "failed");
    if (check != TT_OK) emit_str(&e, "check_error", check_error);
    emit_num(&e, "peak_rss_mb", cli_peak_rss_mb());
    emit_end(&e);
    if (check != TT_OK) {
        fprintf(stderr, "treetrace info: check failed: %s\n", check_error);
        st = CLI_RUNTIME;
    }
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return st;
}
