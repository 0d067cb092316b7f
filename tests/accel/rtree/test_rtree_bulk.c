/* The bulk loaders (STR, Hilbert, SAH), white box and black box: the radix
 * sort against a reference sort, the Hilbert keys (a curve: consecutive
 * keys are neighbouring cells), the level chunking (m..M); every loader x
 * (m, M) with M in {4, 8, 16}: the pointer tree's invariants
 * (rt_builder_check), the expected height and leaf fill, the packed tree's
 * check, and rays against bruteforce, on real scenes and on edge cases
 * (0, 1, M, M+1, 2M+1, M^2+1 triangles, identical triangles, zero-area
 * triangles, all box centres equal, a planar grid); the same tree for 1 and
 * 2 threads; the SAH loader's level form packed into the same compact
 * layout as its pointer tree; the SAH loader's tree cheaper (SAH cost) than
 * the others';
 * option validation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "accel/rtree/rtree.h"
#include "accel/rtree/build/rtree_bulk.h"
#include "compare.h"
#include "io/scene.h"
#include "rtree_test.h"

static const char *const build_names[] = {"insert", "str", "hilbert", "sah"};
static const rt_mm bulk_mm[] = {{2, 4}, {2, 8}, {4, 8}, {3, 16}, {8, 16}};
#define BULK_MM ((int)(sizeof bulk_mm / sizeof bulk_mm[0]))

static uint32_t lcg(uint32_t *x)
{
    *x = *x * 1664525u + 1013904223u;
    return *x >> 8;
}

/* ------------------------------------------------------------ radix sort */

typedef struct pair {
    uint64_t key;
    uint32_t val;
} pair;

static int pair_cmp(const void *a, const void *b)
{
    const pair *p = a, *q = b;
    if (p->key != q->key) return p->key < q->key ? -1 : 1;
    return p->val < q->val ? -1 : p->val > q->val; /* vals start in order: stable */
}

static void test_radix(tt_context *ctx)
{
    static const size_t sizes[] = {0, 1, 5, 32, 33, 1000, 65535, 70001, 200000};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (int bits = 32; bits <= 63; bits += 31)
            for (int threads = 1; threads <= 3; threads++) {
                const size_t n = sizes[si];
                uint64_t *k = malloc((n + 1) * sizeof *k), *tk = malloc((n + 1) * sizeof *tk);
                uint32_t *v = malloc((n + 1) * sizeof *v), *tv = malloc((n + 1) * sizeof *tv);
                pair *ref = malloc((n + 1) * sizeof *ref);
                if (!k || !tk || !v || !tv || !ref) exit(1);
                uint32_t x = (uint32_t)(n * 7 + (size_t)bits);
                for (size_t i = 0; i < n; i++) {
                    /* few distinct keys in the small sizes: many ties */
                    uint64_t key = ((uint64_t)lcg(&x) << 40) ^ ((uint64_t)lcg(&x) << 16) ^ lcg(&x);
                    if (n < 2000) key %= 17;
                    key &= bits == 32 ? 0xFFFFFFFFull : 0x7FFFFFFFFFFFFFFFull;
                    k[i] = key;
                    v[i] = (uint32_t)i;
                    ref[i].key = key;
                    ref[i].val = (uint32_t)i;
                }
                qsort(ref, n, sizeof *ref, pair_cmp);
                CHECK_OK(ctx, rt_radix_sort(ctx, k, v, tk, tv, n, bits, threads));
                size_t bad = 0;
                for (size_t i = 0; i < n; i++) bad += k[i] != ref[i].key || v[i] != ref[i].val;
                CHECK_MSG(bad == 0, "radix sort n=%zu bits=%d threads=%d: %zu entries differ", n,
                          bits, threads, bad);
                free(k), free(tk), free(v), free(tv), free(ref);
            }
}

/* --------------------------------------------------------------- Hilbert */

