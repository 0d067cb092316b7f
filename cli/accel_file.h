/* Saved structures on the command line: `--accel-file FILE` (render, info)
 * takes the structure from a file written by `treetrace build` instead of
 * building it. The file fixes the structure and its options, so structure
 * options beside it are usage errors (--isa alone may choose the kernels). */
#ifndef TT_CLI_ACCEL_FILE_H
#define TT_CLI_ACCEL_FILE_H

#include "accel_args.h"
#include "emit.h"
#include "treetrace/treetrace.h"

/* Before cli_accel_args_finish: refuses structure options beside FILE. */
int cli_accel_file_check(const char *cmd, const char *file, const cli_accel_args *x);

/* Loads the scene (timing it) and then the structure from `file` (or builds
 * it when file is NULL, as cli_load_and_build); on failure prints the
 * library's error and returns CLI_RUNTIME with nothing left to free. */
int cli_load_and_get_accel(const char *cmd, tt_context *ctx, const char *scene_path,
                           const char *file, const tt_build_options *build, tt_scene **scene,
                           double *load_s, tt_accel **accel);

/* The structure's options as output keys (as saved, for a loaded one) and,
 * for a loaded one, accel_file and accel_load_s. */
void cli_accel_file_emit(cli_emit *e, const tt_accel *accel, const char *file,
                         const tt_build_options *given);

#endif
