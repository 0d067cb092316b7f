/* Dynamic scenes (tt_scene_* edits, tt_accel_update): after every update
 * each structure passes tt_accel_check and agrees ray by ray with
 * bruteforce on the edited scene; the R-tree in the compact layout updates
 * in place (refit, deletion with condense, insertion), the others rebuild.
 * Covers deformation, removal + addition, whole triangles moved across the
 * scene, the empty scene, removing everything and adding again, id reuse,
 * bad ids and out-of-range edits (an error, nothing changed), stale
 * structures (TT_ERR_STALE) and a trace in flight (TT_ERR_BUSY). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "compare.h"
#include "io/scene.h"
#include "io/scene_guard.h"

static uint32_t rng = 12345u;
static uint32_t next_u32(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}
static float next_f(void) { return (float)(next_u32() >> 8) / 16777216.0f; }

typedef struct subject {
    const char *label;
    tt_build_options o;
    tt_accel *a;
} subject;

enum { NSUB = 7 };

static int make_subjects(subject *s)
{
    int n = 0;
    tt_build_options o;
    tt_build_options_default(&o);
    s[n++] = (subject){"rtree sah compact", o, NULL};
    o.rtree.build = TT_RTREE_BUILD_INSERT;
    s[n++] = (subject){"rtree insert compact M8", o, NULL};
    s[n - 1].o.rtree.M = 8;
    s[n - 1].o.rtree.m = 3;
    o.rtree.strategy = TT_RTREE_RRSTAR; /* the RR*-tree's insertion, built and updated */
    s[n++] = (subject){"rtree insert rrstar compact", o, NULL};
    tt_build_options_default(&o);
    o.rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
    o.rtree.M = 4;
    s[n++] = (subject){"rtree complete (rebuilds)", o, NULL};
    tt_build_options_default(&o);
    o.accel = "kdtree";
    s[n++] = (subject){"kdtree (rebuilds)", o, NULL};
    if (tt_test_has_accel("embree")) {
        tt_build_options_default(&o);
        o.accel = "embree";
        s[n++] = (subject){"embree (rebuilds)", o, NULL};
    }
    return n;
}

/* Update everything, check, compare with bruteforce on random rays. */
static void verify(tt_context *ctx, tt_scene *scene, tt_accel *bf, subject *s, int n,
                   const char *what, int frame)
{
    CHECK_OK(ctx, tt_accel_update(bf));
    for (int i = 0; i < n; i++) {
        tt_status st = tt_accel_update(s[i].a);
        CHECK_MSG(st == TT_OK, "%s frame %d, %s: update: %s", what, frame, s[i].label,
                  tt_context_last_error(ctx));
        st = tt_accel_check(s[i].a);
        CHECK_MSG(st == TT_OK, "%s frame %d, %s: check: %s", what, frame, s[i].label,
                  tt_context_last_error(ctx));
        size_t bad = tt_test_compare_random(scene, s[i].a, bf, 400, 77u + (uint32_t)frame);
        CHECK_MSG(bad == 0, "%s frame %d, %s: %zu rays disagree with bruteforce", what, frame,
                  s[i].label, bad);
    }
}

static void build_all(tt_context *ctx, tt_scene *scene, subject *s, int n, tt_accel **bf)
{
    *bf = tt_test_build_default(ctx, scene, "bruteforce");
    for (int i = 0; i < n; i++) REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &s[i].o, &s[i].a));
}

static void destroy_all(subject *s, int n, tt_accel *bf)
{
    for (int i = 0; i < n; i++) tt_accel_destroy(s[i].a);
    tt_accel_destroy(bf);
}

/* A random triangle near (c), of size about `size`. */
static void random_triangle(float *t, const float *c, float size)
{
    for (int k = 0; k < 9; k++) t[k] = c[k % 3] + (next_f() - 0.5f) * size;
}