static void test_hilbert(void)
{
    for (int bits = 1; bits <= 4; bits++) {
        const uint32_t side = 1u << bits, cells = side * side * side;
        uint32_t *at = malloc(cells * sizeof *at); /* cell of each key */
        uint8_t *seen = calloc(cells, 1);
        if (!at || !seen) exit(1);
        int bad = 0;
        for (uint32_t c = 0; c < cells; c++) {
            uint32_t x = c % side, y = c / side % side, z = c / (side * side);
            uint64_t key = rt_hilbert_key(x, y, z, bits);
            if (key >= cells || seen[key]++) {
                bad++;
                continue;
            }
            at[key] = c;
        }
        CHECK_MSG(bad == 0, "Hilbert keys of %u bits are not a bijection onto 0..%u", bits,
                  cells - 1);
        for (uint32_t key = 1; key < cells && !bad; key++) {
            uint32_t a = at[key - 1], b = at[key], d = 0;
            for (uint32_t s = 1; s < cells; s *= side) {
                int da = (int)(a / s % side) - (int)(b / s % side);
                d += (uint32_t)(da < 0 ? -da : da);
            }
            if (d != 1) bad++;
        }
        CHECK_MSG(bad == 0, "Hilbert curve of %u bits: consecutive keys are not neighbours", bits);
        free(at);
        free(seen);
    }
    /* the full precision the loader uses stays below 2^63 */
    CHECK(rt_hilbert_key((1u << 21) - 1, 0, 0, 21) < ((uint64_t)1 << 63));
}

/* --------------------------------------------------------------- chunking */

static void test_chunk(void)
{
    uint32_t start[200];
    for (int q = 0; q < BULK_MM; q++)
        for (uint32_t n = 0; n < 150; n++) {
            const int m = bulk_mm[q].m, M = bulk_mm[q].M;
            const uint32_t g = rt_bulk_groups(n, M);
            rt_bulk_chunk(n, m, M, start);
            int bad = start[0] != 0 || start[g] != n || g != (n == 0 ? 1 : (n + M - 1) / M);
            for (uint32_t j = 0; j < g; j++) {
                uint32_t s = start[j + 1] - start[j];
                if (s > (uint32_t)M || (g > 1 && s < (uint32_t)m)) bad = 1;
            }
            CHECK_MSG(!bad, "chunking %u entries for m=%d M=%d", n, m, M);
        }
}

/* ------------------------------------------------------------ white box */

static float *triangle_boxes(const tt_scene *scene)
{
    const uint32_t T = (uint32_t)scene->triangle_count;
    float *box = malloc(((size_t)T + 1) * 6 * sizeof *box);
    if (!box) exit(1);
    for (uint32_t i = 0; i < T; i++)
        for (int k = 0; k < 3; k++) {
            const float *v = scene->tri + 9 * (size_t)i;
            box[6 * i + k] = fminf(fminf(v[k], v[3 + k]), v[6 + k]);
            box[6 * i + k + 3] = fmaxf(fmaxf(v[k], v[3 + k]), v[6 + k]);
        }
    return box;
}

/* The default build's path: the SAH loader's level form packed straight
 * into the compact layout gives the same bytes as its pointer tree packed
 * by rtc_pack. */
static void level_form_same(tt_context *ctx, const rt_builder *b, const tt_rtree_options *o,
                            const float *box, const tt_scene *scene, const char *what)
{
    const uint32_t T = (uint32_t)scene->triangle_count;
    rtc_tree a, c;
    memset(&a, 0, sizeof a);
    memset(&c, 0, sizeof c);
    rt_bulk_levels lv;
    tt_status st = rtc_pack(ctx, b, scene->tri, &a);
    if (st == TT_OK) st = rt_bulk_sah_levels(&lv, ctx, o, box, T);
    else memset(&lv, 0, sizeof lv);
    if (st == TT_OK) st = rtc_pack_levels(ctx, &lv, scene->tri, &c);
    CHECK_MSG(st == TT_OK, "%s: level form m=%d M=%d: %s", what, o->m, o->M,
              tt_context_last_error(ctx));
    if (st == TT_OK) {
        const int same = a.c.nodes == c.c.nodes && a.c.blocks == c.c.blocks &&
                         a.c.words == c.c.words && a.c.height == c.c.height &&
                         memcmp(a.c.node, c.c.node,
                                (size_t)a.c.nodes * a.c.words * sizeof(float)) == 0 &&
                         memcmp(a.c.block, c.c.block, (size_t)a.c.blocks * sizeof(tt_tri_block)) == 0;
        CHECK_MSG(same, "%s: level form m=%d M=%d: a layout other than rtc_pack's", what, o->m,
                  o->M);
    }
    rt_bulk_levels_free(ctx, &lv);
    rtc_free(ctx, &a);
    rtc_free(ctx, &c);
}

