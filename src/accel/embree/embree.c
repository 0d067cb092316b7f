/* The "embree" structure: Intel Embree 3 as the reference ray tracer of the
 * benchmark. One RTCDevice and one RTCScene per structure, holding a single
 * triangle geometry built from the scene's vertices and indices, traced with
 * single-ray queries (rtcIntersect1 / rtcOccluded1) because our structures
 * are compared per ray as well.
 *
 * Intervals. Our rays cover [tmin, tmax) with 0 <= tmin (the tt_ray
 * contract, enforced by accel.c's prepare; Embree's traversal asserts
 * tnear >= 0 too). Embree's own interval ends differ by ISA (robust mode
 * was closed at both ends on AVX-512 and missed t = tnear on AVX2), so it is
 * asked over a slightly wider interval and embree_filter keeps only the
 * triangles our watertight test accepts on [tmin, tmax): the ends are ours
 * exactly. Embree decides which triangles to offer its own way (a Pluecker
 * test with a one-ulp tolerance on the edges), so a hit near a silhouette
 * edge may still be decided differently; that is the only inexactness left,
 * and why the hard tests (tests/hard) hold Embree to exact agreement on generic rays
 * only. The t, u, v of a closest hit are our own (see embree_intersect).
 *
 * Legal rays Embree cannot take. Embree asserts (and the packaged library
 * aborts the process on) origin or direction components beyond 1.844e18;
 * tiny directions make its box tests disagree with its triangle test. The
 * library must never abort, so to_rtc_ray rescales such directions by a
 * power of two (exact) and answers rays whose origin is beyond Embree's
 * range with the bruteforce template instead.
 *
 * A known Embree limitation (shared by any slab test that uses a finite
 * stand-in for 1/0): a ray with a zero direction component lying exactly in
 * the plane of a box's upper face gets the slab [-big, 0] on that axis and
 * is culled, so Embree misses triangles lying in that face for such rays.
 *
 * Statistics. Embree's internals (nodes, boxes, triangle tests) cannot be
 * counted from outside, so the counting variants count rays only and every
 * other field stays 0. The memory is what Embree allocates, observed through
 * the device's memory monitor: its BVH plus its own copy of the vertices and
 * indices (Embree needs padded buffers, so it cannot share the scene's). */
#include <embree3/rtcore.h>
#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

#include "accel/accel.h"
#include "geometry/triangle.h"

/* The bruteforce template (fast variant only) answers the few rays Embree
 * cannot take (see to_rtc_ray). */
#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/bruteforce/bruteforce_trace.h"

#define EMBREE_MESSAGE_MAX 512

typedef struct embree_impl {
    RTCDevice device;
    RTCScene scene;
    int has_geometry;         /* 0 for an empty scene: nothing attached      */
    int committed;            /* rtcCommitScene returned without an error    */
    atomic_llong bytes;       /* live bytes, from the memory monitor         */
    atomic_llong peak_bytes;  /* the most live bytes seen (during the build) */
    long long geometry_bytes; /* live bytes after the buffers, before the BVH */
    /* The first error Embree reported; the callback may run on Embree's
     * build threads, so it only claims the slot once (atomic flag). */
    atomic_int error_claimed;
    int error_code;
    char error[EMBREE_MESSAGE_MAX];
} embree_impl;

static const char *rtc_error_name(enum RTCError code)
{
    switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    }
    return "unrecognised error";
}

static void on_rtc_error(void *user, enum RTCError code, const char *message)
{
    embree_impl *e = user;
    if (atomic_exchange(&e->error_claimed, 1)) return;
    e->error_code = (int)code;
    snprintf(e->error, sizeof e->error, "%s%s%s", rtc_error_name(code), message ? ": " : "",
             message ? message : "");
}

static bool on_rtc_memory(void *user, ssize_t bytes, bool post)
{
    embree_impl *e = user;
    (void)post; /* counted once, before the allocation (post is for frees) */
    long long now = atomic_fetch_add(&e->bytes, (long long)bytes) + (long long)bytes;
    long long peak = atomic_load(&e->peak_bytes);
    while (now > peak && !atomic_compare_exchange_weak(&e->peak_bytes, &peak, now)) {
    }
    return true; /* never veto an allocation: Embree would report it as an error */
}