static void frames_on_bunny(tt_context *ctx)
{
    tt_scene *scene = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    subject s[NSUB];
    const int n = make_subjects(s);
    tt_accel *bf;
    build_all(ctx, scene, s, n, &bf);
    CHECK(tt_accel_updates_in_place(s[0].a) == 1);
    CHECK(tt_accel_updates_in_place(s[3].a) == 0); /* the complete layout rebuilds */
    CHECK(tt_accel_updates_in_place(bf) == 0);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    const float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                             (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const size_t V = tt_scene_vertex_count(scene);
    float *base = malloc(V * 3 * sizeof(float)), *pos = malloc(V * 3 * sizeof(float));
    memcpy(base, scene->vertices, V * 3 * sizeof(float));

    /* deformation: every vertex moves (a wave along y), the dynembree way */
    for (int f = 1; f <= 6; f++) {
        for (size_t v = 0; v < V; v++) {
            const float *p = base + 3 * v;
            const float w = 0.002f * diag * sinf(0.7f * (float)f + 40.0f * p[1] / diag);
            pos[3 * v] = p[0] + w * (float)f * 0.2f;
            pos[3 * v + 1] = p[1];
            pos[3 * v + 2] = p[2];
        }
        CHECK_OK(ctx, tt_scene_move_vertices(scene, NULL, pos, V));
        verify(ctx, scene, bf, s, n, "deform", f);
    }
    /* a long deformation whose wave grows: the refit's cost estimate grows
     * past the envelope rebuild's trigger (rtree_vtable.c), the tree is
     * built again from 8 frames' boxes mid-run, and an edit after it makes
     * the pointer tree from the new records */
    for (int f = 7; f <= 48; f++) {
        for (size_t v = 0; v < V; v++) {
            const float *p = base + 3 * v;
            const float w = 0.002f * diag * sinf(0.7f * (float)f + 40.0f * p[1] / diag);
            pos[3 * v] = p[0] + w * (float)f;
            pos[3 * v + 1] = p[1];
            pos[3 * v + 2] = p[2];
        }
        CHECK_OK(ctx, tt_scene_move_vertices(scene, NULL, pos, V));
        if (f % 4 == 0 || f >= 30) verify(ctx, scene, bf, s, n, "long deform", f);
        else
            for (int i = 0; i < n; i++) CHECK_OK(ctx, tt_accel_update(s[i].a));
    }
    memcpy(pos, base, V * 3 * sizeof(float));
    CHECK_OK(ctx, tt_scene_move_vertices(scene, NULL, pos, V));
    verify(ctx, scene, bf, s, n, "long deform: back", 0);
    /* a few vertices moved far (few triangles: the jump path) */
    {
        uint32_t ids[5];
        float p[15];
        for (int i = 0; i < 5; i++) {
            ids[i] = next_u32() % (uint32_t)V;
            for (int k = 0; k < 3; k++) p[3 * i + k] = lo[k] + next_f() * (hi[k] - lo[k]);
        }
        CHECK_OK(ctx, tt_scene_move_vertices(scene, ids, p, 5));
        verify(ctx, scene, bf, s, n, "move few vertices", 0);
    }
    /* edits: 3% removed, 3% added (ids reused), some moved across the scene */
    const size_t T = tt_scene_triangle_count(scene);
    for (int f = 1; f <= 5; f++) {
        const size_t k = T * 3 / 100 + 1;
        uint32_t *ids = malloc(k * sizeof *ids);
        float *tri = malloc(k * 9 * sizeof(float));
        size_t m = 0;
        while (m < k) {
            uint32_t id = next_u32() % (uint32_t)tt_scene_triangle_count(scene);
            int dup = !tt_scene_triangle_alive(scene, id);
            for (size_t j = 0; j < m && !dup; j++) dup = ids[j] == id;
            if (!dup) ids[m++] = id;
        }
        CHECK_OK(ctx, tt_scene_remove_triangles(scene, ids, k));
        for (size_t j = 0; j < k; j++) {
            float c[3];
            for (int a = 0; a < 3; a++) c[a] = lo[a] + next_f() * (hi[a] - lo[a]);
            random_triangle(tri + 9 * j, c, 0.02f * diag);
        }
        uint32_t *got = malloc((k + 3) * sizeof *got);
        CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, k, got));
        /* the most recently removed ids come back first */
        CHECK(got[0] == ids[k - 1]);
        CHECK(tt_scene_triangle_count(scene) == T);
        /* whole triangles moved across the scene */
        for (size_t j = 0; j < 3; j++) {
            float c[3];
            for (int a = 0; a < 3; a++) c[a] = lo[a] + next_f() * (hi[a] - lo[a]);
            random_triangle(tri + 9 * j, c, 0.01f * diag);
        }
        CHECK_OK(ctx, tt_scene_set_triangles(scene, got, tri, 3));
        verify(ctx, scene, bf, s, n, "edits", f);
        free(ids);
        free(tri);
        free(got);
    }
    /* growth: new ids past the end */
    {
        float tri[9 * 40];
        for (int j = 0; j < 40; j++) {
            float c[3];
            for (int a = 0; a < 3; a++) c[a] = lo[a] + next_f() * (hi[a] - lo[a]);
            random_triangle(tri + 9 * j, c, 0.02f * diag);
        }
        uint32_t got[40];
        CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, 40, got));
        CHECK(got[0] == T && got[39] == T + 39);
        verify(ctx, scene, bf, s, n, "growth", 0);
    }
    /* deformations and edits in turn: a deformation leaves the kept
     * pointer tree's boxes to be refit by the next update that edits */
    for (int r = 1; r <= 3; r++) {
        const size_t V2 = tt_scene_vertex_count(scene);
        float *p2 = malloc(V2 * 3 * sizeof(float));
        memcpy(p2, scene->vertices, V2 * 3 * sizeof(float));
        for (size_t v = 0; v < V2; v++) p2[3 * v + 1] += 0.003f * diag * sinf((float)(v + r));
        CHECK_OK(ctx, tt_scene_move_vertices(scene, NULL, p2, V2));
        verify(ctx, scene, bf, s, n, "deform then edit: deform", r);
        uint32_t ids[4];
        size_t m = 0;
        while (m < 4) {
            uint32_t id = next_u32() % (uint32_t)tt_scene_triangle_count(scene);
            int dup = !tt_scene_triangle_alive(scene, id);
            for (size_t j = 0; j < m && !dup; j++) dup = ids[j] == id;
            if (!dup) ids[m++] = id;
        }
        float tri[4 * 9];
        for (size_t j = 0; j < 4; j++) {
            float c[3];
            for (int a = 0; a < 3; a++) c[a] = lo[a] + next_f() * (hi[a] - lo[a]);
            random_triangle(tri + 9 * j, c, 0.02f * diag);
        }
        CHECK_OK(ctx, tt_scene_remove_triangles(scene, ids, 4));
        CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, 4, NULL));
        verify(ctx, scene, bf, s, n, "deform then edit: edit", r);
        free(p2);
    }
    free(base);
    free(pos);
    destroy_all(s, n, bf);
    tt_scene_destroy(scene);
}

