/* Steps shared by the commands: finding the bundled default scene, loading a
 * scene and building a structure with run-time errors reported, and the
 * process's peak memory. */
#ifndef TT_CLI_COMMON_H
#define TT_CLI_COMMON_H

#include <stddef.h>

#include "treetrace/treetrace.h"

/* The bundled data/bunny.ply: next to the executable (<exe dir>/../data,
 * e.g. build/../data) or in the source tree this binary was built from.
 * Returns 0 and fills buf, or -1 after printing where it looked. */
int cli_default_scene(const char *cmd, char *buf, size_t size);

/* views.tsv in the folder of the scene file. */
void cli_views_beside(const char *scene, char *buf, size_t size);

/* Prints "treetrace CMD: <the context's last error>" and returns CLI_RUNTIME. */
int cli_runtime_error(const char *cmd, const tt_context *ctx);

/* Loads the scene (timing it) and builds the structure; on failure prints
 * the library's error and returns CLI_RUNTIME with nothing left to free. */
int cli_load_and_build(const char *cmd, tt_context *ctx, const char *path,
                       const tt_build_options *build, tt_scene **scene, double *load_s,
                       tt_accel **accel);

/* Peak resident set size of this process in MiB (getrusage). */
double cli_peak_rss_mb(void);

#endif
