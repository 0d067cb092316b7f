/* Allocation failure anywhere in the library returns an error to the caller:
 * never a crash, an exit or a leak. A counting allocator makes the k-th
 * allocation (or reallocation) fail, for k = 1, 2, ... until the step under
 * test succeeds without reaching k. Steps: loading a scene from memory (OBJ,
 * ascii and binary PLY), tt_scene_create, building every registered
 * structure in its main option variants, and rendering a small image with
 * the hit buffer, the image, statistics and per-pixel counts kept. Every
 * injected failure must give TT_ERR_OUT_OF_MEMORY with a message, no object
 * back, and the bytes held before the step (nothing leaked); after
 * everything is destroyed the allocator must hold nothing at all. */
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <string.h>

#include "accel/kdtree/build/kd_build_par.h"
#include "check.h"

/* ------------------------------------------------------------ allocator */

typedef struct alloc_state {
    pthread_mutex_t lock; /* the library may allocate from worker threads */
    long calls;           /* allocation and reallocation calls while armed */
    long fail_at;         /* the armed call (1-based) that fails; 0: none  */
    int armed, failed;
    size_t live_bytes;
    long live_blocks;
} alloc_state;

#define HEADER 16

static void *a_alloc(void *user, size_t size)
{
    alloc_state *a = user;
    pthread_mutex_lock(&a->lock);
    int fail = 0;
    if (a->armed) {
        a->calls++;
        if (a->calls == a->fail_at) fail = a->failed = 1;
    }
    unsigned char *p = fail || size > SIZE_MAX - HEADER ? NULL : malloc(size + HEADER);
    if (p) {
        memcpy(p, &size, sizeof size);
        a->live_bytes += size;
        a->live_blocks++;
    }
    pthread_mutex_unlock(&a->lock);
    return p ? p + HEADER : NULL;
}

static void a_free(void *user, void *ptr)
{
    alloc_state *a = user;
    if (!ptr) return;
    unsigned char *p = (unsigned char *)ptr - HEADER;
    size_t size;
    memcpy(&size, p, sizeof size);
    pthread_mutex_lock(&a->lock);
    a->live_bytes -= size;
    a->live_blocks--;
    pthread_mutex_unlock(&a->lock);
    free(p);
}

/* A failed reallocation leaves the old block alone, as realloc does. */
static void *a_realloc(void *user, void *ptr, size_t size)
{
    if (!ptr) return a_alloc(user, size);
    void *q = a_alloc(user, size);
    if (!q) return NULL;
    size_t old;
    memcpy(&old, (unsigned char *)ptr - HEADER, sizeof old);
    memcpy(q, ptr, old < size ? old : size);
    a_free(user, ptr);
    return q;
}

static void arm(alloc_state *a, long fail_at)
{
    pthread_mutex_lock(&a->lock);
    a->calls = 0;
    a->fail_at = fail_at;
    a->failed = 0;
    a->armed = 1;
    pthread_mutex_unlock(&a->lock);
}

static void disarm(alloc_state *a)
{
    pthread_mutex_lock(&a->lock);
    a->armed = 0;
    pthread_mutex_unlock(&a->lock);
}

/* ----------------------------------------------------------- the driver */

/* One step under test: does its work, returns its status, and on success
 * has created an object that `undo` destroys. */
typedef struct step {
    const char *name;
    tt_status (*run)(void *arg);
    void (*undo)(void *arg);
    void *arg;
} step;

static alloc_state A;
static tt_context *ctx;
static long total_failures_injected;

/* Runs the step with the 1st, 2nd, ... allocation failing until it
 * succeeds untouched; checks each failure. Returns the number of
 * allocations the step makes. */
