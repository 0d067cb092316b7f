/* One structure, many threads: every structure (bruteforce, the R-tree in
 * both layouts, the kd-tree with each traversal and the shadow-caster hint)
 * built once, then traced at the same time by THREADS POSIX threads through
 * the single-ray calls (tt_intersect1_ex with start hints and counting,
 * tt_occluded1_ex) and the batch calls (tt_intersect, tt_occluded, with and
 * without statistics, packets on and off). Every thread's answers must be
 * bit-identical to those traced alone beforehand.
 *
 * CI also runs this program under ThreadSanitizer (build-ci-tsan), where a
 * data race in tracing (a cache or counter written through a const
 * structure, shared scratch memory) is reported. The structures' context
 * has threads = 1 so that the batch calls run their OpenMP region with a
 * team of one, in the calling thread: the concurrency under test is the
 * caller's, and libgomp/libomp (not built with TSan, so its
 * synchronisation is invisible to it) cannot give false reports. Embree is
 * left out: its library is not instrumented either. Scene-free: a
 * generated terrain with overhangs. */
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "check.h"

#define THREADS 6
#define GRID 24
#define RAYS 1500

static uint32_t next(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}

static float unit(uint32_t *x) { return (float)(next(x) >> 8) * (1.0f / 16777216.0f); }

/* A height field (2 GRID^2 triangles) and floating slabs above it. */
static tt_scene *make_scene(tt_context *ctx)
{
    enum { V = (GRID + 1) * (GRID + 1), SLABS = 40 };
    static float v[3 * (V + 4 * SLABS)];
    static uint32_t idx[3 * (2 * GRID * GRID + 2 * SLABS)];
    uint32_t seed = 99;
    size_t nv = 0, nt = 0;
    for (int y = 0; y <= GRID; y++)
        for (int x = 0; x <= GRID; x++) {
            v[3 * nv] = (float)x;
            v[3 * nv + 1] = 0.7f * unit(&seed);
            v[3 * nv + 2] = (float)y;
            nv++;
        }
    for (uint32_t y = 0; y < GRID; y++)
        for (uint32_t x = 0; x < GRID; x++) {
            uint32_t a = y * (GRID + 1) + x, b = a + 1, c = a + GRID + 1, d = c + 1;
            uint32_t *t = &idx[3 * nt];
            t[0] = a, t[1] = c, t[2] = b, t[3] = b, t[4] = c, t[5] = d;
            nt += 2;
        }
    for (int s = 0; s < SLABS; s++) {
        float x0 = unit(&seed) * GRID, z0 = unit(&seed) * GRID, h = 1.0f + 3.0f * unit(&seed);
        float w = 0.5f + 2.0f * unit(&seed);
        uint32_t base = (uint32_t)nv;
        const float corner[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
        for (int k = 0; k < 4; k++) {
            v[3 * nv] = x0 + w * corner[k][0];
            v[3 * nv + 1] = h + 0.2f * unit(&seed);
            v[3 * nv + 2] = z0 + w * corner[k][1];
            nv++;
        }
        uint32_t *t = &idx[3 * nt];
        t[0] = base, t[1] = base + 2, t[2] = base + 1;
        t[3] = base + 1, t[4] = base + 2, t[5] = base + 3;
        nt += 2;
    }
    tt_scene *scene = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, nv, idx, nt, &scene));
    return scene;
}

typedef struct answers {
    tt_hit hit[RAYS], batch_hit[RAYS], mode_hit[RAYS];
    uint8_t occ[RAYS], batch_occ[RAYS];
    tt_ray_stats stats, batch_stats;
} answers;

typedef struct job {
    const tt_accel *accel;
    const tt_ray *rays;
    const uint32_t *hints;
    answers *out;
    int offset; /* each thread starts at another ray */
    int failed;
    pthread_barrier_t *step; /* threads: all meet here every WINDOW rays */
} job;