/* From nothing, to everything removed, and back. */
static void empty_and_back(tt_context *ctx)
{
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, NULL, 0, NULL, 0, &scene));
    subject s[NSUB];
    const int n = make_subjects(s);
    tt_accel *bf;
    build_all(ctx, scene, s, n, &bf);
    const size_t N = 300;
    float *tri = malloc(N * 9 * sizeof(float));
    uint32_t *ids = malloc(N * sizeof *ids);
    for (size_t j = 0; j < N; j++) {
        float c[3] = {next_f() * 10, next_f() * 10, next_f() * 10};
        random_triangle(tri + 9 * j, c, 1.0f);
    }
    /* one at a time first (growth), then the rest at once */
    for (size_t j = 0; j < 20; j++) {
        CHECK_OK(ctx, tt_scene_add_triangles(scene, tri + 9 * j, 1, ids + j));
        CHECK(ids[j] == j);
        if (j % 4 == 3) verify(ctx, scene, bf, s, n, "grow one by one", (int)j);
    }
    CHECK_OK(ctx, tt_scene_add_triangles(scene, tri + 9 * 20, N - 20, ids + 20));
    verify(ctx, scene, bf, s, n, "filled", 0);
    /* everything removed: an empty tree, every ray misses */
    CHECK_OK(ctx, tt_scene_remove_triangles(scene, ids, N));
    CHECK(tt_scene_live_triangle_count(scene) == 0);
    verify(ctx, scene, bf, s, n, "all removed", 0);
    tt_ray r = {{5, 5, -20}, 0, {0, 0, 1}, INFINITY};
    tt_hit h;
    CHECK_OK(ctx, tt_intersect1(s[0].a, &r, &h));
    CHECK(h.prim == TT_INVALID_ID);
    /* added again: the ids come back (last removed first) */
    CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, N, ids));
    CHECK(ids[0] == N - 1 && tt_scene_triangle_count(scene) == N);
    verify(ctx, scene, bf, s, n, "re-added", 0);
    /* removed in halves with updates between (condense over several frames) */
    CHECK_OK(ctx, tt_scene_remove_triangles(scene, ids, N / 2));
    verify(ctx, scene, bf, s, n, "half removed", 0);
    CHECK_OK(ctx, tt_scene_remove_triangles(scene, ids + N / 2, N - N / 2 - 1));
    verify(ctx, scene, bf, s, n, "one left", 0);
    free(tri);
    free(ids);
    destroy_all(s, n, bf);
    tt_scene_destroy(scene);
}

