/* A minimal test harness: CHECK counts failures and reports file:line; every
 * test program ends with `return tt_test_finish();`, which prints the plain
 * "N passed, N failed" line and returns the exit status. */
#ifndef TT_TEST_CHECK_H
#define TT_TEST_CHECK_H

#include <stdio.h>
#include <stdlib.h>

#include "treetrace/treetrace.h"

extern int tt_test_passed, tt_test_failed;

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (cond) tt_test_passed++;                                                        \
        else {                                                                             \
            tt_test_failed++;                                                              \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);      \
        }                                                                                  \
    } while (0)

#define CHECK_MSG(cond, ...)                                                               \
    do {                                                                                   \
        if (cond) tt_test_passed++;                                                        \
        else {                                                                             \
            tt_test_failed++;                                                              \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);       \
            fprintf(stderr, __VA_ARGS__);                                                  \
            fputc('\n', stderr);                                                           \
        }                                                                                  \
    } while (0)

/* Checks a call returned TT_OK, printing the context's last error if not. */
#define CHECK_OK(ctx, expr)                                                                \
    do {                                                                                   \
        tt_status st_ = (expr);                                                            \
        CHECK_MSG(st_ == TT_OK, "%s: %s", tt_strerror(st_), tt_context_last_error(ctx));  \
    } while (0)

/* Aborts the test program (a failure) when a setup step fails. */
#define REQUIRE_OK(ctx, expr)                                                              \
    do {                                                                                   \
        tt_status st_ = (expr);                                                            \
        if (st_ != TT_OK) {                                                                \
            fprintf(stderr, "%s:%d: %s failed: %s: %s\n", __FILE__, __LINE__, #expr,       \
                    tt_strerror(st_), tt_context_last_error(ctx));                         \
            exit(1);                                                                       \
        }                                                                                  \
    } while (0)

int tt_test_finish(void);

/* A context that aborts the test on creation failure. */
tt_context *tt_test_context(void);

/* Path of a shared scene file (TT_SCENES_DIR/file); when the shared folder is
 * absent, prints why and exits 77 (ctest: skipped). */
const char *tt_test_scene_path(const char *file);
/* Loads a shared scene, skipping as above, failing the test on a load error. */
tt_scene *tt_test_load_scene(tt_context *ctx, const char *file);
/* Finds a view in the shared views.tsv ("bunny:main"). */
void tt_test_view(tt_context *ctx, const char *name, tt_camera *out);

/* Whether this build has the structure `name` (optional back ends such as
 * embree may be missing). */
int tt_test_has_accel(const char *name);
/* The structure's statistic `name` (tt_accel_statistics); -1 when absent. */
double tt_test_stat(const tt_accel *accel, const char *name);
/* Builds structure `name` with default options, failing the test on error. */
tt_accel *tt_test_build_default(tt_context *ctx, const tt_scene *scene, const char *name);

#endif
