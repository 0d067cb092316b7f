/* The threading contract of dynamic scenes (treetrace.h, "scene edits and
 * updates"), exercised from many threads; CI also runs this program built
 * with ThreadSanitizer (.ci/run), which fails on any data race:
 *  1. phases: 4 threads trace (single rays and batches) while the main
 *     thread waits at a barrier; then the main thread edits and updates
 *     alone; every trace agrees with bruteforce of the current frame;
 *  2. a free-for-all: tracers run without pause while the main thread keeps
 *     editing and updating; every call either succeeds or is refused
 *     (TT_ERR_BUSY while the other side holds the scene, TT_ERR_STALE
 *     between an edit and its update), and a successful trace agrees with
 *     bruteforce of the frame it ran on: never a torn read. */
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <string.h>
#include <time.h>

#include "check.h"

#define THREADS 4
#define RAYS 64

typedef struct shared {
    tt_context *ctx;
    tt_scene *scene;
    tt_accel *rtree, *bf;
    tt_ray rays[RAYS];
    pthread_barrier_t go, done;
    atomic_int stop, phase_frames;
    atomic_long traced, refused, wrong;
} shared;

static void make_rays(shared *s)
{
    uint32_t x = 7;
    for (int i = 0; i < RAYS; i++) {
        tt_ray *r = &s->rays[i];
        for (int k = 0; k < 3; k++) {
            x = x * 1664525u + 1013904223u;
            r->org[k] = (float)(x >> 8) / 16777216.0f * 10.0f;
        }
        r->org[2] = -5.0f;
        r->dir[0] = 0.01f * (float)(i % 7);
        r->dir[1] = 0.01f * (float)(i % 5);
        r->dir[2] = 1.0f;
        r->tmin = 0.0f;
        r->tmax = INFINITY;
    }
}

/* One pass of the rays through the R-tree, each checked against bruteforce
 * inside the same bracket of the scene (both see one frame or neither
 * runs). Returns 0 when refused. */
static int trace_pass(shared *s, int batch)
{
    tt_hit h[RAYS], ref[RAYS];
    tt_status st = batch ? tt_intersect(s->rtree, s->rays, RAYS, h, NULL, NULL) : TT_OK;
    for (int i = 0; !batch && i < RAYS && st == TT_OK; i++) st = tt_intersect1(s->rtree, &s->rays[i], &h[i]);
    if (st == TT_ERR_BUSY || st == TT_ERR_STALE) return 0;
    if (st != TT_OK) {
        atomic_fetch_add(&s->wrong, 1);
        return 1;
    }
    st = tt_intersect(s->bf, s->rays, RAYS, ref, NULL, NULL);
    if (st != TT_OK) return 0; /* the frame moved on between the two: no verdict */
    /* both succeeded, but an edit + update could have run in between:
     * compare only when no edit happened meanwhile (the version is read
     * through the rtree's refusal: a second rtree pass must agree too) */
    tt_hit h2[RAYS];
    st = tt_intersect(s->rtree, s->rays, RAYS, h2, NULL, NULL);
    if (st != TT_OK) return 0;
    int same_frame = memcmp(h, h2, sizeof h) == 0;
    for (int i = 0; same_frame && i < RAYS; i++) {
        const int agree = h[i].prim == ref[i].prim ||
                          (h[i].prim != TT_INVALID_ID && ref[i].prim != TT_INVALID_ID &&
                           fabsf(h[i].t - ref[i].t) <= 1e-4f * fabsf(ref[i].t));
        if (!agree) {
            atomic_fetch_add(&s->wrong, 1);
            break;
        }
    }
    return 1;
}

static void *tracer(void *arg)
{
    shared *s = arg;
    /* phase 1: in lockstep with the editor */
    for (;;) {
        pthread_barrier_wait(&s->go);
        if (atomic_load(&s->stop)) break;
        for (int k = 0; k < 4; k++) {
            if (trace_pass(s, k & 1)) atomic_fetch_add(&s->traced, 1);
            else atomic_fetch_add(&s->refused, 1); /* must not happen in phase 1 */
        }
        pthread_barrier_wait(&s->done);
    }
    /* phase 2: free for all until told to stop */
    while (atomic_load(&s->stop) == 1) {
        if (trace_pass(s, 1)) atomic_fetch_add(&s->traced, 1);
        else atomic_fetch_add(&s->refused, 1);
        /* a pause between passes, so that the editor finds the scene free
         * now and then (refused calls do not queue: a writer waits for a
         * moment without traces) */
        struct timespec pause = {0, 50000};
        nanosleep(&pause, NULL);
    }
    return NULL;
}