/* Triangles so large that their boxes' areas overflow a float, added to
 * a built scene of triangles of size base: every entry's growth in the SAH
 * insertion search is then +inf (or NaN, inf - inf, where the entries'
 * own areas overflow too: base huge), and the choice must stay among the
 * node's entries (its spare SIMD lanes hold +inf). Embree is left out: it
 * drops triangles beyond its coordinate range. The test draws from its own
 * copy of the random state, so the other tests see the numbers they did. */
static void huge_triangles(tt_context *ctx, float base)
{
    const uint32_t rng_before = rng;
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, NULL, 0, NULL, 0, &scene));
    subject s[NSUB];
    int n = make_subjects(s);
    if (s[n - 1].o.accel && strcmp(s[n - 1].o.accel, "embree") == 0) n--;
    const size_t N = 600, H = 24;
    float *tri = malloc(N * 9 * sizeof(float));
    uint32_t *ids = malloc(N * sizeof *ids);
    if (!tri || !ids) exit(1);
    for (size_t j = 0; j < N; j++) {
        float c[3] = {next_f() * 10, next_f() * 10, next_f() * 10};
        random_triangle(tri + 9 * j, c, base);
    }
    CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, N, ids));
    tt_accel *bf;
    build_all(ctx, scene, s, n, &bf);
    verify(ctx, scene, bf, s, n, "before huge", 0);
    for (size_t j = 0; j < H; j++) {
        const float c[3] = {next_f() * 10, next_f() * 10, next_f() * 10};
        random_triangle(tri + 9 * j, c, 1e25f);
    }
    CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, H, ids));
    verify(ctx, scene, bf, s, n, "huge added", 0);
    CHECK_OK(ctx, tt_scene_remove_triangles(scene, ids, H / 2));
    verify(ctx, scene, bf, s, n, "huge half removed", 0);
    free(tri);
    free(ids);
    destroy_all(s, n, bf);
    tt_scene_destroy(scene);
    rng = rng_before;
}

/* One statistic of an accel (NAN: not reported). */
typedef struct stat_find {
    const char *key;
    double value;
} stat_find;
static void stat_cb(void *user, const char *key, double value)
{
    stat_find *f = user;
    if (strcmp(key, f->key) == 0) f->value = value;
}
static double stat_of(const tt_accel *a, const char *key)
{
    stat_find f = {key, NAN};
    (void)tt_accel_statistics(a, stat_cb, &f);
    return f.value;
}

/* The slack layout (rtree/update/rtree_dyn.h) over many small frames:
 * groups and regions freed and reused, compaction when fragmented, and
 * between compactions only the touched records written: checked and
 * compared every frame, and the in-place path must carry most frames. */
