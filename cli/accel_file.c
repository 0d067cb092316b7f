#include "accel_file.h"

#include <string.h>

#include "args.h"
#include "cli.h"
#include "common.h"
#include "core/context.h" /* tt_now */

int cli_accel_file_check(const char *cmd, const char *file, const cli_accel_args *x)
{
    if (!file) return CLI_OK;
    const char *opt = x->accel ? "--accel"
                      : x->rtree_opt ? x->rtree_opt
                      : x->kd_opt ? x->kd_opt
                      : x->embree_opt ? x->embree_opt
                      : x->traversal ? "--traversal"
                      : x->m_given ? "--m"
                      : x->M_given ? "--M"
                                   : NULL;
    if (opt)
        return cli_usage_error(cmd,
                               "option %s cannot be combined with --accel-file %s: the file "
                               "fixes the structure and its options (only --isa may be given)",
                               opt, file);
    return CLI_OK;
}

int cli_load_and_get_accel(const char *cmd, tt_context *ctx, const char *scene_path,
                           const char *file, const tt_build_options *build, tt_scene **scene,
                           double *load_s, tt_accel **accel)
{
    if (!file) return cli_load_and_build(cmd, ctx, scene_path, build, scene, load_s, accel);
    *accel = NULL;
    *scene = NULL;
    double t0 = tt_now();
    if (tt_scene_load(ctx, scene_path, scene) != TT_OK) return cli_runtime_error(cmd, ctx);
    *load_s = tt_now() - t0;
    if (tt_accel_load(ctx, *scene, file, build->isa, accel) != TT_OK) {
        int st = cli_runtime_error(cmd, ctx);
        tt_scene_destroy(*scene);
        *scene = NULL;
        return st;
    }
    return CLI_OK;
}

void cli_accel_file_emit(cli_emit *e, const tt_accel *accel, const char *file,
                         const tt_build_options *given)
{
    if (!file) {
        cli_accel_args_emit(e, given);
        return;
    }
    tt_build_options saved;
    tt_accel_options(accel, &saved);
    cli_accel_args_emit(e, &saved);
    emit_str(e, "accel_file", file);
}
