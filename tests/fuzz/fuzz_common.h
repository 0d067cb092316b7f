/* Shared by the libFuzzer targets and by the replay of their regression
 * inputs (tests/hard/test_fuzz_regressions.c): a context whose allocator
 * enforces the "never allocate more than the input can justify" rule, and
 * the invariants every accepted input must satisfy. In a fuzzer a broken rule
 * abort()s, which libFuzzer reports as a crash, saving the input; the replay
 * defines FUZZ_FAILED to count the failure and go on with the next file. */
#ifndef TT_FUZZ_COMMON_H
#define TT_FUZZ_COMMON_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "treetrace/treetrace.h"

/* The most live bytes an input of n bytes may cost: a linear factor covers
 * the worst legal case (a binary face list of 1-byte indices gives one
 * triangle, 48 bytes of indices and vertex copies, per input byte, plus the
 * arrays' doubling slack), the constant covers the parsers' first reserves. */
#define FUZZ_BYTES_PER_INPUT_BYTE 128u
#define FUZZ_BASE_BYTES ((size_t)4 << 20)

/* The status of the last load or lookup (for the replay's expectations). */
static tt_status fuzz_last_status;

typedef struct fuzz_alloc {
    size_t live, peak, limit;
    long count;      /* successful allocations so far                      */
    long fail_at;    /* the allocation (1-based) that fails; 0: none       */
    int failed;      /* whether an injected failure happened              */
    int over_limit;  /* whether an allocation broke the bound (refused)    */
} fuzz_alloc;

#define FUZZ_HEADER 16

/* What to do after a broken rule has been printed; every function using it
 * returns void. */
#ifndef FUZZ_FAILED
#define FUZZ_FAILED() abort()
#define FUZZ_ABORT_OVER_LIMIT 1 /* the stack of the guilty allocation */
#endif
#ifndef FUZZ_PASSED
#define FUZZ_PASSED() ((void)0)
#endif

static inline void *fuzz_malloc(void *user, size_t size)
{
    fuzz_alloc *a = user;
    if (a->fail_at && a->count + 1 == a->fail_at) {
        a->failed = 1;
        a->fail_at = 0;
        return NULL;
    }
    if (size > a->limit || a->live + size > a->limit) {
        fprintf(stderr, "fuzz: allocation of %zu bytes with %zu live exceeds the %zu-byte bound for this input\n",
                size, a->live, a->limit);
        a->over_limit = 1;
#ifdef FUZZ_ABORT_OVER_LIMIT
        abort();
#endif
        return NULL;
    }
    unsigned char *p = malloc(size + FUZZ_HEADER);
    if (!p) return NULL;
    memcpy(p, &size, sizeof size);
    a->count++;
    a->live += size;
    if (a->live > a->peak) a->peak = a->live;
    return p + FUZZ_HEADER;
}

static inline void fuzz_free(void *user, void *ptr)
{
    fuzz_alloc *a = user;
    if (!ptr) return;
    unsigned char *p = (unsigned char *)ptr - FUZZ_HEADER;
    size_t size;
    memcpy(&size, p, sizeof size);
    a->live -= size;
    free(p);
}

static inline void *fuzz_realloc(void *user, void *ptr, size_t size)
{
    if (!ptr) return fuzz_malloc(user, size);
    void *q = fuzz_malloc(user, size);
    if (!q) return NULL;
    size_t old;
    memcpy(&old, (unsigned char *)ptr - FUZZ_HEADER, sizeof old);
    memcpy(q, ptr, old < size ? old : size);
    fuzz_free(user, ptr);
    return q;
}

static inline tt_context *fuzz_context(fuzz_alloc *a, size_t input_size, long fail_at)
{
    memset(a, 0, sizeof *a);
    a->limit = FUZZ_BASE_BYTES + FUZZ_BYTES_PER_INPUT_BYTE * input_size;
    a->fail_at = fail_at;
    tt_context_options o;
    tt_context_options_default(&o);
    o.allocator.alloc = fuzz_malloc;
    o.allocator.realloc = fuzz_realloc;
    o.allocator.free = fuzz_free;
    o.allocator.user = a;
    tt_context *ctx = NULL;
    if (tt_context_create(&o, &ctx) != TT_OK) abort();
    return ctx;
}