static long exercise(const step *s)
{
    size_t base_bytes = A.live_bytes;
    long base_blocks = A.live_blocks;
    for (long k = 1;; k++) {
        arm(&A, k);
        tt_status st = s->run(s->arg);
        disarm(&A);
        if (!A.failed) {
            CHECK_MSG(st == TT_OK, "%s: fails without an injected failure: %s: %s", s->name,
                      tt_strerror(st), tt_context_last_error(ctx));
            if (st == TT_OK) s->undo(s->arg);
            CHECK_MSG(A.live_bytes == base_bytes && A.live_blocks == base_blocks,
                      "%s: %zu bytes in %ld blocks leaked by a successful run", s->name,
                      A.live_bytes - base_bytes, A.live_blocks - base_blocks);
            return k - 1;
        }
        total_failures_injected++;
        CHECK_MSG(st == TT_ERR_OUT_OF_MEMORY, "%s: allocation %ld failed, the step returned %s: %s",
                  s->name, k, tt_strerror(st), tt_context_last_error(ctx));
        CHECK_MSG(tt_context_last_error(ctx)[0] != '\0', "%s: allocation %ld: no message", s->name, k);
        if (st == TT_OK) s->undo(s->arg); /* it claimed success anyway */
        if (A.live_bytes != base_bytes || A.live_blocks != base_blocks) {
            CHECK_MSG(0, "%s: allocation %ld failed and %zu bytes in %ld blocks leaked", s->name, k,
                      A.live_bytes - base_bytes, A.live_blocks - base_blocks);
            return k; /* every later k would report the same leak */
        }
        if (k > 1000000) {
            CHECK_MSG(0, "%s: more than a million allocations", s->name);
            return k;
        }
    }
}

/* ---------------------------------------------------------------- steps */

/* The scene: a grid of cubes (quads, so the fan triangulation runs) as one
 * OBJ text and the same as ascii and binary PLY; 2592 triangles and 1728
 * vertices, past the loaders' first reserve so that their arrays grow. The
 * structures are built on a smaller grid (324 triangles, still many nodes):
 * a build is repeated once for each of its allocations, and the kd-tree's
 * builders allocate per node. */
#define CUBES 6
#define TRIANGLES (CUBES * CUBES * CUBES * 12)
#define BUILD_CUBES 3

typedef struct text {
    char *data;
    size_t size, cap;
} text;

static void put(text *t, const void *p, size_t n)
{
    if (t->size + n > t->cap) {
        t->cap = 2 * (t->size + n) + 4096;
        t->data = realloc(t->data, t->cap);
        if (!t->data) exit(1);
    }
    memcpy(t->data + t->size, p, n);
    t->size += n;
}