/* Turns the first recorded Embree error (if any) into a tt_error. */
static tt_status embree_failed(tt_accel *a, const char *step)
{
    embree_impl *e = a->impl;
    if (e && atomic_load(&e->error_claimed)) {
        tt_status st = e->error_code == RTC_ERROR_OUT_OF_MEMORY ? TT_ERR_OUT_OF_MEMORY
                                                                : TT_ERR_INTERNAL;
        return tt_error(a->ctx, st, "embree: %s failed: %s", step, e->error);
    }
    return TT_OK;
}

/* (below: the filter that holds Embree to our interval ends) */
static void embree_filter(const struct RTCFilterFunctionNArguments *args);

static tt_status embree_build(tt_accel *a)
{
    const tt_scene *s = a->scene;
    if (s->triangle_count > UINT32_MAX - 1 || s->vertex_count > UINT32_MAX)
        return tt_error(a->ctx, TT_ERR_INVALID_ARGUMENT,
                        "embree: %zu triangles / %zu vertices exceed Embree's 32-bit ids",
                        s->triangle_count, s->vertex_count);
    embree_impl *e = tt_calloc(a->ctx, 1, sizeof *e);
    if (!e) return tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY, "embree: out of memory");
    a->impl = e;
    atomic_init(&e->bytes, 0);
    atomic_init(&e->peak_bytes, 0);
    atomic_init(&e->error_claimed, 0);

    /* Embree builds with its own (TBB) threads; honour the context's count. */
    char config[64] = "verbose=0";
    int threads = tt_context_threads(a->ctx);
    if (threads > 0) snprintf(config, sizeof config, "verbose=0,threads=%d", threads);
    e->device = rtcNewDevice(config);
    if (!e->device)
        return tt_error(a->ctx, TT_ERR_INTERNAL, "embree: rtcNewDevice(\"%s\") failed: %s",
                        config, rtc_error_name(rtcGetDeviceError(NULL)));
    rtcSetDeviceErrorFunction(e->device, on_rtc_error, e);
    rtcSetDeviceMemoryMonitorFunction(e->device, on_rtc_memory, e);

    e->scene = rtcNewScene(e->device);
    tt_status st = embree_failed(a, "rtcNewScene");
    if (st != TT_OK) return st;
    /* ROBUST: conservative box tests and the watertight Pluecker triangle
     * test, the closest Embree gets to our watertight test (see the top). */
    rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
    const tt_embree_quality q = a->options.embree.quality;
    if ((unsigned)q > (unsigned)TT_EMBREE_LOW)
        return tt_error(a->ctx, TT_ERR_INVALID_ARGUMENT, "embree: unknown build quality %d",
                        (int)q);
    const enum RTCBuildQuality quality = q == TT_EMBREE_LOW      ? RTC_BUILD_QUALITY_LOW
                                         : q == TT_EMBREE_MEDIUM ? RTC_BUILD_QUALITY_MEDIUM
                                                                 : RTC_BUILD_QUALITY_HIGH;
    rtcSetSceneBuildQuality(e->scene, quality);

    if (s->triangle_count > 0) {
        RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if ((st = embree_failed(a, "rtcNewGeometry")) != TT_OK) {
            if (g) rtcReleaseGeometry(g);
            return st;
        }
        rtcSetGeometryBuildQuality(g, quality);
        float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                           3 * sizeof(float), s->vertex_count);
        uint32_t *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                3 * sizeof(uint32_t), s->triangle_count);
        if ((st = embree_failed(a, "rtcSetNewGeometryBuffer")) != TT_OK || !v || !idx) {
            rtcReleaseGeometry(g);
            return st != TT_OK ? st
                               : tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY,
                                          "embree: no geometry buffers for %zu triangles",
                                          s->triangle_count);
        }
        memcpy(v, s->vertices, s->vertex_count * 3 * sizeof(float));
        memcpy(idx, s->indices, s->triangle_count * 3 * sizeof(uint32_t));
        rtcSetGeometryIntersectFilterFunction(g, embree_filter);
        rtcSetGeometryOccludedFilterFunction(g, embree_filter);
        rtcCommitGeometry(g);
        unsigned id = rtcAttachGeometry(e->scene, g);
        rtcReleaseGeometry(g); /* the scene holds its own reference */
        if ((st = embree_failed(a, "attaching the triangle geometry")) != TT_OK) return st;
        if (id != 0)
            return tt_error(a->ctx, TT_ERR_INTERNAL, "embree: geometry id %u, expected 0", id);
        e->has_geometry = 1;
    }
    e->geometry_bytes = atomic_load(&e->bytes);
    rtcCommitScene(e->scene);
    if ((st = embree_failed(a, "rtcCommitScene")) != TT_OK) return st;
    e->committed = 1;
    return TT_OK;
}