#define FUZZ_REQUIRE(cond, ...)                                                            \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "fuzz: invariant broken: %s: ", #cond);                        \
            fprintf(stderr, __VA_ARGS__);                                                  \
            fputc('\n', stderr);                                                           \
            FUZZ_FAILED();                                                                 \
        }                                                                                  \
        FUZZ_PASSED();                                                                     \
    } while (0)

/* What a loaded scene must satisfy: triangles and vertices, finite ordered
 * bounds, and every triangle's vertices finite and inside the bounds. */
static inline void fuzz_check_scene(const tt_scene *s)
{
    size_t nt = tt_scene_triangle_count(s), nv = tt_scene_vertex_count(s);
    FUZZ_REQUIRE(nt > 0 && nv > 0, "%zu triangles, %zu vertices", nt, nv);
    float lo[3], hi[3];
    tt_scene_bounds(s, lo, hi);
    for (int k = 0; k < 3; k++)
        FUZZ_REQUIRE(isfinite(lo[k]) && isfinite(hi[k]) && lo[k] <= hi[k], "axis %d: [%g, %g]", k,
                     lo[k], hi[k]);
    for (size_t i = 0; i < nt; i++) {
        float t[9];
        FUZZ_REQUIRE(tt_scene_triangle(s, i, t) == TT_OK, "triangle %zu", i);
        for (int k = 0; k < 9; k++)
            FUZZ_REQUIRE(isfinite(t[k]) && t[k] >= lo[k % 3] && t[k] <= hi[k % 3],
                         "triangle %zu value %d = %g outside the bounds", i, k, t[k]);
    }
}

/* Loads the input as `format`; on success checks the scene, on failure that
 * a message names the cause and no scene came back. Then, to exercise the
 * error paths with this input, loads it again with one allocation failing
 * (which one depends on the input): that must give TT_ERR_OUT_OF_MEMORY or
 * the same error as before. Leaks are LeakSanitizer's job; the allocator
 * checks that everything is freed by the end. */
static inline void fuzz_load(const char *format, const uint8_t *data, size_t size)
{
    fuzz_alloc a;
    tt_context *ctx = fuzz_context(&a, size, 0);
    tt_scene *s = (tt_scene *)&a;
    tt_status st = tt_scene_load_memory(ctx, "fuzz", format, data, size, &s);
    fuzz_last_status = st;
    FUZZ_REQUIRE(!a.over_limit, "the load allocated more than the input justifies");
    if (st == TT_OK) {
        FUZZ_REQUIRE(s != NULL, "TT_OK without a scene");
        fuzz_check_scene(s);
        tt_scene_destroy(s);
    } else {
        FUZZ_REQUIRE(s == NULL, "an error (%s) but a scene came back", tt_strerror(st));
        FUZZ_REQUIRE(st == TT_ERR_PARSE, "status %s: %s", tt_strerror(st), tt_context_last_error(ctx));
        FUZZ_REQUIRE(strstr(tt_context_last_error(ctx), "fuzz") != NULL,
                     "the message does not name the input: \"%s\"", tt_context_last_error(ctx));
    }
    long allocations = a.count;
    tt_context_destroy(ctx);
    FUZZ_REQUIRE(a.live == 0, "%zu bytes still allocated", a.live);
    if (allocations <= 1) return; /* only the context itself */

    uint32_t h = 2166136261u; /* FNV-1a: a fixed choice per input */
    for (size_t i = 0; i < size; i++) h = (h ^ data[i]) * 16777619u;
    long fail_at = 2 + (long)(h % (uint32_t)(allocations - 1)); /* not the context's */
    ctx = fuzz_context(&a, size, fail_at);
    s = NULL;
    tt_status st2 = tt_scene_load_memory(ctx, "fuzz", format, data, size, &s);
    if (a.failed) {
        FUZZ_REQUIRE(st2 == TT_ERR_OUT_OF_MEMORY && s == NULL,
                     "allocation %ld failed but the load returned %s", fail_at, tt_strerror(st2));
    } else {
        FUZZ_REQUIRE(st2 == st, "a second load of the same input gave %s, then %s", tt_strerror(st),
                     tt_strerror(st2));
        tt_scene_destroy(s);
    }
    tt_context_destroy(ctx);
    FUZZ_REQUIRE(a.live == 0, "%zu bytes still allocated after an injected failure", a.live);
}

/* The PLY fuzzer's format: "ply" for inputs starting so (even without the
 * newline detection wants), detection otherwise. */
