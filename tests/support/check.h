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

/* Ends the program as skipped (exit 77, ctest: skipped) saying why, unless a
 * check already failed: then it exits 1 (a skip never hides a failure). */
void tt_test_skip(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2), noreturn))
#endif
    ;

/* Whether this machine must trace on a GPU: /dev/nvidia0 exists or
 * TT_REQUIRE_GPU=1 is set. GPU tests then fail, instead of skipping, when
 * the GPU cannot be used (a driver mismatch must not stay green). */
int tt_test_gpu_required(void);
/* For a GPU test that found no usable GPU (st, why: tt_device_check's status
 * and message): fails the program when tt_test_gpu_required() (for a build
 * without CUDA, TT_ERR_UNSUPPORTED: only when TT_REQUIRE_GPU=1), else skips
 * saying why. */
void tt_test_no_gpu(tt_status st, const char *why)
#if defined(__GNUC__)
    __attribute__((noreturn))
#endif
    ;

/* Whether a test may run isa's kernels here (tt_isa_supported). A run ISA
 * is recorded and tt_test_finish prints the list ("ISAs compared: ...");
 * an ISA compiled into this binary that this CPU cannot run is announced
 * once ("SKIPPED: ... compiled in, this CPU cannot run it") and makes
 * tt_test_finish exit 77 (a visible skip) when nothing failed, so a CPU
 * without AVX2 or AVX-512 never shows a green "scalar against scalar".
 * TT_TEST_HIDE_ISAS=avx2,avx512 pretends this CPU lacks those. */
int tt_test_isa_runs(tt_isa isa);

/* Path of a shared scene file (TT_SCENES_DIR/file); when the shared folder is
 * absent, tt_test_skip()s saying so. */
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
/* The same with the kernels of `isa` (TT_ISA_AUTO: tt_test_build_default). */
tt_accel *tt_test_build_isa(tt_context *ctx, const tt_scene *scene, const char *name, tt_isa isa);

#endif
