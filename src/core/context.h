/* The context's internals, shared by every part of the library: allocation
 * through the user's hooks and error reporting with a formatted message. */
#ifndef TT_CORE_CONTEXT_H
#define TT_CORE_CONTEXT_H

#include <stdarg.h>
#include <stddef.h>

#include "treetrace/treetrace.h"

#define TT_ERROR_MAX 1024

struct tt_context {
    int threads;
    tt_allocator allocator;
    tt_error_fn on_error;
    void *on_error_user;
    char last_error[TT_ERROR_MAX];
};

#if defined(__GNUC__)
#define TT_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define TT_PRINTF(a, b)
#endif

/* Records the message on the context, calls the error hook and returns
 * status, so that callers can write `return tt_error(ctx, ...)`. */
tt_status tt_error(tt_context *ctx, tt_status status, const char *fmt, ...) TT_PRINTF(3, 4);
tt_status tt_verror(tt_context *ctx, tt_status status, const char *fmt, va_list ap);

/* Allocation through the context's hooks. NULL on failure (callers report
 * TT_ERR_OUT_OF_MEMORY). Sizes of zero allocate one byte so NULL always means
 * failure. tt_alloc_array checks count * size for overflow. */
void *tt_alloc(tt_context *ctx, size_t size);
void *tt_calloc(tt_context *ctx, size_t count, size_t size);
void *tt_alloc_array(tt_context *ctx, size_t count, size_t size);
void *tt_realloc(tt_context *ctx, void *ptr, size_t size);
void *tt_realloc_array(tt_context *ctx, void *ptr, size_t count, size_t size);
void tt_free(tt_context *ctx, void *ptr);

/* The threads a parallel region of this context runs: the context's
 * count (tt_context_options.threads), or OpenMP's default where it is 0. */
int tt_context_team(const tt_context *ctx);

/* Seconds on a monotonic clock. */
double tt_now(void);

#endif