static void putf(text *t, const char *fmt, ...)
{
    char line[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    put(t, line, (size_t)n);
}

static text obj_text, ply_ascii, ply_binary, small_obj;

static void make_files(void)
{
    for (int c = 0; c < BUILD_CUBES * BUILD_CUBES * BUILD_CUBES; c++) {
        for (int q = 0; q < 8; q++)
            putf(&small_obj, "v %d %d %d\n", 2 * (c % BUILD_CUBES) + (q & 1),
                 2 * (c / BUILD_CUBES % BUILD_CUBES) + ((q >> 1) & 1),
                 2 * (c / (BUILD_CUBES * BUILD_CUBES)) + ((q >> 2) & 1));
        putf(&small_obj, "f -8 -7 -5 -6\nf -4 -2 -1 -3\nf -8 -4 -3 -7\n"
                         "f -6 -5 -1 -2\nf -8 -6 -2 -4\nf -7 -3 -1 -5\n");
    }
    static const int face[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                   {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    const size_t nv = CUBES * CUBES * CUBES * 8, nf = CUBES * CUBES * CUBES * 6;
    const char *hdr = "ply\nformat %s 1.0\nelement vertex %zu\nproperty float x\nproperty float y\n"
                      "property float z\nelement face %zu\nproperty list uchar int vertex_indices\n"
                      "end_header\n";
    putf(&ply_ascii, hdr, "ascii", nv, nf);
    putf(&ply_binary, hdr, "binary_little_endian", nv, nf);
    for (int c = 0; c < CUBES * CUBES * CUBES; c++)
        for (int q = 0; q < 8; q++) {
            float p[3] = {(float)(2 * (c % CUBES) + (q & 1)),
                          (float)(2 * (c / CUBES % CUBES) + ((q >> 1) & 1)),
                          (float)(2 * (c / (CUBES * CUBES)) + ((q >> 2) & 1))};
            putf(&obj_text, "v %g %g %g\n", p[0], p[1], p[2]);
            putf(&ply_ascii, "%g %g %g\n", p[0], p[1], p[2]);
            put(&ply_binary, p, sizeof p);
        }
    for (int c = 0; c < CUBES * CUBES * CUBES; c++)
        for (int f = 0; f < 6; f++) {
            int32_t id[4];
            for (int k = 0; k < 4; k++) id[k] = 8 * c + face[f][k];
            /* OBJ: 1-based, the last one relative (negative) */
            putf(&obj_text, "f %d %d %d %d\n", id[0] + 1, id[1] + 1, id[2] + 1, id[3] - (int)nv);
            putf(&ply_ascii, "4 %d %d %d %d\n", id[0], id[1], id[2], id[3]);
            unsigned char four = 4;
            put(&ply_binary, &four, 1);
            put(&ply_binary, id, sizeof id);
        }
}

typedef struct load_arg {
    const char *format;
    const void *data;
    size_t size;
    tt_scene *scene;
} load_arg;

static tt_status load_run(void *p)
{
    load_arg *a = p;
    a->scene = (tt_scene *)p; /* must come back NULL on failure */
    tt_status st = tt_scene_load_memory(ctx, "alloc-test", a->format, a->data, a->size, &a->scene);
    if (st != TT_OK) CHECK_MSG(a->scene == NULL, "a failed load returned a scene");
    return st;
}

static void load_undo(void *p)
{
    load_arg *a = p;
    CHECK(tt_scene_triangle_count(a->scene) == TRIANGLES);
    tt_scene_destroy(a->scene);
}

typedef struct create_arg {
    tt_scene *scene;
} create_arg;

static tt_status create_run(void *p)
{
    static const float v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    create_arg *a = p;
    return tt_scene_create(ctx, v, 4, idx, 2, &a->scene);
}

static void create_undo(void *p)
{
    create_arg *a = p;
    tt_scene_destroy(a->scene);
}

typedef struct build_arg {
    const tt_scene *scene;
    tt_build_options opt;
    uint32_t kd_cutoff; /* the kd-tree's task cutoff, 0: the default */
    tt_accel *accel;
} build_arg;

static tt_status build_run(void *p)
{
    build_arg *a = p;
    a->accel = (tt_accel *)p;
    const uint32_t saved = kd_par_cutoff;
    if (a->kd_cutoff) kd_par_cutoff = a->kd_cutoff;
    tt_status st = tt_accel_build(ctx, a->scene, &a->opt, &a->accel);
    kd_par_cutoff = saved;
    if (st != TT_OK) CHECK_MSG(a->accel == NULL, "a failed build returned a structure");
    return st;
}

static void build_undo(void *p)
{
    build_arg *a = p;
    CHECK_OK(ctx, tt_accel_check(a->accel));
    tt_accel_destroy(a->accel);
}

typedef struct render_arg {
    const tt_scene *scene;
    const tt_accel *accel;
    tt_camera camera;
    tt_render_options opt;
    tt_render_result *result;
} render_arg;

static tt_status render_run(void *p)
{
    render_arg *a = p;
    a->result = (tt_render_result *)p;
    tt_status st = tt_render(ctx, a->scene, a->accel, &a->camera, &a->opt, &a->result);
    if (st != TT_OK) CHECK_MSG(a->result == NULL, "a failed render returned a result");
    return st;
}

static void render_undo(void *p)
{
    render_arg *a = p;
    size_t size = 0;
    CHECK(tt_render_hits(a->result, &size) != NULL && size == 12u * a->opt.width * a->opt.height);
    CHECK(tt_render_image(a->result) != NULL);
    CHECK(tt_render_pixel_stats(a->result, TT_HEAT_NODES) != NULL);
    const tt_render_summary *s = tt_render_get_summary(a->result);
    CHECK(s && s->primary_hits > 0 && s->has_stats);
    tt_render_result_destroy(a->result);
}

/* The main option variants of a structure: what changes how it is built
 * (the R-tree's strategies, reinsertion, split, node sizes and bulk loaders; the
 * kd-tree's builders and sparse boxes) and each traversal once (some keep
 * per-traversal data). Other structures: their defaults. */
static size_t variants(const char *name, tt_build_options *v, const char **label, uint32_t *cutoff)
{
    size_t n = 0;
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = name;
    if (strcmp(name, "rtree") == 0) {
        static const char *const s_names[] = {"min-volume", "min-surface", "min-overlap", "rstar",
                                              "rstar-surface"};
        for (int s = TT_RTREE_MIN_VOLUME; s <= TT_RTREE_RSTAR_SURFACE; s++) {
            v[n] = o;
            v[n].rtree.strategy = (tt_rtree_strategy)s;
            v[n].rtree.traversal = (tt_rtree_traversal)(s % 4);
            label[n++] = s_names[s];
        }
        v[n] = o, v[n].rtree.reinsert = 0, label[n++] = "no reinsert";
        v[n] = o, v[n].rtree.split = TT_RTREE_SPLIT_QUADRATIC, label[n++] = "quadratic split";
        v[n] = o, v[n].rtree.m = 4, v[n].rtree.M = 16, label[n++] = "m=4 M=16";
        v[n] = o, v[n].rtree.reinsert_far = 0, v[n].rtree.traversal = TT_RTREE_STACK;
        label[n++] = "close reinsert, stack traversal";
        v[n] = o, v[n].rtree.build = TT_RTREE_BUILD_STR, label[n++] = "build str";
        v[n] = o, v[n].rtree.build = TT_RTREE_BUILD_HILBERT, label[n++] = "build hilbert";
        v[n] = o, v[n].rtree.build = TT_RTREE_BUILD_SAH, label[n++] = "build sah";
        v[n] = o, v[n].rtree.build = TT_RTREE_BUILD_SAH, v[n].rtree.m = 4, v[n].rtree.M = 16;
        label[n++] = "build sah m=4 M=16";
        v[n] = o, v[n].rtree.layout = TT_RTREE_LAYOUT_COMPACT, v[n].rtree.m = 3, v[n].rtree.M = 8;
        label[n++] = "compact layout m=3 M=8";
        v[n] = o, v[n].rtree.layout = TT_RTREE_LAYOUT_COMPACT;
        v[n].rtree.traversal = TT_RTREE_STACKLESS, label[n++] = "compact layout stackless";
        v[n] = o, v[n].rtree.layout = TT_RTREE_LAYOUT_COMPACT, v[n].rtree.build = TT_RTREE_BUILD_SAH;
        v[n].rtree.m = 4, v[n].rtree.M = 16, label[n++] = "compact layout, build sah m=4 M=16";
    } else if (strcmp(name, "kdtree") == 0) {
        static const char *const t_names[] = {"nlogn htr dmin=1", "nlogn btr dmin=1",
                                              "nlogn sltr dmin=1", "nlogn seq dmin=1"};
        for (int t = TT_KD_HTR; t <= TT_KD_SEQ; t++) {
            v[n] = o, v[n].kdtree.traversal = (tt_kd_traversal)t, v[n].kdtree.dmin = 1;
            label[n++] = t_names[t];
        }
        v[n] = o, v[n].kdtree.builder = TT_KD_NLOG2N, label[n++] = "nlog2n";
        v[n] = o, v[n].kdtree.dmin = -1, label[n++] = "no sparse boxes";
        v[n] = o, v[n].kdtree.builder = TT_KD_NLOG2N, v[n].kdtree.dmin = 3;
        v[n].kdtree.traversal = TT_KD_SLTR, v[n].kdtree.shadow_caster_hint = 1;
        label[n++] = "nlog2n sltr dmin=3 caster hint";
        v[n] = o, v[n].kdtree.builder = TT_KD_BINNED, label[n++] = "binned";
        /* The parallel builders (the context has 2 threads): every node of
         * 16 triangles or more split by tasks, failures inside them. */
        v[n] = o, cutoff[n] = 16, label[n++] = "nlogn parallel";
        v[n] = o, v[n].kdtree.builder = TT_KD_NLOG2N, cutoff[n] = 16, label[n++] = "nlog2n parallel";
        v[n] = o, v[n].kdtree.builder = TT_KD_BINNED, cutoff[n] = 16, label[n++] = "binned parallel";
    } else {
        v[n] = o, label[n++] = "defaults";
    }
    return n;
}

int main(void)
{
    uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    if (first != 1) {
        printf("skipped: the binary PLY here is written little-endian\n");
        return 77;
    }
    pthread_mutex_init(&A.lock, NULL);
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = 2;
    co.allocator.alloc = a_alloc;
    co.allocator.realloc = a_realloc;
    co.allocator.free = a_free;
    co.allocator.user = &A;
    REQUIRE_OK(ctx, tt_context_create(&co, &ctx));
    make_files();

    /* loading */
    load_arg la[3] = {{"obj", obj_text.data, obj_text.size, NULL},
                      {"ply", ply_ascii.data, ply_ascii.size, NULL},
                      {NULL, ply_binary.data, ply_binary.size, NULL}};
    static const char *const load_names[3] = {"load OBJ", "load ascii PLY", "load binary PLY"};
    for (int i = 0; i < 3; i++) {
        step s = {load_names[i], load_run, load_undo, &la[i]};
        printf("%-40s %4ld allocations\n", s.name, exercise(&s));
    }
    create_arg ca = {NULL};
    step cs = {"tt_scene_create", create_run, create_undo, &ca};
    printf("%-40s %4ld allocations\n", cs.name, exercise(&cs));

    /* the scene every structure is built on and rendered with */
    tt_scene *scene = NULL;
    REQUIRE_OK(ctx, tt_scene_load_memory(ctx, "small.obj", "obj", small_obj.data, small_obj.size, &scene));
    CHECK(tt_scene_triangle_count(scene) == BUILD_CUBES * BUILD_CUBES * BUILD_CUBES * 12);
    tt_camera cam;
    tt_camera_frame_scene(scene, &cam);

    size_t structures = 0;
    for (const char *const *name = tt_accel_names(); *name; name++) {
        tt_build_options v[16];
        const char *label[16];
        uint32_t cutoff[16] = {0};
        size_t nv = variants(*name, v, label, cutoff);
        for (size_t i = 0; i < nv; i++) {
            build_arg ba = {scene, v[i], cutoff[i], NULL};
            char what[128];
            snprintf(what, sizeof what, "build %s (%s)", *name, label[i]);
            step s = {what, build_run, build_undo, &ba};
            printf("%-40s %4ld allocations\n", what, exercise(&s));
        }
        /* render with the structure's defaults */
        build_arg ba = {scene, v[0], 0, NULL};
        tt_build_options_default(&ba.opt);
        ba.opt.accel = *name;
        REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &ba.opt, &ba.accel));
        render_arg ra;
        memset(&ra, 0, sizeof ra);
        ra.scene = scene;
        ra.accel = ba.accel;
        ra.camera = cam;
        tt_render_options_default(&ra.opt);
        ra.opt.width = 16;
        ra.opt.height = 12;
        ra.opt.keep_hits = ra.opt.keep_image = ra.opt.keep_pixel_stats = 1;
        ra.opt.stats = 1;
        ra.opt.repeat = 3;
        char what[128];
        snprintf(what, sizeof what, "render with %s", *name);
        step s = {what, render_run, render_undo, &ra};
        printf("%-40s %4ld allocations\n", what, exercise(&s));
        tt_accel_destroy(ba.accel);
        structures++;
    }
    CHECK(structures > 0);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    CHECK_MSG(A.live_bytes == 0 && A.live_blocks == 0,
              "%zu bytes in %ld blocks still allocated after everything was destroyed",
              A.live_bytes, A.live_blocks);
    printf("%ld injected allocation failures, all refused cleanly\n", total_failures_injected);
    pthread_mutex_destroy(&A.lock);
    free(obj_text.data);
    free(small_obj.data);
    free(ply_ascii.data);
    free(ply_binary.data);
    return tt_test_finish();
}
