/* The structure options shared by `render` and `info` (--accel and the
 * R-tree and kd-tree options), mapped onto tt_build_options. Options of a
 * structure other than the chosen one are errors, never silently ignored. */
#ifndef TT_CLI_ACCEL_ARGS_H
#define TT_CLI_ACCEL_ARGS_H

#include "args.h"
#include "emit.h"
#include "treetrace/treetrace.h"

typedef struct cli_accel_args {
    tt_build_options build;
    const char *accel;     /* as given; NULL: the default                      */
    const char *traversal; /* as given; resolved once the structure is known  */
    const char *rtree_opt; /* the first R-tree option given, for messages     */
    const char *rtree_opt_not_M; /* the first other than --M (wbvh takes --M)  */
    const char *kd_opt;    /* the first kd-tree option given                  */
    const char *embree_opt; /* the Embree option given                        */
    const char *insert_opt; /* the first insertion-only R-tree option given  */
    int m_given, M_given;
} cli_accel_args;

void cli_accel_args_init(cli_accel_args *x);
/* If the current argument is a structure option, parses it (and its value):
 * returns CLI_OK with *taken = 1, or CLI_USAGE. Otherwise *taken = 0. */
int cli_accel_args_parse(cli_args *a, cli_accel_args *x, int *taken);
/* Picks the default structure, checks the options against it and against
 * each other, and resolves --traversal. */
int cli_accel_args_finish(const char *cmd, cli_accel_args *x);
/* The chosen structure's build options, as output keys. */
void cli_accel_args_emit(cli_emit *e, const tt_build_options *b);
/* The options' help text. */
void cli_accel_args_help(FILE *out);

#endif