static inline const char *fuzz_ply_format(const uint8_t *data, size_t size)
{
    return size >= 3 && memcmp(data, "ply", 3) == 0 ? "ply" : NULL;
}

/* ------------------------------------------------------------- views.tsv */

/* "scene:view" from the first two tab-separated fields of line 2, or "" */
static inline void fuzz_second_line_name(const uint8_t *data, size_t size, char *name, size_t cap)
{
    name[0] = '\0';
    const uint8_t *nl = memchr(data, '\n', size);
    if (!nl) return;
    const uint8_t *p = nl + 1, *end = data + size;
    const uint8_t *le = memchr(p, '\n', (size_t)(end - p));
    if (!le) le = end;
    const uint8_t *t1 = memchr(p, '\t', (size_t)(le - p));
    if (!t1) return;
    const uint8_t *t2 = memchr(t1 + 1, '\t', (size_t)(le - t1 - 1));
    if (!t2) return;
    size_t a = (size_t)(t1 - p), b = (size_t)(t2 - t1 - 1);
    if (a + b + 2 > cap) return;
    memcpy(name, p, a);
    name[a] = ':';
    memcpy(name + a + 1, t1 + 1, b);
    name[a + 1 + b] = '\0';
}

static inline void fuzz_check_camera(const tt_camera *c)
{
    for (int k = 0; k < 3; k++)
        FUZZ_REQUIRE(isfinite(c->eye[k]) && isfinite(c->look[k]) && isfinite(c->up[k]),
                     "component %d", k);
    FUZZ_REQUIRE(c->fov_deg > 0.0f && c->fov_deg < 180.0f, "fov %g", c->fov_deg);
    FUZZ_REQUIRE(c->has_light == 0 || c->has_light == 1, "has_light %d", c->has_light);
    if (c->has_light)
        for (int k = 0; k < 3; k++) FUZZ_REQUIRE(isfinite(c->light[k]), "light %d", k);
    static const uint32_t px[5][2] = {{0, 0}, {2, 0}, {0, 1}, {2, 1}, {1, 1}};
    for (int i = 0; i < 5; i++) {
        tt_ray r;
        FUZZ_REQUIRE(tt_camera_ray(c, 3, 2, px[i][0], px[i][1], &r) == TT_OK, "pixel %d", i);
        float len2 = 0.0f;
        for (int k = 0; k < 3; k++) {
            FUZZ_REQUIRE(isfinite(r.dir[k]), "pixel %d: direction %g %g %g", i, r.dir[0], r.dir[1],
                         r.dir[2]);
            len2 += r.dir[k] * r.dir[k];
        }
        FUZZ_REQUIRE(fabsf(len2 - 1.0f) < 1e-3f, "pixel %d: direction %g %g %g is not unit", i,
                     r.dir[0], r.dir[1], r.dir[2]);
    }
}

/* Looks `name` up in the input: an accepted view must be a usable camera
 * (finite values, fov in (0, 180), primary rays from tt_camera_ray with
 * finite unit directions), a refused one must have a message naming the
 * file. */
static inline void fuzz_find_view(const uint8_t *data, size_t size, const char *name)
{
    fuzz_alloc a;
    tt_context *ctx = fuzz_context(&a, size, 0);
    tt_camera cam;
    memset(&cam, 0xA5, sizeof cam);
    tt_status st = tt_view_find_memory(ctx, "fuzz.tsv", (const char *)data, size, name, &cam);
    fuzz_last_status = st;
    if (st == TT_OK) {
        fuzz_check_camera(&cam);
    } else {
        const char *msg = tt_context_last_error(ctx);
        FUZZ_REQUIRE(st == TT_ERR_PARSE || st == TT_ERR_INVALID_ARGUMENT, "status %s: %s",
                     tt_strerror(st), msg);
        FUZZ_REQUIRE(strstr(msg, "fuzz.tsv") != NULL, "the message does not name the file: \"%s\"",
                     msg);
    }
    tt_context_destroy(ctx);
    FUZZ_REQUIRE(a.live == 0, "%zu bytes still allocated", a.live);
}

/* Both lookups of the views fuzzer: the view named by line 2, then an
 * absent one. */
static inline void fuzz_views(const uint8_t *data, size_t size)
{
    char name[256];
    fuzz_second_line_name(data, size, name, sizeof name);
    if (name[0]) fuzz_find_view(data, size, name);
    fuzz_find_view(data, size, "no such scene:no such view");
}

#endif