static void edits_in_place(tt_context *ctx)
{
    tt_scene *scene = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    subject s[3];
    tt_build_options o;
    tt_build_options_default(&o);
    s[0] = (subject){"rtree sah compact", o, NULL};
    o.rtree.build = TT_RTREE_BUILD_INSERT;
    o.rtree.M = 8;
    o.rtree.m = 3;
    s[1] = (subject){"rtree insert compact M8", o, NULL};
    tt_build_options_default(&o);
    o.rtree.M = 5;
    o.rtree.m = 2;
    s[2] = (subject){"rtree sah compact M5", o, NULL};
    const int n = 3;
    tt_accel *bf;
    build_all(ctx, scene, s, n, &bf);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    const size_t T = tt_scene_triangle_count(scene);
    const int frames = 40;
    for (int f = 1; f <= frames; f++) {
        /* 1-2% replaced, about half near where they were, half anywhere */
        const size_t k = T / 100 + 1 + (size_t)(f % 2) * (T / 100);
        uint32_t ids[64], got[64];
        float tri[64 * 9];
        size_t m = 0;
        while (m < k && m < 64) {
            uint32_t id = next_u32() % (uint32_t)tt_scene_triangle_count(scene);
            int dup = !tt_scene_triangle_alive(scene, id);
            for (size_t j = 0; j < m && !dup; j++) dup = ids[j] == id;
            if (!dup) ids[m++] = id;
        }
        for (size_t j = 0; j < m; j++) {
            float c[3];
            const float *old = scene->tri + 9 * (size_t)ids[j];
            for (int a = 0; a < 3; a++)
                c[a] = j % 2 ? lo[a] + next_f() * (hi[a] - lo[a]) : old[a] + 0.01f * next_f();
            random_triangle(tri + 9 * j, c, 0.01f * (hi[0] - lo[0]));
        }
        CHECK_OK(ctx, tt_scene_remove_triangles(scene, ids, m));
        if (f % 7 == 0) verify(ctx, scene, bf, s, n, "in place: removed only", f);
        CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, m, got));
        verify(ctx, scene, bf, s, n, "in place: edits", f);
    }
    for (int i = 0; i < n; i++) {
        const double comp = stat_of(s[i].a, "update_compactions");
        const double recs = stat_of(s[i].a, "update_records_written");
        const double nodes = stat_of(s[i].a, "nodes");
        CHECK_MSG(comp >= 1 && comp < frames / 2, "%s: %g compactions in %d frames", s[i].label,
                  comp, frames);
        CHECK_MSG(recs > 0 && !(recs >= nodes), "%s: the last frame wrote %g records of %g",
                  s[i].label, recs, nodes);
    }
    /* an updated tree (leaves of one triangle after lazy deletions) saved
     * and loaded: it passes the check and traces as before */
    {
        char path[256];
        snprintf(path, sizeof path, "/tmp/tt_dynamic_%d.tta", (int)getpid());
        tt_accel *loaded = NULL;
        CHECK_OK(ctx, tt_accel_save(s[0].a, path, "bunny"));
        CHECK_OK(ctx, tt_accel_load(ctx, scene, path, TT_ISA_AUTO, &loaded));
        if (loaded) {
            CHECK_OK(ctx, tt_accel_check(loaded));
            CHECK(tt_test_compare_random(scene, loaded, bf, 400, 99u) == 0);
            tt_accel_destroy(loaded);
        }
        remove(path);
    }
    /* everything removed and back, through the in-place path */
    uint32_t *all = malloc(T * sizeof *all);
    size_t live = 0;
    for (uint32_t id = 0; id < tt_scene_triangle_count(scene); id++)
        if (tt_scene_triangle_alive(scene, id)) all[live++] = id;
    float *tri = malloc(live * 9 * sizeof(float));
    for (size_t j = 0; j < live; j++) memcpy(tri + 9 * j, scene->tri + 9 * (size_t)all[j], 36);
    CHECK_OK(ctx, tt_scene_remove_triangles(scene, all, live));
    verify(ctx, scene, bf, s, n, "in place: all removed", 0);
    CHECK_OK(ctx, tt_scene_add_triangles(scene, tri, live, all));
    verify(ctx, scene, bf, s, n, "in place: all back", 0);
    free(all);
    free(tri);
    destroy_all(s, n, bf);
    tt_scene_destroy(scene);
}