/* The pointer tree of every loader: its invariants, and its shape: the
 * smallest height for SAH, and full leaves (M each, the last two evened)
 * for STR and Hilbert. */
static void white_box(tt_context *ctx, const tt_scene *scene, const char *what)
{
    const uint32_t T = (uint32_t)scene->triangle_count;
    float *box = triangle_boxes(scene);
    for (int bld = TT_RTREE_BUILD_STR; bld <= TT_RTREE_BUILD_SAH; bld++)
        for (int q = 0; q < BULK_MM; q++) {
            tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, bulk_mm[q].m,
                                            bulk_mm[q].M);
            o.rtree.build = (tt_rtree_build)bld;
            const int M = o.rtree.M, m = o.rtree.m;
            rt_builder b;
            tt_status st = rt_bulk_build(&b, ctx, &o.rtree, box, T);
            if (st == TT_OK) st = rt_builder_check(&b);
            CHECK_MSG(st == TT_OK, "%s: %s m=%d M=%d: %s", what, build_names[bld], m, M,
                      tt_context_last_error(ctx));
            if (st == TT_OK) {
                int L = 0;
                for (uint64_t cap = (uint64_t)M; cap < T; cap *= (uint64_t)M) L++;
                int level = b.hdr[b.root].level;
                CHECK_MSG(level == L, "%s: %s m=%d M=%d: root on level %d, the smallest is %d",
                          what, build_names[bld], m, M, level, L);
                if (bld == TT_RTREE_BUILD_SAH && T > (uint32_t)M)
                    level_form_same(ctx, &b, &o.rtree, box, scene, what);
                if (bld != TT_RTREE_BUILD_SAH) {
                    uint32_t short_leaves = 0;
                    for (uint32_t n = 0; n < b.node_count; n++)
                        short_leaves += b.hdr[n].level == 0 && b.hdr[n].count < M;
                    CHECK_MSG(short_leaves <= 2, "%s: %s m=%d M=%d: %u leaves not full", what,
                              build_names[bld], m, M, short_leaves);
                }
            }
            rt_builder_free(&b);
        }
    free(box);
}

/* ------------------------------------------------------------ black box */

/* Every loader x (m, M), each with one traversal (cycling), built, checked
 * and compared with bruteforce on random rays and rays aimed at triangles. */
