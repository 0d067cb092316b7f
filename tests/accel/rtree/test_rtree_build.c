/* R-tree construction: every invariant (tt_accel_check) after builds with
 * every strategy, with and without forced reinsert (far and close), both
 * splits and several (m, M); the pointer tree's invariants after every
 * single insertion (white box); the statistics; option validation. */
#include <math.h>
#include <string.h>

#include "accel/rtree/rtree.h"
#include "accel/rtree/build/rtree_build.h"
#include "io/scene.h"
#include "rtree_test.h"

/* Structural invariants on a small real scene, the full option matrix. */
static void test_matrix(tt_context *ctx, const tt_scene *scene)
{
    for (int s = 0; s < 5; s++)
        for (int mm = 0; mm < RT_MM_COUNT; mm++)
            for (int variant = 0; variant < 4; variant++)
                for (int split = 0; split < 2; split++) {
                    tt_build_options o = rt_options(s, TT_RTREE_AUTO, rt_mm_list[mm].m,
                                                    rt_mm_list[mm].M);
                    o.rtree.reinsert = variant != 0;
                    o.rtree.reinsert_far = variant != 2;
                    if (variant == 3) o.rtree.reinsert_fraction = 0.45f;
                    o.rtree.split = (tt_rtree_split)split;
                    tt_accel *a = rt_build_checked(ctx, scene, &o);
                    tt_accel_destroy(a);
                }
}

/* White box: the pointer tree after every insertion, so a broken invariant
 * is caught at the insertion that broke it. */
static void test_every_insertion(tt_context *ctx, const tt_scene *scene)
{
    const uint32_t T = (uint32_t)scene->triangle_count;
    float *box = malloc((size_t)T * 6 * sizeof *box);
    REQUIRE_OK(ctx, box ? TT_OK : TT_ERR_OUT_OF_MEMORY);
    for (uint32_t i = 0; i < T; i++)
        for (int k = 0; k < 3; k++) {
            const float *v = scene->tri + 9 * (size_t)i;
            box[6 * i + k] = fminf(fminf(v[k], v[3 + k]), v[6 + k]);
            box[6 * i + k + 3] = fmaxf(fmaxf(v[k], v[3 + k]), v[6 + k]);
        }
    for (int s = 0; s < 5; s++)
        for (int cfg = 0; cfg < 3; cfg++) {
            tt_build_options o = rt_options(s, TT_RTREE_AUTO, cfg == 2 ? 3 : 2, cfg == 2 ? 8 : 4);
            o.rtree.split = cfg == 1 ? TT_RTREE_SPLIT_QUADRATIC : TT_RTREE_SPLIT_RSTAR;
            o.rtree.reinsert_far = cfg != 2;
            rt_builder b;
            REQUIRE_OK(ctx, rt_builder_init(&b, ctx, &o.rtree, box, T));
            tt_status st = TT_OK;
            for (uint32_t i = 0; i < T && st == TT_OK; i++) {
                st = rt_builder_insert_triangle(&b, i);
                if (st == TT_OK) st = rt_builder_check(&b);
                CHECK_MSG(st == TT_OK, "%s, after inserting triangle %u: %s", rt_describe(&o), i,
                          tt_context_last_error(ctx));
            }
            rt_builder_free(&b);
        }
    free(box);
}

typedef struct stats_seen {
    double triangles, M, height, nodes, leaves, slots, empty, memory, sah, fill0, level_nodes, level_sah;
    int keys;
} stats_seen;

static void collect(void *user, const char *key, double v)
{
    stats_seen *s = user;
    s->keys++;
    if (!strcmp(key, "triangles")) s->triangles = v;
    else if (!strcmp(key, "M")) s->M = v;
    else if (!strcmp(key, "height")) s->height = v;
    else if (!strcmp(key, "nodes")) s->nodes = v;
    else if (!strcmp(key, "leaves")) s->leaves = v;
    else if (!strcmp(key, "slots")) s->slots = v;
    else if (!strcmp(key, "empty_slots")) s->empty = v;
    else if (!strcmp(key, "memory_bytes")) s->memory = v;
    else if (!strcmp(key, "sah_cost")) s->sah = v;
    else if (!strcmp(key, "level0_fill")) s->fill0 = v;
    if (!strncmp(key, "level", 5) && strstr(key, "_nodes")) s->level_nodes += v;
    if (!strncmp(key, "level", 5) && strstr(key, "_sah")) s->level_sah += v;
}

