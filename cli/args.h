/* Command-line parsing helpers. Every check that fails prints one message to
 * stderr naming the command, the option and the offending value, and returns
 * CLI_USAGE; success returns CLI_OK. Options take their value either as the
 * next argument (--size 64x64) or after '=' (--size=64x64). */
#ifndef TT_CLI_ARGS_H
#define TT_CLI_ARGS_H

#include <stdint.h>

#include "cli.h"

typedef struct cli_args {
    const char *cmd; /* for messages: "render"                              */
    int argc;
    char **argv;
    int i; /* the argument being parsed                                     */
} cli_args;

/* Prints "treetrace CMD: <message>" and a pointer to the help; returns CLI_USAGE. */
int cli_usage_error(const char *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Whether the current argument is option `name` (alone or as name=value). */
int cli_is(const cli_args *a, const char *name);
/* The current option's value (consuming the next argument if needed); NULL
 * after printing an error when there is none. */
const char *cli_value(cli_args *a, const char *name);

/* The current argument when no option took it: the one SCENE (into
 * *scene), or an error for an unknown option or a second scene. */
int cli_scene_arg(const cli_args *a, const char **scene);

/* Integers: decimal, the whole string, in [lo, hi]. */
int cli_parse_long(const char *cmd, const char *opt, const char *s, long lo, long hi, long *out);
int cli_parse_int(const char *cmd, const char *opt, const char *s, int lo, int hi, int *out);
/* A finite float in (lo, hi) or [lo, hi] by lo_open/hi_open. */
int cli_parse_float(const char *cmd, const char *opt, const char *s, double lo, int lo_open,
                    double hi, int hi_open, float *out);
/* "x,y,z", three finite floats. */
int cli_parse_vec3(const char *cmd, const char *opt, const char *s, float out[3]);
/* "WxH", each in [1, max]. */
int cli_parse_size(const char *cmd, const char *opt, const char *s, uint32_t max, uint32_t *w,
                   uint32_t *h);
/* One of names[0..count-1]; *out is its index. */
int cli_parse_choice(const char *cmd, const char *opt, const char *s, const char *const *names,
                     int count, int *out);

#endif