static void rays_all(tt_context *ctx, const tt_scene *scene, const char *what, uint32_t nrays)
{
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    const uint32_t T = (uint32_t)scene->triangle_count;
    tt_ray *aimed = malloc(((size_t)nrays + 1) * sizeof *aimed);
    if (!aimed) exit(1);
    uint32_t x = 99;
    for (uint32_t i = 0; i < nrays && T > 0; i++) {
        /* from a random point at a random triangle's centroid */
        const float *v = scene->tri + 9 * (size_t)(lcg(&x) % T);
        tt_ray *r = &aimed[i];
        float lo[3], hi[3];
        tt_scene_bounds(scene, lo, hi);
        for (int k = 0; k < 3; k++) {
            float e = hi[k] - lo[k] + 1.0f;
            r->org[k] = lo[k] - e + 3.0f * e * (float)(lcg(&x) & 0xFFFF) / 65536.0f;
            r->dir[k] = (v[k] + v[3 + k] + v[6 + k]) / 3.0f - r->org[k];
        }
        if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) r->dir[2] = 1.0f;
        r->tmin = 0.0f;
        r->tmax = i % 4 == 0 ? 0.5f : INFINITY;
    }
    for (int bld = TT_RTREE_BUILD_STR; bld <= TT_RTREE_BUILD_SAH; bld++)
        for (int q = 0; q < BULK_MM; q++) {
            tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, (bld + q) % 4, bulk_mm[q].m,
                                            bulk_mm[q].M);
            o.rtree.build = (tt_rtree_build)bld;
            tt_accel *a = rt_build_checked(ctx, scene, &o);
            if (!a) continue;
            size_t bad = tt_test_compare_random(scene, a, bf, nrays, 11u);
            if (T > 0) bad += tt_test_compare_rays(a, bf, aimed, nrays);
            CHECK_MSG(bad == 0, "%s, build %s %s: %zu rays disagree", what, build_names[bld],
                      rt_describe(&o), bad);
            tt_accel_destroy(a);
        }
    free(aimed);
    tt_accel_destroy(bf);
}

static tt_scene *make_scene(tt_context *ctx, const float *v, size_t nv, const uint32_t *idx,
                            size_t nt)
{
    tt_scene *s = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, nv, idx, nt, &s));
    return s;
}

/* n random small triangles in the unit cube (n <= 4096). */
static tt_scene *random_scene(tt_context *ctx, uint32_t n, uint32_t seed)
{
    static float v[3 * 3 * 4096];
    static uint32_t idx[3 * 4096];
    for (uint32_t t = 0; t < n; t++) {
        float c[3];
        for (int k = 0; k < 3; k++) c[k] = (float)(lcg(&seed) & 0xFFFF) / 65536.0f;
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                v[9 * t + 3 * j + k] = c[k] + 0.1f * ((float)(lcg(&seed) & 0xFFFF) / 65536.0f - 0.5f);
        for (int j = 0; j < 3; j++) idx[3 * t + j] = 3 * t + (uint32_t)j;
    }
    return make_scene(ctx, v, 3 * (size_t)n, idx, n);
}

static void both(tt_context *ctx, tt_scene *s, const char *what)
{
    white_box(ctx, s, what);
    rays_all(ctx, s, what, 200);
    tt_scene_destroy(s);
}

