/* Helpers shared by the io tests: loading from strings, asserting on error
 * status and message content, and an allocator that counts, measures and can
 * fail on demand. */
#ifndef TT_TEST_IO_UTIL_H
#define TT_TEST_IO_UTIL_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

/* Loads a scene from a NUL-terminated string (format detected). */
static inline tt_status load_str(tt_context *ctx, const char *name, const char *text, tt_scene **out)
{
    return tt_scene_load_memory(ctx, name, NULL, text, strlen(text), out);
}

/* Checks that `st` is `want` and that the context's message contains every
 * one of the NULL-terminated needles. */
#define EXPECT_ERR(ctx, st, want, ...) expect_err_(__FILE__, __LINE__, ctx, st, want, __VA_ARGS__, (const char *)NULL)

static inline void expect_err_(const char *file, int line, tt_context *ctx, tt_status st,
                               tt_status want, ...)
{
    const char *msg = tt_context_last_error(ctx);
    int ok = st == want;
    va_list ap;
    va_start(ap, want);
    for (const char *n = va_arg(ap, const char *); n; n = va_arg(ap, const char *))
        if (!strstr(msg, n)) {
            ok = 0;
            fprintf(stderr, "%s:%d: message lacks \"%s\"\n", file, line, n);
        }
    va_end(ap);
    if (ok) {
        tt_test_passed++;
    } else {
        tt_test_failed++;
        fprintf(stderr, "%s:%d: expected %s, got %s: \"%s\"\n", file, line, tt_strerror(want),
                tt_strerror(st), msg);
    }
}

/* Loads text expecting failure; the scene pointer must come back NULL. */
#define EXPECT_LOAD_ERR(ctx, name, text, want, ...)                                          \
    do {                                                                                     \
        tt_scene *s_ = (tt_scene *)1;                                                        \
        tt_status st_ = load_str(ctx, name, text, &s_);                                      \
        CHECK(s_ == NULL);                                                                   \
        if (st_ == TT_OK) tt_scene_destroy(s_);                                              \
        EXPECT_ERR(ctx, st_, want, __VA_ARGS__);                                             \
    } while (0)

/* A growable byte buffer for writing test files. */
typedef struct buf {
    char *data;
    size_t size, cap;
} buf;

static inline void buf_put(buf *b, const void *p, size_t n)
{
    if (b->size + n > b->cap) {
        b->cap = (b->size + n) * 2 + 64;
        b->data = realloc(b->data, b->cap);
        if (!b->data) abort();
    }
    memcpy(b->data + b->size, p, n);
    b->size += n;
}

static inline void buf_printf(buf *b, const char *fmt, ...)
{
    char tmp[4096];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    buf_put(b, tmp, (size_t)n);
}

/* An allocator that tracks live blocks and bytes, the peak bytes, and fails
 * every allocation after `fail_after` successful ones (-1: never). Each
 * block carries a 16-byte header with its size. */
typedef struct counting_alloc {
    long live_blocks;
    size_t live_bytes, peak_bytes;
    long allocations, fail_after;
} counting_alloc;

static inline void *ca_alloc(void *user, size_t size)
{
    counting_alloc *a = user;
    if (a->fail_after >= 0 && a->allocations >= a->fail_after) return NULL;
    if (size > SIZE_MAX - 16) return NULL;
    unsigned char *p = malloc(size + 16);
    if (!p) return NULL;
    a->allocations++;
    memcpy(p, &size, sizeof size);
    a->live_blocks++;
    a->live_bytes += size;
    if (a->live_bytes > a->peak_bytes) a->peak_bytes = a->live_bytes;
    return p + 16;
}

static inline void ca_free(void *user, void *ptr)
{
    counting_alloc *a = user;
    if (!ptr) return;
    unsigned char *p = (unsigned char *)ptr - 16;
    size_t size;
    memcpy(&size, p, sizeof size);
    a->live_blocks--;
    a->live_bytes -= size;
    free(p);
}

static inline void *ca_realloc(void *user, void *ptr, size_t size)
{
    counting_alloc *a = user;
    if (!ptr) return ca_alloc(user, size);
    if (a->fail_after >= 0 && a->allocations >= a->fail_after) return NULL;
    void *q = ca_alloc(user, size);
    if (!q) return NULL;
    size_t old;
    memcpy(&old, (unsigned char *)ptr - 16, sizeof old);
    memcpy(q, ptr, old < size ? old : size);
    ca_free(user, ptr);
    return q;
}

static inline tt_context *counting_context(counting_alloc *a)
{
    memset(a, 0, sizeof *a);
    a->fail_after = -1;
    tt_context_options o;
    tt_context_options_default(&o);
    o.allocator.alloc = ca_alloc;
    o.allocator.realloc = ca_realloc;
    o.allocator.free = ca_free;
    o.allocator.user = a;
    tt_context *ctx = NULL;
    if (tt_context_create(&o, &ctx) != TT_OK) abort();
    return ctx;
}

/* Checks a scene's triangle i against nine expected floats, exactly. */
static inline int triangle_is(const tt_scene *s, size_t i, const float want[9])
{
    float t[9];
    if (tt_scene_triangle(s, i, t) != TT_OK) return 0;
    return memcmp(t, want, sizeof t) == 0;
}

#endif