/* Bad input: a clear error and nothing changed. */
static void bad_edits(tt_context *ctx)
{
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    const uint32_t idx[] = {0, 1, 2, 1, 3, 2};
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 4, idx, 2, &scene));
    tt_accel *a = tt_test_build_default(ctx, scene, "rtree");
    float before[18];
    tt_scene_triangle(scene, 0, before);
    tt_scene_triangle(scene, 1, before + 9);
    const uint64_t ver = tt_scene_version(scene);
    uint32_t bad_id = 7, dup[2] = {1, 1};
    CHECK(tt_scene_remove_triangles(scene, &bad_id, 1) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "ids[0] = 7") != NULL);
    CHECK(tt_scene_remove_triangles(scene, dup, 2) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "twice") != NULL);
    float nan_tri[9] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
    uint32_t one = 1;
    CHECK(tt_scene_set_triangles(scene, &one, nan_tri, 1) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_scene_add_triangles(scene, nan_tri, 1, NULL) == TT_ERR_INVALID_ARGUMENT);
    uint32_t vbad = 4;
    float p[3] = {1, 2, 3};
    CHECK(tt_scene_move_vertices(scene, &vbad, p, 1) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "not a vertex") != NULL);
    CHECK(tt_scene_move_vertices(scene, NULL, p, 5) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_scene_remove_triangles(scene, NULL, 1) == TT_ERR_INVALID_ARGUMENT);
    /* a removed id is not an id to remove or move again */
    uint32_t zero = 0;
    CHECK_OK(ctx, tt_scene_remove_triangles(scene, &zero, 1));
    CHECK(tt_scene_remove_triangles(scene, &zero, 1) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "was removed") != NULL);
    CHECK(tt_scene_set_triangles(scene, &zero, before, 1) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_scene_version(scene) == ver + 1);
    float now[9];
    tt_scene_triangle(scene, 1, now);
    CHECK(memcmp(now, before + 9, sizeof now) == 0);
    /* stale: the structure refuses to trace until updated */
    tt_ray r = {{0.2f, 0.2f, -1}, 0, {0, 0, 1}, INFINITY};
    tt_hit h;
    CHECK(tt_intersect1(a, &r, &h) == TT_ERR_STALE);
    CHECK(tt_intersect(a, &r, 1, &h, NULL, NULL) == TT_ERR_STALE);
    CHECK_OK(ctx, tt_accel_update(a));
    CHECK_OK(ctx, tt_intersect1(a, &r, &h));
    CHECK(h.prim == TT_INVALID_ID); /* triangle 0 is gone, 1 is not under (0.2, 0.2) */
    /* busy: a trace in flight (held by hand) refuses edits and updates */
    CHECK(tt_scene_trace_enter(scene));
    CHECK(tt_scene_add_triangles(scene, before, 1, NULL) == TT_ERR_BUSY);
    CHECK(tt_accel_update(a) == TT_ERR_BUSY); /* even with nothing to do */
    tt_scene_trace_leave(scene);
    CHECK_OK(ctx, tt_scene_add_triangles(scene, before, 1, NULL));
    CHECK(tt_scene_trace_enter(scene));
    CHECK(tt_accel_update(a) == TT_ERR_BUSY);
    tt_scene_trace_leave(scene);
    CHECK(tt_scene_write_enter(scene)); /* an edit in flight refuses traces */
    CHECK_OK(ctx, tt_accel_update(a) == TT_ERR_BUSY ? TT_OK : TT_ERR_INTERNAL);
    tt_scene_write_leave(scene);
    CHECK_OK(ctx, tt_accel_update(a));
    CHECK(tt_scene_write_enter(scene));
    CHECK(tt_intersect1(a, &r, &h) == TT_ERR_BUSY);
    tt_scene_write_leave(scene);
    CHECK_OK(ctx, tt_intersect1(a, &r, &h));
    CHECK(h.prim == 0); /* the re-added triangle took id 0 back */
    CHECK_OK(ctx, tt_accel_check(a));
    tt_accel_destroy(a);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    bad_edits(ctx);
    empty_and_back(ctx);
    huge_triangles(ctx, 1.0f);
    huge_triangles(ctx, 1e25f);
    frames_on_bunny(ctx);
    edits_in_place(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