static void edge_cases(tt_context *ctx)
{
    char what[96];
    /* counts around every M: 0, 1, M, M+1, 2M+1, M^2+1 */
    static const uint32_t counts[] = {0, 1, 4, 5, 8, 9, 16, 17, 33, 65, 257};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        snprintf(what, sizeof what, "%u random triangles", counts[i]);
        both(ctx, random_scene(ctx, counts[i], 3u + (uint32_t)i), what);
    }
    /* identical triangles: all boxes and centres equal */
    const float tv[] = {0, 0, 0, 1, 0, 0, 0, 1, 0.5f};
    uint32_t idx[3 * 300];
    for (int i = 0; i < 300; i++) idx[3 * i] = 0, idx[3 * i + 1] = 1, idx[3 * i + 2] = 2;
    both(ctx, make_scene(ctx, tv, 3, idx, 17), "17 identical triangles");
    both(ctx, make_scene(ctx, tv, 3, idx, 300), "300 identical triangles");
    /* different triangles whose boxes share one centre (the origin) */
    float cv[3 * 3 * 200];
    uint32_t cidx[3 * 200];
    for (int t = 0; t < 200; t++) {
        float s = 0.05f + 0.01f * (float)t, r = (float)(t % 7) / 7.0f;
        const float tri[9] = {-s, -s, -s, s, s, s, s * r, -s * r, s * (1.0f - r)};
        memcpy(cv + 9 * t, tri, sizeof tri);
        for (int j = 0; j < 3; j++) cidx[3 * t + j] = 3 * (uint32_t)t + (uint32_t)j;
    }
    both(ctx, make_scene(ctx, cv, 600, cidx, 200), "200 triangles, one box centre");
    /* zero-area triangles (points, segments) mixed with real ones */
    const float zv[] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 0, 1, 0, 1, 0, 0, 3, 3, 3};
    uint32_t zidx[3 * 120];
    static const uint32_t zpat[18] = {0, 0, 0, 0, 1, 2, 0, 3, 4, 1, 1, 1, 5, 5, 2, 0, 1, 5};
    for (int i = 0; i < 120; i++)
        for (int j = 0; j < 3; j++) zidx[3 * i + j] = zpat[(3 * i + j) % 18];
    both(ctx, make_scene(ctx, zv, 6, zidx, 120), "zero-area triangles");
    /* a planar axis-aligned grid: every box flat */
    float gv[3 * 17 * 17];
    uint32_t gidx[6 * 16 * 16];
    for (int y = 0; y <= 16; y++)
        for (int xg = 0; xg <= 16; xg++) {
            float *p = gv + 3 * (y * 17 + xg);
            p[0] = (float)xg, p[1] = (float)y, p[2] = 0.0f;
        }
    for (int y = 0, t = 0; y < 16; y++)
        for (int xg = 0; xg < 16; xg++, t += 2) {
            uint32_t a = (uint32_t)(y * 17 + xg), b = a + 1, c = a + 17, d = c + 1;
            const uint32_t q[6] = {a, b, d, a, d, c};
            memcpy(gidx + 3 * t, q, sizeof q);
        }
    both(ctx, make_scene(ctx, gv, 17 * 17, gidx, 512), "planar grid");
}

/* ------------------------------------------------------ determinism */

/* The packed tree built with 1 and with 2 threads: the same arrays. The
 * conference (331179 triangles) is past every parallel threshold
 * (RT_BULK_PARALLEL_MIN: radix sort, STR slabs, Hilbert keys, the leaf
 * level's packing at M = 4, SAH tasks). */
static void test_threads(const tt_scene *scene1, const tt_scene *scene2, tt_context *c1,
                         tt_context *c2)
{
    for (int bld = TT_RTREE_BUILD_STR; bld <= TT_RTREE_BUILD_SAH; bld++)
        for (int M = 4; M <= 8; M += 4) {
            tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, M);
            o.rtree.build = (tt_rtree_build)bld;
            tt_accel *a = rt_build_checked(c1, scene1, &o), *b = rt_build_checked(c2, scene2, &o);
            if (a && b) {
                const rt_tree *x = a->impl, *y = b->impl;
                int same = x->p.slots == y->p.slots && x->box_floats == y->box_floats &&
                           x->p.triangles == y->p.triangles &&
                           !memcmp(x->box, y->box, x->box_floats * sizeof(float)) &&
                           !memcmp(x->prim, y->prim, x->p.triangles * sizeof(uint32_t)) &&
                           !memcmp(x->count, y->count, x->p.delta[0]) &&
                           !memcmp(x->leaf_start, y->leaf_start,
                                   ((size_t)x->p.leaf_slots + 1) * sizeof(uint32_t));
                CHECK_MSG(same, "build %s M=%d: 1 and 2 threads give different trees",
                          build_names[bld], M);
            }
            tt_accel_destroy(a);
            tt_accel_destroy(b);
        }
}

/* ------------------------------------------------------------ quality */

typedef struct stat_get {
    double sah, leaf_fill, interior_fill, triangles, leaves;
} stat_get;

static void get_stats(void *user, const char *key, double value)
{
    stat_get *g = user;
    if (!strcmp(key, "sah_cost")) g->sah = value;
    else if (!strcmp(key, "leaf_fill")) g->leaf_fill = value;
    else if (!strcmp(key, "interior_fill")) g->interior_fill = value;
    else if (!strcmp(key, "triangles")) g->triangles = value;
    else if (!strcmp(key, "leaves")) g->leaves = value;
}