/* The statistics describe the tree consistently: slot count of the complete
 * M-ary tree, leaves x fill = triangles, nodes summed over levels, and a
 * SAH cost of at least the root's own term. */
static void test_statistics(tt_context *ctx, const tt_scene *scene)
{
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
    tt_accel *a = rt_build_checked(ctx, scene, &o);
    if (!a) return;
    stats_seen s;
    memset(&s, 0, sizeof s);
    CHECK_OK(ctx, tt_accel_statistics(a, collect, &s));
    CHECK(s.triangles == (double)scene->triangle_count);
    CHECK(s.M == 4);
    double slots = (pow(4.0, s.height) - 1.0) / 3.0;
    CHECK_MSG(s.slots == slots, "slots %g, complete 4-ary tree of height %g has %g", s.slots,
              s.height, slots);
    CHECK(s.nodes + s.empty == s.slots);
    CHECK(s.level_nodes == s.nodes);
    CHECK(fabs(s.leaves * s.fill0 - s.triangles) < 1e-6 * s.triangles);
    CHECK(s.memory == (double)tt_accel_memory_bytes(a) && s.memory > 0);
    CHECK(s.sah > 1.0); /* the interior root alone costs 1 */
    CHECK_MSG(fabs(s.level_sah - s.sah) <= 1e-9 * s.sah, "levels' SAH %g, sah_cost %g",
              s.level_sah, s.sah);
    tt_accel_destroy(a);
    /* the compact layout (the default build): its levels' parts too */
    a = NULL;
    CHECK_OK(ctx, tt_accel_build(ctx, scene, NULL, &a));
    if (!a) return;
    memset(&s, 0, sizeof s);
    CHECK_OK(ctx, tt_accel_statistics(a, collect, &s));
    CHECK(s.sah > 1.0);
    CHECK_MSG(fabs(s.level_sah - s.sah) <= 1e-9 * s.sah, "compact: levels' SAH %g, sah_cost %g",
              s.level_sah, s.sah);
    tt_accel_destroy(a);
}

static void expect_invalid(tt_context *ctx, const tt_scene *scene, tt_build_options o,
                           const char *what)
{
    tt_accel *a = NULL;
    tt_status st = tt_accel_build(ctx, scene, &o, &a);
    CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT && a == NULL, "%s: expected invalid argument, got %s",
              what, tt_strerror(st));
    CHECK_MSG(strstr(tt_context_last_error(ctx), what) != NULL,
              "the message \"%s\" does not name \"%s\"", tt_context_last_error(ctx), what);
    tt_accel_destroy(a);
}

static void test_validation(tt_context *ctx, const tt_scene *scene)
{
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
    tt_build_options b = o;
    b.rtree.M = 3;
    expect_invalid(ctx, scene, b, "M = 3");
    b = o;
    b.rtree.M = 17;
    expect_invalid(ctx, scene, b, "M = 17");
    b = o;
    b.rtree.m = 1;
    expect_invalid(ctx, scene, b, "m = 1");
    b = o;
    b.rtree.m = 3; /* 3 > 4/2 */
    expect_invalid(ctx, scene, b, "m = 3");
    b = o;
    b.rtree.strategy = (tt_rtree_strategy)7;
    expect_invalid(ctx, scene, b, "strategy");
    b = o;
    b.rtree.split = (tt_rtree_split)5;
    expect_invalid(ctx, scene, b, "split");
    b = o;
    b.rtree.traversal = (tt_rtree_traversal)9;
    expect_invalid(ctx, scene, b, "traversal");
    b = o;
    b.rtree.reinsert_fraction = NAN;
    expect_invalid(ctx, scene, b, "reinsert_fraction");
    b = o;
    b.rtree.reinsert_fraction = 1.0f;
    expect_invalid(ctx, scene, b, "reinsert_fraction");
    b = o;
    b.rtree.reinsert_fraction = 0.9f; /* ejects 4 of 5, leaving 1 < m */
    expect_invalid(ctx, scene, b, "reinsert_fraction");
    /* the largest M the options allow builds */
    b = o;
    b.rtree.m = 8;
    b.rtree.M = 16;
    tt_accel_destroy(rt_build_checked(ctx, scene, &b));
}