static void embree_destroy(tt_accel *a)
{
    embree_impl *e = a->impl;
    if (!e) return;
    if (e->scene) rtcReleaseScene(e->scene);
    if (e->device) rtcReleaseDevice(e->device);
    tt_free(a->ctx, e);
    a->impl = NULL;
}

/* Embree's ray.valid(), asserted by its traversal (and the Debian build
 * keeps the assertions, so a failing one aborts the whole process): every
 * origin and direction component at most FLT_LARGE = 1.844e18 in
 * magnitude. Origins are kept a little inside that. */
#define EMBREE_ORG_LIMIT 1.0e18f
/* Directions whose largest component lies in [2^-20, 2^20] are passed as
 * they are (the common case: the exact ray the caller gave). Outside it, a
 * huge component breaks valid() and a tiny direction makes Embree's safe
 * reciprocals (clamped for tiny inputs) inconsistent with the triangle test,
 * so the direction is rescaled by a power of two to a largest component in
 * [1, 2). */
#define EMBREE_DIR_LO 0x1p-20f
#define EMBREE_DIR_HI 0x1p20f

typedef enum rtc_ray_kind {
    RTC_RAY_EMPTY,      /* [tmin, tmax) is empty: a miss, Embree not asked   */
    RTC_RAY_READY,      /* *out is the ray, exactly                          */
    RTC_RAY_BRUTEFORCE, /* Embree cannot take it exactly: answer without it */
} rtc_ray_kind;

/* Fills Embree's ray from ours. The tt_ray contract (accel.c's prepare)
 * guarantees 0 <= tmin and no NaN. *scale_exp is e such that our t is
 * ldexpf(Embree's t, e): a direction scaled by 2^-e reaches the same points
 * at t * 2^-e, and both scalings are exact in binary floating point as long
 * as nothing overflows or becomes subnormal, which is checked by scaling
 * back: a ray where that fails, or whose origin is beyond Embree's range, is
 * not given to Embree at all. */
static rtc_ray_kind to_rtc_ray(const tt_wray *r, struct RTCRay *out, int *scale_exp)
{
    float tmin = r->tmin, tmax = r->tmax;
    if (!(tmin < tmax)) return RTC_RAY_EMPTY;
    float m = 0.0f;
    for (int k = 0; k < 3; k++) {
        if (!(fabsf(r->org[k]) <= EMBREE_ORG_LIMIT)) return RTC_RAY_BRUTEFORCE;
        m = fmaxf(m, fabsf(r->dir[k]));
    }
    float dir[3] = {r->dir[0], r->dir[1], r->dir[2]};
    int e = 0;
    if (!(m >= EMBREE_DIR_LO && m <= EMBREE_DIR_HI)) {
        /* m = 2^e * [1, 2) (m > 0: prepare refused zero directions); the
         * direction becomes dir * 2^-e, t becomes t * 2^e */
        e = ilogbf(m);
        for (int k = 0; k < 3; k++) {
            dir[k] = ldexpf(r->dir[k], -e);
            if (ldexpf(dir[k], e) != r->dir[k]) return RTC_RAY_BRUTEFORCE;
        }
        float lo = ldexpf(tmin, e), hi = ldexpf(tmax, e); /* inf stays inf */
        if (ldexpf(lo, -e) != tmin || ldexpf(hi, -e) != tmax) return RTC_RAY_BRUTEFORCE;
        tmin = lo;
        tmax = hi;
    }
    *scale_exp = -e;
    out->org_x = r->org[0];
    out->org_y = r->org[1];
    out->org_z = r->org[2];
    out->dir_x = dir[0];
    out->dir_y = dir[1];
    out->dir_z = dir[2];
    /* a little wider than [tmin, tmax): embree_filter cuts it to ours */
    const float lo = tmin - fabsf(tmin) * 0x1p-16f;
    out->tnear = lo > 0.0f ? lo : 0.0f;
    /* An open-ended ray still ends where our t overflows: the watertight
     * test (every other structure) cannot return a hit beyond FLT_MAX, and a
     * tiny direction may reach the scene only there. For a direction scaled
     * down (e > 0) that bound is inf again. */
    out->tfar = isinf(tmax) ? ldexpf(FLT_MAX, e) : tmax + fabsf(tmax) * 0x1p-16f;
    out->time = 0.0f;
    out->mask = 0xFFFFFFFFu;
    out->id = 0;
    out->flags = 0;
    return RTC_RAY_READY;
}

