#include "core/context.h"

#include <omp.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void *default_alloc(void *user, size_t size)
{
    (void)user;
    return malloc(size);
}

static void *default_realloc(void *user, void *ptr, size_t size)
{
    (void)user;
    return realloc(ptr, size);
}

static void default_free(void *user, void *ptr)
{
    (void)user;
    free(ptr);
}

const char *tt_version(void) { return TT_VERSION_STRING; }

const char *tt_strerror(tt_status status)
{
    switch (status) {
    case TT_OK: return "ok";
    case TT_ERR_INVALID_ARGUMENT: return "invalid argument";
    case TT_ERR_OUT_OF_MEMORY: return "out of memory";
    case TT_ERR_IO: return "input/output error";
    case TT_ERR_PARSE: return "malformed input";
    case TT_ERR_UNSUPPORTED: return "not supported by this build";
    case TT_ERR_NO_DEVICE: return "no usable device";
    case TT_ERR_INVARIANT: return "broken invariant";
    case TT_ERR_INTERNAL: return "internal error";
    case TT_ERR_BUSY: return "busy: an edit or update overlapped traces";
    case TT_ERR_STALE: return "structure out of date with its scene";
    }
    return "unknown status";
}

void tt_context_options_default(tt_context_options *options)
{
    memset(options, 0, sizeof *options);
}

tt_status tt_context_create(const tt_context_options *options, tt_context **out)
{
    if (!out) return TT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    tt_context_options opt;
    if (options) opt = *options;
    else tt_context_options_default(&opt);
    int hooks = (opt.allocator.alloc != NULL) + (opt.allocator.realloc != NULL) +
                (opt.allocator.free != NULL);
    if (hooks != 0 && hooks != 3) return TT_ERR_INVALID_ARGUMENT;
    if (opt.threads < 0) return TT_ERR_INVALID_ARGUMENT;
    if (hooks == 0) {
        opt.allocator.alloc = default_alloc;
        opt.allocator.realloc = default_realloc;
        opt.allocator.free = default_free;
        opt.allocator.user = NULL;
    }
    tt_context *ctx = opt.allocator.alloc(opt.allocator.user, sizeof *ctx);
    if (!ctx) return TT_ERR_OUT_OF_MEMORY;
    memset(ctx, 0, sizeof *ctx);
    ctx->threads = opt.threads;
    ctx->allocator = opt.allocator;
    ctx->on_error = opt.on_error;
    ctx->on_error_user = opt.on_error_user;
    *out = ctx;
    return TT_OK;
}

void tt_context_destroy(tt_context *ctx)
{
    if (!ctx) return;
    ctx->allocator.free(ctx->allocator.user, ctx);
}

const char *tt_context_last_error(const tt_context *ctx) { return ctx ? ctx->last_error : ""; }

int tt_context_threads(const tt_context *ctx) { return ctx ? ctx->threads : 0; }

int tt_context_team(const tt_context *ctx)
{
    const int t = tt_context_threads(ctx);
    return t > 0 ? t : omp_get_max_threads();
}

/* Errors may be reported from several threads at once (a trace refused on
 * each of them: TT_ERR_BUSY / TT_ERR_STALE): the message is formatted
 * apart, then stored and handed to the hook under one lock, so the last
 * error is always one whole message and hooks run one at a time. */
static atomic_flag error_lock = ATOMIC_FLAG_INIT;

tt_status tt_verror(tt_context *ctx, tt_status status, const char *fmt, va_list ap)
{
    if (!ctx) return status;
    char msg[TT_ERROR_MAX];
    vsnprintf(msg, sizeof msg, fmt, ap);
    while (atomic_flag_test_and_set_explicit(&error_lock, memory_order_acquire)) {
    }
    memcpy(ctx->last_error, msg, sizeof msg);
    if (ctx->on_error) ctx->on_error(ctx->on_error_user, status, ctx->last_error);
    atomic_flag_clear_explicit(&error_lock, memory_order_release);
    return status;
}

tt_status tt_error(tt_context *ctx, tt_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    tt_verror(ctx, status, fmt, ap);
    va_end(ap);
    return status;
}

void *tt_alloc(tt_context *ctx, size_t size)
{
    return ctx->allocator.alloc(ctx->allocator.user, size ? size : 1);
}

void *tt_calloc(tt_context *ctx, size_t count, size_t size)
{
    void *p = tt_alloc_array(ctx, count, size);
    if (p) memset(p, 0, count * size);
    return p;
}

void *tt_alloc_array(tt_context *ctx, size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) return NULL;
    return tt_alloc(ctx, count * size);
}

void *tt_realloc(tt_context *ctx, void *ptr, size_t size)
{
    return ctx->allocator.realloc(ctx->allocator.user, ptr, size ? size : 1);
}

void *tt_realloc_array(tt_context *ctx, void *ptr, size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) return NULL;
    return tt_realloc(ctx, ptr, count * size);
}

void tt_free(tt_context *ctx, void *ptr)
{
    if (ptr) ctx->allocator.free(ctx->allocator.user, ptr);
}

double tt_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
