/* `treetrace build`: builds a structure and saves it (tt_accel_save), for
 * `render --accel-file` / `info --accel-file` and tt_accel_load to map
 * instead of rebuilding. */
#include <string.h>
#include <sys/stat.h>

#include "accel_args.h"
#include "args.h"
#include "cli.h"
#include "common.h"
#include "core/context.h" /* tt_now */
#include "emit.h"

typedef struct build_args {
    const char *scene, *out;
    int json;
    cli_accel_args accel;
} build_args;

void cmd_build_help(FILE *out)
{
    fprintf(out,
            "usage: treetrace build SCENE -o FILE [options]\n"
            "\n"
            "Builds a structure on SCENE (OBJ or PLY) and saves it to FILE, which\n"
            "`treetrace render SCENE --accel-file FILE` (and info, and tt_accel_load)\n"
            "then maps instead of building again. The file is tied to the scene's\n"
            "triangles (a hash, checked on load) and to this library's layouts; the format\n"
            "is docs/accel-file.md. Every structure but embree can be saved.\n"
            "\n"
            "  -o, --output FILE        where to write the structure\n"
            "  --json                   one JSON object instead of `key: value` lines\n"
            "\n");
    cli_accel_args_help(out);
    fprintf(out,
            "\n"
            "example:\n"
            "  treetrace build ../shared/scenes/conference.ply -o conference.tta\n"
            "  treetrace render ../shared/scenes/conference.ply --accel-file conference.tta \\\n"
            "      --view conference:main --png conference.png\n");
}

static int parse(int argc, char **argv, build_args *r)
{
    memset(r, 0, sizeof *r);
    cli_accel_args_init(&r->accel);
    cli_args a = {"build", argc, argv, 1};
    for (; a.i < argc; a.i++) {
        const char *arg = argv[a.i];
        int taken, st = cli_accel_args_parse(&a, &r->accel, &taken);
        if (st != CLI_OK) return st;
        if (taken) continue;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) return -1;
        if (strcmp(arg, "--json") == 0) r->json = 1;
        else if (strcmp(arg, "-o") == 0 || cli_is(&a, "--output")) {
            const char *v = strcmp(arg, "-o") == 0
                                ? (a.i + 1 < argc ? argv[++a.i] : NULL)
                                : cli_value(&a, "--output");
            if (!v) return cli_usage_error("build", "option %s needs a FILE", arg);
            if (!*v) return cli_usage_error("build", "option %s: empty file name", arg);
            r->out = v;
        } else if ((st = cli_scene_arg(&a, &r->scene)) != CLI_OK)
            return st;
    }
    if (!r->scene) return cli_usage_error("build", "no SCENE given");
    if (!r->out) return cli_usage_error("build", "no output FILE given (-o FILE)");
    return cli_accel_args_finish("build", &r->accel);
}

int cmd_build(int argc, char **argv)
{
    build_args r;
    int st = parse(argc, argv, &r);
    if (st == -1) {
        cmd_build_help(stdout);
        return CLI_OK;
    }
    if (st != CLI_OK) return st;
    tt_context *ctx = NULL;
    if (tt_context_create(NULL, &ctx) != TT_OK) {
        fprintf(stderr, "treetrace build: cannot create a context\n");
        return CLI_RUNTIME;
    }
    tt_scene *scene = NULL;
    tt_accel *accel = NULL;
    double load_s = 0.0;
    st = cli_load_and_build("build", ctx, r.scene, &r.accel.build, &scene, &load_s, &accel);
    if (st != CLI_OK) {
        tt_context_destroy(ctx);
        return st;
    }
    double t0 = tt_now();
    if (tt_accel_save(accel, r.out, r.scene) != TT_OK) st = cli_runtime_error("build", ctx);
    double save_s = tt_now() - t0;
    if (st == CLI_OK) {
        struct stat sb;
        cli_emit e;
        emit_begin(&e, stdout, r.json);
        emit_str(&e, "scene", r.scene);
        emit_u64(&e, "triangles", tt_scene_triangle_count(scene));
        emit_num(&e, "load_s", load_s);
        emit_str(&e, "accel", tt_accel_name(accel));
        emit_str(&e, "isa", tt_isa_name(tt_accel_isa(accel)));
        cli_accel_args_emit(&e, &r.accel.build);
        emit_num(&e, "build_s", tt_accel_build_seconds(accel));
        emit_num(&e, "save_s", save_s);
        emit_str(&e, "file", r.out);
        emit_u64(&e, "file_bytes", stat(r.out, &sb) == 0 ? (uint64_t)sb.st_size : 0);
        emit_end(&e);
    }
    tt_accel_destroy(accel);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return st;
}