/* Embree's triangle test is tolerant and its interval ends are not the same
 * on every ISA (on an AVX2 CPU a hit at exactly tmin was missed and one at
 * tmax taken, in robust mode). So Embree is asked over an interval a little
 * wider than ours, and every triangle it accepts passes this filter only
 * when the project's watertight test accepts it for our ray on [tmin,
 * tmax): the interval's ends are then ours exactly, on every ISA. The ray
 * travels in a context that begins with Embree's own. */
typedef struct embree_ctx {
    struct RTCIntersectContext ic;
    const tt_wray *ray;
    const float *tri;
} embree_ctx;

static void embree_filter(const struct RTCFilterFunctionNArguments *args)
{
    const embree_ctx *c = (const embree_ctx *)args->context;
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] != -1) continue;
        /* RTCHitN is N-wide rows: Ng x, y, z, u, v, then primID (the C
         * header has no accessor) */
        const uint32_t prim = ((const uint32_t *)args->hit)[5 * args->N + i];
        const float *p = c->tri + 9 * (size_t)prim;
        float t, u, v;
        if (!tt_intersect_triangle(c->ray, p, p + 3, p + 6, c->ray->tmax, &t, &u, &v))
            args->valid[i] = 0;
    }
}

static void embree_context(embree_ctx *c, const tt_accel *a, const tt_wray *r)
{
    rtcInitIntersectContext(&c->ic);
    c->ray = r;
    c->tri = a->scene->tri;
}