/* The threads trace in lock-step windows: every thread is inside the same
 * window at the same time, so any two of them touch shared state
 * concurrently, and ThreadSanitizer (which may miss a race between threads
 * that run one after the other: seen 1 run in 5 with free-running threads)
 * sees the unordered accesses within each window. */
#define WINDOW 100

static void meet(job *j)
{
    if (j->step) pthread_barrier_wait(j->step);
}

static void trace_all(job *j)
{
    answers *o = j->out;
    memset(&o->stats, 0, sizeof o->stats);
    memset(&o->batch_stats, 0, sizeof o->batch_stats);
    for (int k = 0; k < RAYS; k++) {
        if (k % WINDOW == 0) meet(j);
        int i = (k + j->offset) % RAYS;
        tt_trace_args a = {j->hints[i], TT_INVALID_ID, &o->stats};
        int occ = -1;
        if (tt_intersect1_ex(j->accel, &j->rays[i], &o->hit[i], &a) != TT_OK) j->failed = 1;
        tt_trace_args s = {a.end_hint, TT_INVALID_ID, NULL};
        if (tt_occluded1_ex(j->accel, &j->rays[i], &occ, &s) != TT_OK) j->failed = 1;
        o->occ[i] = (uint8_t)occ;
    }
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    /* counts are per ray only ray by ray (a packet's rays share its visits),
     * so the counting batch runs with packets off; the others alternate
     * between packets on and off with the thread */
    bo.stats = &o->batch_stats;
    bo.packets = TT_PACKETS_OFF;
    meet(j);
    if (tt_intersect(j->accel, j->rays, RAYS, o->batch_hit, NULL, &bo) != TT_OK) j->failed = 1;
    bo.stats = NULL;
    bo.packets = (uint32_t)(j->offset & 1 ? TT_PACKETS_ON : TT_PACKETS_OFF);
    meet(j);
    if (tt_intersect(j->accel, j->rays, RAYS, o->mode_hit, NULL, &bo) != TT_OK) j->failed = 1;
    meet(j);
    if (tt_occluded(j->accel, j->rays, RAYS, o->batch_occ, NULL, &bo) != TT_OK) j->failed = 1;
}

static pthread_barrier_t step;

static void *thread_main(void *arg)
{
    trace_all(arg);
    return NULL;
}

static int stats_equal(const tt_ray_stats *a, const tt_ray_stats *b)
{
    return memcmp(a, b, sizeof *a) == 0;
}

static void check_structure(tt_context *ctx, const tt_scene *scene, const tt_build_options *bo,
                            const char *what, const tt_ray *rays)
{
    tt_accel *a = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, bo, &a));
    static uint32_t hints[RAYS];
    for (int i = 0; i < RAYS; i++) hints[i] = i % 3 ? tt_accel_locate(a, rays[i].org) : TT_INVALID_ID;
    static answers alone, many[THREADS];
    job ref = {a, rays, hints, &alone, 0, 0, NULL};
    trace_all(&ref);
    CHECK_MSG(!ref.failed, "%s: a call failed", what);
    int hits = 0;
    for (int i = 0; i < RAYS; i++) hits += alone.hit[i].prim != TT_INVALID_ID;
    CHECK_MSG(hits > RAYS / 4 && hits < RAYS, "%s: %d of %d rays hit", what, hits, RAYS);

    pthread_t th[THREADS];
    job jobs[THREADS];
    pthread_barrier_init(&step, NULL, THREADS);
    for (int t = 0; t < THREADS; t++) {
        jobs[t] = (job){a, rays, hints, &many[t], 1 + t * (RAYS / THREADS), 0, &step};
        if (pthread_create(&th[t], NULL, thread_main, &jobs[t]) != 0) {
            fprintf(stderr, "pthread_create failed\n");
            exit(1);
        }
    }
    for (int t = 0; t < THREADS; t++) pthread_join(th[t], NULL);
    pthread_barrier_destroy(&step);
    for (int t = 0; t < THREADS; t++) {
        const answers *m = &many[t];
        size_t bad = 0;
        for (int i = 0; i < RAYS; i++)
            bad += memcmp(&m->hit[i], &alone.hit[i], sizeof(tt_hit)) != 0 ||
                   memcmp(&m->batch_hit[i], &alone.hit[i], sizeof(tt_hit)) != 0 ||
                   memcmp(&m->mode_hit[i], &alone.hit[i], sizeof(tt_hit)) != 0 ||
                   m->occ[i] != alone.occ[i] || m->batch_occ[i] != alone.occ[i];
        CHECK_MSG(!jobs[t].failed && bad == 0, "%s, thread %d: %zu of %d rays differ from alone",
                  what, t, bad, RAYS);
        CHECK_MSG(stats_equal(&m->stats, &alone.stats) &&
                      stats_equal(&m->batch_stats, &alone.batch_stats),
                  "%s, thread %d: counts differ (%llu vs %llu nodes)", what, t,
                  (unsigned long long)m->stats.nodes, (unsigned long long)alone.stats.nodes);
    }
    tt_accel_destroy(a);
}