/* The check can fail: corrupt the packed tree in several ways and expect
 * TT_ERR_INVARIANT with a message naming the broken rule; restore it and
 * expect a pass again. */
static void test_check_detects(tt_context *ctx, const tt_scene *scene)
{
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 4);
    tt_accel *a = rt_build_checked(ctx, scene, &o);
    if (!a) return;
    rt_tree *t = a->impl;
    const tt_rtree_packed *p = &t->p;
    const uint32_t c0 = p->delta[p->L - 1]; /* the root's first child */
    uint32_t pos;
    float *g = (float *)tt_rt_group(p, c0, &pos);

    float keep = g[3 * p->M + pos];
    g[3 * p->M + pos] = keep + 1.0f; /* hi x of a child grows */
    expect_broken(ctx, a, "exact union");
    g[3 * p->M + pos] = keep;
    CHECK_OK(ctx, tt_accel_check(a));

    uint32_t n = 1; /* an interior node with more than m entries */
    while (n < p->delta[0] && t->count[n] <= t->m) n++;
    CHECK(n < p->delta[0]);
    if (n < p->delta[0]) {
        uint8_t c = t->count[n];
        t->count[n] = (uint8_t)(c - 1); /* the node forgets an entry */
        expect_broken(ctx, a, "not marked empty");
        t->count[n] = (uint8_t)(p->M + 1);
        expect_broken(ctx, a, "entries");
        t->count[n] = c;
    }

    uint32_t id = t->prim[1];
    t->prim[1] = t->prim[0];
    expect_broken(ctx, a, "stored twice");
    t->prim[1] = id;

    float v = t->tri[4];
    t->tri[4] = v + 1e-3f;
    expect_broken(ctx, a, "differ from the scene");
    t->tri[4] = v;

    uint32_t last = p->delta[0] + p->leaf_slots - 1; /* an empty leaf slot */
    float *lg = (float *)tt_rt_group(p, last, &pos);
    if (lg[pos] == TT_INF) {
        lg[pos] = 0.0f;
        expect_broken(ctx, a, "not marked empty");
        lg[pos] = TT_INF;
    }

    uint32_t d = t->p.delta[0];
    t->p.delta[0] = d + 1;
    expect_broken(ctx, a, "Delta_L(0)");
    t->p.delta[0] = d;
    CHECK_OK(ctx, tt_accel_check(a));
    tt_accel_destroy(a);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *bunny4 = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    tt_scene *cornell = tt_test_load_scene(ctx, "cornell_box.obj");
    test_matrix(ctx, bunny4);
    test_matrix(ctx, cornell);
    test_every_insertion(ctx, bunny4);
    test_every_insertion(ctx, cornell);
    test_statistics(ctx, bunny4);
    test_validation(ctx, cornell);
    test_check_detects(ctx, bunny4);
    /* the default configuration on the full bunny */
    tt_scene *bunny = tt_test_load_scene(ctx, "bun_zipper.ply");
    tt_build_options o;
    tt_build_options_default(&o);
    o.rtree.build = TT_RTREE_BUILD_INSERT; /* Feldmann's R-tree */
    o.rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
    tt_accel_destroy(rt_build_checked(ctx, bunny, &o));
    tt_scene_destroy(bunny);
    tt_scene_destroy(bunny4);
    tt_scene_destroy(cornell);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