static void embree_intersect(const tt_accel *a, const tt_wray *r, tt_hit *hit,
                             tt_trace_args *args)
{
    const embree_impl *e = a->impl;
    (void)args;
    tt_hit_clear(hit);
    if (!e->has_geometry) return;
    struct RTCRayHit rh;
    int scale_exp = 0;
    switch (to_rtc_ray(r, &rh.ray, &scale_exp)) {
    case RTC_RAY_EMPTY: return;
    case RTC_RAY_BRUTEFORCE:
        /* Origins beyond 1e18 (or directions that no power of two brings
         * into range exactly): Embree would abort on them, so these rays,
         * which a real scene hardly ever casts, get the reference answer. */
        tt_bf_intersect(a->scene->tri, (uint32_t)a->scene->triangle_count, r, hit, NULL);
        return;
    case RTC_RAY_READY: break;
    }
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    embree_ctx ic;
    embree_context(&ic, a, r);
    rtcIntersect1(e->scene, &ic.ic, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
    hit->prim = rh.hit.primID;
    /* Embree chose the triangle; t, u, v are recomputed with the project's
     * watertight test so that a hit on the same triangle gives the same
     * bits in every structure (triangle.h's contract). embree_filter let
     * only triangles pass that this same call accepts, so it cannot fail. */
    const float *p = a->scene->tri + 9 * (size_t)rh.hit.primID;
    (void)tt_intersect_triangle(r, p, p + 3, p + 6, r->tmax, &hit->t, &hit->u, &hit->v);
}

static int embree_occluded(const tt_accel *a, const tt_wray *r, tt_trace_args *args)
{
    const embree_impl *e = a->impl;
    (void)args;
    if (!e->has_geometry) return 0;
    struct RTCRay ray;
    int scale_exp = 0;
    switch (to_rtc_ray(r, &ray, &scale_exp)) {
    case RTC_RAY_EMPTY: return 0;
    case RTC_RAY_BRUTEFORCE: /* see embree_intersect */
        return tt_bf_occluded(a->scene->tri, (uint32_t)a->scene->triangle_count, r, NULL);
    case RTC_RAY_READY: break;
    }
    embree_ctx ic;
    embree_context(&ic, a, r);
    rtcOccluded1(e->scene, &ic.ic, &ray);
    return ray.tfar == -INFINITY; /* Embree's mark for an occluded ray */
}

/* The counting variants: Embree's traversal cannot be instrumented, so only
 * the ray itself is counted (nodes, boxes, triangles stay 0). */
static void embree_intersect_stats(const tt_accel *a, const tt_wray *r, tt_hit *hit,
                                   tt_trace_args *args, tt_ray_stats *stats)
{
    embree_intersect(a, r, hit, args);
    stats->rays += 1;
}

static int embree_occluded_stats(const tt_accel *a, const tt_wray *r, tt_trace_args *args,
                                 tt_ray_stats *stats)
{
    stats->rays += 1;
    return embree_occluded(a, r, args);
}

static tt_status embree_check(const tt_accel *a)
{
    const embree_impl *e = a->impl;
    if (!e || !e->device || !e->scene || !e->committed)
        return tt_error(a->ctx, TT_ERR_INVARIANT, "embree: the scene was never committed");
    if (atomic_load(&((embree_impl *)e)->error_claimed))
        return tt_error(a->ctx, TT_ERR_INVARIANT, "embree: the device reported an error: %s",
                        e->error);
    const tt_aabb *want = &a->scene->bounds;
    if (!e->has_geometry) {
        if (a->scene->triangle_count != 0)
            return tt_error(a->ctx, TT_ERR_INVARIANT,
                            "embree: no geometry attached for %zu triangles",
                            a->scene->triangle_count);
        return TT_OK;
    }
    struct RTCBounds b;
    rtcGetSceneBounds(e->scene, &b);
    const float got_lo[3] = {b.lower_x, b.lower_y, b.lower_z};
    const float got_hi[3] = {b.upper_x, b.upper_y, b.upper_z};
    for (int k = 0; k < 3; k++) {
        if (got_lo[k] != want->lo[k] || got_hi[k] != want->hi[k])
            return tt_error(a->ctx, TT_ERR_INVARIANT,
                            "embree: scene bounds on axis %d are [%.9g, %.9g], the scene's "
                            "are [%.9g, %.9g]",
                            k, got_lo[k], got_hi[k], want->lo[k], want->hi[k]);
    }
    return TT_OK;
}

static void embree_statistics(const tt_accel *a, tt_stat_fn fn, void *user)
{
    const embree_impl *e = a->impl;
    fn(user, "triangles", (double)a->scene->triangle_count);
    fn(user, "embree_version", (double)rtcGetDeviceProperty(e->device, RTC_DEVICE_PROPERTY_VERSION));
    /* 0 high, 1 medium, 2 low (tt_embree_quality) */
    fn(user, "build_quality", (double)a->options.embree.quality);
    long long total = atomic_load(&((embree_impl *)e)->bytes);
    fn(user, "memory_bytes", (double)total);
    fn(user, "geometry_bytes", (double)e->geometry_bytes);
    fn(user, "bvh_bytes", (double)(total - e->geometry_bytes));
    fn(user, "peak_build_bytes", (double)atomic_load(&((embree_impl *)e)->peak_bytes));
}

static size_t embree_memory(const tt_accel *a)
{
    embree_impl *e = a->impl;
    long long b = atomic_load(&e->bytes);
    return b > 0 ? (size_t)b : 0;
}

const tt_accel_vtable tt_embree_vtable = {
    .name = "embree",
    .gpu = TT_ACCEL_GPU_NONE,
    .build = embree_build,
    .destroy = embree_destroy,
    .intersect = embree_intersect,
    .occluded = embree_occluded,
    .intersect_stats = embree_intersect_stats,
    .occluded_stats = embree_occluded_stats,
    .locate = NULL,
    .check = embree_check,
    .statistics = embree_statistics,
    .memory = embree_memory,
    /* Embree's BVH is built and held inside Embree (rtcore has no call to
     * save or restore it), so there is nothing of ours to write. */
    .no_save = "Embree builds its BVH inside the library and offers no way to save or restore "
               "it; build it again instead (a few hundred milliseconds on the shared scenes)",
};