int main(void)
{
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = 1; /* see above: no OpenMP team inside the batch calls */
    tt_context *ctx = NULL;
    REQUIRE_OK(NULL, tt_context_create(&co, &ctx));
    tt_scene *scene = make_scene(ctx);
    static tt_ray rays[RAYS];
    uint32_t seed = 7;
    for (int i = 0; i < RAYS; i++) {
        tt_ray *r = &rays[i];
        int from_above = i % 2;
        r->org[0] = unit(&seed) * GRID;
        r->org[1] = from_above ? 8.0f : 0.8f + 3.0f * unit(&seed);
        r->org[2] = unit(&seed) * GRID;
        r->dir[0] = unit(&seed) - 0.5f;
        r->dir[1] = from_above ? -1.0f : unit(&seed) - 0.5f;
        r->dir[2] = unit(&seed) - 0.5f;
        r->tmin = 0.0f;
        r->tmax = i % 5 == 0 ? 3.0f : INFINITY;
    }
    struct {
        const char *accel;
        int traversal, layout, caster;
    } variants[] = {
        {"bruteforce", -1, -1, 0},
        {"rtree", -1, TT_RTREE_LAYOUT_COMPACT, 0},
        {"rtree", TT_RTREE_STACKLESS, TT_RTREE_LAYOUT_COMPACT, 0},
        {"rtree", TT_RTREE_ORDERED, TT_RTREE_LAYOUT_COMPLETE, 0},
        {"rtree", TT_RTREE_STACKLESS, TT_RTREE_LAYOUT_COMPLETE, 0},
        {"kdtree", TT_KD_HTR, -1, 0},
        {"kdtree", TT_KD_BTR, -1, 0},
        {"kdtree", TT_KD_SLTR, -1, 1},
        {"kdtree", TT_KD_SEQ, -1, 0},
    };
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        tt_build_options bo;
        tt_build_options_default(&bo);
        bo.accel = variants[v].accel;
        if (variants[v].layout >= 0) bo.rtree.layout = (tt_rtree_layout)variants[v].layout;
        if (variants[v].traversal >= 0) {
            bo.rtree.traversal = (tt_rtree_traversal)variants[v].traversal;
            bo.kdtree.traversal = (tt_kd_traversal)variants[v].traversal;
        }
        bo.kdtree.shadow_caster_hint = variants[v].caster;
        char what[96];
        snprintf(what, sizeof what, "%s traversal %d layout %d caster %d", variants[v].accel,
                 variants[v].traversal, variants[v].layout, variants[v].caster);
        check_structure(ctx, scene, &bo, what, rays);
    }
    printf("%zu structures x %d threads x %d rays\n", sizeof variants / sizeof variants[0],
           THREADS, RAYS);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