/* On the full bunny at M = 4: the SAH loader's tree has the least SAH cost
 * of all builders (measured: about half of insertion's), STR and Hilbert
 * have full leaves; the fill statistics agree with the counts. */
static void test_quality(tt_context *ctx, const tt_scene *scene)
{
    stat_get g[4];
    for (int bld = 0; bld < 4; bld++) {
        tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
        o.rtree.build = (tt_rtree_build)bld;
        memset(&g[bld], 0, sizeof g[bld]);
        tt_accel *a = rt_build_checked(ctx, scene, &o);
        if (a) CHECK_OK(ctx, tt_accel_statistics(a, get_stats, &g[bld]));
        tt_accel_destroy(a);
        CHECK_MSG(g[bld].leaves > 0 &&
                      fabs(g[bld].leaf_fill * g[bld].leaves - g[bld].triangles) < 1e-3,
                  "build %s: leaf_fill %g x leaves %g != triangles %g", build_names[bld],
                  g[bld].leaf_fill, g[bld].leaves, g[bld].triangles);
        CHECK_MSG(g[bld].interior_fill >= 2.0 && g[bld].interior_fill <= 4.0,
                  "build %s: interior_fill %g", build_names[bld], g[bld].interior_fill);
    }
    for (int bld = 0; bld < 3; bld++)
        CHECK_MSG(g[TT_RTREE_BUILD_SAH].sah < g[bld].sah, "SAH cost: sah %g, %s %g",
                  g[TT_RTREE_BUILD_SAH].sah, build_names[bld], g[bld].sah);
    CHECK(g[TT_RTREE_BUILD_STR].leaf_fill > 3.99 && g[TT_RTREE_BUILD_HILBERT].leaf_fill > 3.99);
}

static void test_validation(tt_context *ctx, const tt_scene *scene)
{
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
    o.rtree.build = (tt_rtree_build)9;
    tt_accel *a = NULL;
    tt_status st = tt_accel_build(ctx, scene, &o, &a);
    CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT && !a && strstr(tt_context_last_error(ctx), "build"),
              "build 9: %s: %s", tt_strerror(st), tt_context_last_error(ctx));
    tt_accel_destroy(a);
    /* the (m, M) rules hold for the bulk loaders too */
    o.rtree.build = TT_RTREE_BUILD_SAH;
    o.rtree.m = 3;
    st = tt_accel_build(ctx, scene, &o, &a);
    CHECK(st == TT_ERR_INVALID_ARGUMENT && !a);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    test_radix(ctx);
    test_hilbert();
    test_chunk();
    edge_cases(ctx);
    tt_scene *bunny4 = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    tt_scene *cornell = tt_test_load_scene(ctx, "cornell_box.obj");
    white_box(ctx, bunny4, "bunny res4");
    white_box(ctx, cornell, "cornell");
    rays_all(ctx, bunny4, "bunny res4", 2000);
    rays_all(ctx, cornell, "cornell", 2000);
    test_validation(ctx, cornell);

    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = 1;
    tt_context *c1 = NULL, *c2 = NULL;
    REQUIRE_OK(ctx, tt_context_create(&co, &c1));
    co.threads = 2;
    REQUIRE_OK(ctx, tt_context_create(&co, &c2));
    tt_scene *conf1 = tt_test_load_scene(c1, "conference.ply");
    tt_scene *conf2 = tt_test_load_scene(c2, "conference.ply");
    CHECK(tt_scene_triangle_count(conf1) >= RT_BULK_PARALLEL_MIN);
    test_threads(conf1, conf2, c1, c2);
    tt_scene_destroy(conf1);
    tt_scene_destroy(conf2);
    tt_scene *bunny2 = tt_test_load_scene(c2, "bun_zipper.ply");
    white_box(c2, bunny2, "bunny");
    test_quality(c2, bunny2);
    tt_scene_destroy(bunny2);
    tt_context_destroy(c1);
    tt_context_destroy(c2);
    tt_scene_destroy(bunny4);
    tt_scene_destroy(cornell);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