/* An edit of frame f: move a triangle, remove one, add one. */
static tt_status edit(shared *s, int f)
{
    uint32_t id = (uint32_t)(f * 7) % (uint32_t)tt_scene_triangle_count(s->scene);
    while (!tt_scene_triangle_alive(s->scene, id)) id = (id + 1) % (uint32_t)tt_scene_triangle_count(s->scene);
    float t[9];
    for (int k = 0; k < 9; k++) t[k] = (float)((f * 13 + k * 7) % 10) + (k % 3 == 2 ? 0.5f : 0.0f);
    tt_status st = tt_scene_set_triangles(s->scene, &id, t, 1);
    if (st != TT_OK) return st;
    uint32_t rm = (id + 1) % (uint32_t)tt_scene_triangle_count(s->scene);
    if (tt_scene_triangle_alive(s->scene, rm)) {
        st = tt_scene_remove_triangles(s->scene, &rm, 1);
        if (st != TT_OK) return st;
    }
    for (int k = 0; k < 9; k++) t[k] = (float)((f * 5 + k * 3) % 10);
    return tt_scene_add_triangles(s->scene, t, 1, NULL);
}

int main(void)
{
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = 1; /* the batches stay on their caller's thread: the test's threads race */
    tt_context *ctx;
    REQUIRE_OK(NULL, tt_context_create(&co, &ctx));
    shared s;
    memset(&s, 0, sizeof s);
    s.ctx = ctx;
    float v[3 * 3 * 200];
    uint32_t idx[3 * 200];
    uint32_t x = 3;
    for (int i = 0; i < 3 * 3 * 200; i++) {
        x = x * 1664525u + 1013904223u;
        v[i] = (float)(x >> 8) / 16777216.0f * 10.0f;
    }
    for (uint32_t i = 0; i < 3 * 200; i++) idx[i] = i;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 600, idx, 200, &s.scene));
    s.rtree = tt_test_build_default(ctx, s.scene, "rtree");
    s.bf = tt_test_build_default(ctx, s.scene, "bruteforce");
    make_rays(&s);
    pthread_barrier_init(&s.go, NULL, THREADS + 1);
    pthread_barrier_init(&s.done, NULL, THREADS + 1);
    pthread_t th[THREADS];
    for (int i = 0; i < THREADS; i++) pthread_create(&th[i], NULL, tracer, &s);

    /* phase 1 */
    for (int f = 0; f < 12; f++) {
        pthread_barrier_wait(&s.go);
        pthread_barrier_wait(&s.done);
        CHECK_OK(ctx, edit(&s, f));
        CHECK_OK(ctx, tt_accel_update(s.rtree));
        CHECK_OK(ctx, tt_accel_update(s.bf));
        CHECK_OK(ctx, tt_accel_check(s.rtree));
    }
    CHECK(atomic_load(&s.refused) == 0);
    CHECK(atomic_load(&s.wrong) == 0);
    const long phase1 = atomic_load(&s.traced);
    CHECK(phase1 == 12 * THREADS * 4);

    /* phase 2: tracers run free */
    atomic_store(&s.stop, 1);
    pthread_barrier_wait(&s.go);
    int edits = 0, busy = 0;
    for (int f = 100; f < 1000000 && edits < 40; f++) {
        /* let the tracers make progress between edits (a few passes) */
        const long seen = atomic_load(&s.traced) + atomic_load(&s.refused);
        while (atomic_load(&s.traced) + atomic_load(&s.refused) < seen + 3) sched_yield();
        tt_status st = edit(&s, f);
        if (st == TT_ERR_BUSY) {
            busy++;
            continue;
        }
        CHECK_OK(ctx, st);
        edits++;
        /* the update must eventually get the scene alone */
        while ((st = tt_accel_update(s.rtree)) == TT_ERR_BUSY) busy++;
        CHECK_OK(ctx, st);
        while ((st = tt_accel_update(s.bf)) == TT_ERR_BUSY) busy++;
        CHECK_OK(ctx, st);
    }
    atomic_store(&s.stop, 2);
    for (int i = 0; i < THREADS; i++) pthread_join(th[i], NULL);
    CHECK(edits > 0);
    CHECK(atomic_load(&s.traced) > phase1);
    CHECK(atomic_load(&s.wrong) == 0);
    CHECK_OK(ctx, tt_accel_check(s.rtree));
    printf("phase 2: %d edits (%d refused busy), %ld passes traced, %ld refused\n", edits, busy,
           atomic_load(&s.traced) - phase1, atomic_load(&s.refused));
    pthread_barrier_destroy(&s.go);
    pthread_barrier_destroy(&s.done);
    tt_accel_destroy(s.rtree);
    tt_accel_destroy(s.bf);
    tt_scene_destroy(s.scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
