/* The compact layout's check and bookkeeping, white box: corrupting a child
 * box, a node's entry count, a parent link, a child reference, a triangle
 * lane or a triangle id, two leaves sharing lanes, an id in an unused lane
 * makes tt_accel_check fail with TT_ERR_INVARIANT
 * naming the rule, and restoring it passes again; tt_accel_memory_bytes
 * counts the node records and blocks; tiny scenes (0, 1, 3 triangles, a
 * leaf root) build, check and trace like bruteforce; the statistics say
 * bytes per triangle; options out of range are refused. */
#include <string.h>

#include "accel/accel.h"
#include "accel/rtree/rtree.h"
#include "compare.h"
#include "rtree_test.h"

static tt_build_options compact(int m, int M)
{
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, m, M);
    o.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
    return o;
}

static void test_check_detects(tt_context *ctx, const tt_scene *scene)
{
    tt_build_options o = compact(2, 4);
    tt_accel *a = rt_build_checked(ctx, scene, &o);
    if (!a) return;
    rt_tree *t = a->impl;
    tt_rtc *c = &t->compact.c;
    CHECK(c->height >= 3);
    float *root = (float *)tt_rtc_node(c, 0);
    uint32_t *ref = (uint32_t *)tt_rtc_child(c, root);
    uint32_t *hdr = ref + c->S;

    float keep = root[3 * c->S + 1]; /* hi x of the root's second child grows */
    root[3 * c->S + 1] = keep + 1.0f;
    expect_broken(ctx, a, "exact union");
    root[3 * c->S + 1] = keep;
    CHECK_OK(ctx, tt_accel_check(a));

    const uint32_t cnt = hdr[1] & 0xff;
    hdr[1] = (hdr[1] & ~0xffu) | (cnt - 1); /* the root forgets an entry */
    expect_broken(ctx, a, "not marked empty");
    hdr[1] = (hdr[1] & ~0xffu) | (c->M + 1);
    expect_broken(ctx, a, "entries");
    hdr[1] = (hdr[1] & ~0xffu) | cnt;
    CHECK_OK(ctx, tt_accel_check(a));

    /* node 1 (the root's first child): parent link, level */
    uint32_t *hdr1 = (uint32_t *)tt_rtc_child(c, tt_rtc_node(c, 1)) + c->S;
    hdr1[0] = 2;
    expect_broken(ctx, a, "links to parent");
    hdr1[0] = 0;
    hdr1[1] += 1u << 8;
    expect_broken(ctx, a, "says level");
    hdr1[1] -= 1u << 8;
    CHECK_OK(ctx, tt_accel_check(a));

    /* the root's children out of order */
    uint32_t r0 = ref[0], r1 = ref[1];
    ref[0] = r1, ref[1] = r0;
    expect_broken(ctx, a, "consecutive");
    ref[0] = r0, ref[1] = r1;
    CHECK_OK(ctx, tt_accel_check(a));

    /* a triangle lane and an id in the first block */
    tt_tri_block *b = (tt_tri_block *)c->block;
    float v = b[0].v[4][0];
    b[0].v[4][0] = v + 1e-3f;
    expect_broken(ctx, a, "differ from the scene");
    b[0].v[4][0] = v;
    uint32_t id = b[0].prim[1];
    b[0].prim[1] = b[0].prim[0];
    expect_broken(ctx, a, "stored twice");
    b[0].prim[1] = id;
    CHECK_OK(ctx, tt_accel_check(a));

    /* two leaves claiming the same lanes; an unused lane given an id */
    for (uint32_t n = 0; n < c->nodes; n++) {
        float *rec = (float *)tt_rtc_node(c, n);
        uint32_t *r = (uint32_t *)tt_rtc_child(c, rec);
        if (tt_rtc_level(c, rec) != 1 || tt_rtc_count(c, rec) < 2) continue;
        const uint32_t r1 = r[1];
        r[1] = r[0];
        expect_broken(ctx, a, "another leaf holds");
        r[1] = r1;
        CHECK_OK(ctx, tt_accel_check(a));
        break;
    }
    for (uint32_t g = 0; g < c->blocks * TT_TRI_BLOCK_W; g++) {
        tt_tri_block *bk = &b[g / TT_TRI_BLOCK_W];
        if (bk->prim[g % TT_TRI_BLOCK_W] != TT_INVALID_ID) continue;
        bk->prim[g % TT_TRI_BLOCK_W] = 0;
        expect_broken(ctx, a, "not marked unused");
        bk->prim[g % TT_TRI_BLOCK_W] = TT_INVALID_ID;
        CHECK_OK(ctx, tt_accel_check(a));
        break;
    }

    /* memory: the records and blocks, nothing less */
    size_t bytes = tt_accel_memory_bytes(a);
    CHECK_MSG(bytes >= (size_t)c->nodes * c->words * 4 + (size_t)c->blocks * sizeof(tt_tri_block),
              "memory %zu bytes for %u nodes and %u blocks", bytes, c->nodes, c->blocks);
    tt_accel_destroy(a);
}

/* bytes per triangle for M = 4, 8, 16 (printed for the report) and the
 * statistics keys; the compact tree is far smaller than the complete one. */
typedef struct get {
    double bpt, mem;
} get;

static void get_stat(void *user, const char *key, double value)
{
    get *g = user;
    if (!strcmp(key, "bytes_per_triangle")) g->bpt = value;
    if (!strcmp(key, "memory_bytes")) g->mem = value;
}

static void test_memory(tt_context *ctx, const tt_scene *scene)
{
    static const rt_mm mm[] = {{2, 4}, {3, 8}, {4, 16}};
    for (int k = 0; k < 3; k++) {
        tt_build_options o = compact(mm[k].m, mm[k].M);
        o.rtree.build = TT_RTREE_BUILD_INSERT; /* the complete layout's worst case */
        tt_accel *a = rt_build_checked(ctx, scene, &o);
        o.rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
        tt_accel *full = rt_build_checked(ctx, scene, &o);
        if (!a || !full) continue;
        get g = {0, 0};
        tt_accel_statistics(a, get_stat, &g);
        CHECK_MSG(g.mem == (double)tt_accel_memory_bytes(a) && g.bpt > 36.0,
                  "M=%d: statistics memory %g, bytes per triangle %g", mm[k].M, g.mem, g.bpt);
        CHECK_MSG(tt_accel_memory_bytes(a) < tt_accel_memory_bytes(full),
                  "M=%d: compact %zu bytes, complete %zu", mm[k].M, tt_accel_memory_bytes(a),
                  tt_accel_memory_bytes(full));
        printf("  M=%d m=%d: compact %.1f bytes/triangle, complete %.1f\n", mm[k].M, mm[k].m,
               g.bpt, (double)tt_accel_memory_bytes(full) / (double)tt_scene_triangle_count(scene));
        tt_accel_destroy(a);
        tt_accel_destroy(full);
    }
}

/* 0, 1, 3 and 9 triangles (a leaf root; with M = 4 a two-level tree). */
static void test_tiny(tt_context *ctx)
{
    float v[3 * 30];
    uint32_t idx[3 * 10];
    for (int i = 0; i < 10; i++) {
        float x = (float)i;
        float q[9] = {x, 0, 0, x + 1, 0, 0.5f, x, 1, 0.25f};
        memcpy(v + 9 * i, q, sizeof q);
        for (int k = 0; k < 3; k++) idx[3 * i + k] = (uint32_t)(3 * i + k);
    }
    static const size_t counts[] = {0, 1, 3, 9};
    for (int k = 0; k < 4; k++) {
        tt_scene *s = NULL;
        REQUIRE_OK(ctx, tt_scene_create(ctx, v, 30, idx, counts[k], &s));
        tt_accel *bf = tt_test_build_default(ctx, s, "bruteforce");
        for (int tr = TT_RTREE_AUTO; tr <= TT_RTREE_STACK; tr++) {
            tt_build_options o = compact(2, 4);
            o.rtree.traversal = (tt_rtree_traversal)tr;
            tt_accel *a = rt_build_checked(ctx, s, &o);
            if (!a) continue;
            size_t bad = tt_test_compare_random(s, a, bf, 500, 5u + (uint32_t)k);
            CHECK_MSG(bad == 0, "%zu triangles, traversal %s: %zu random rays disagree",
                      counts[k], rt_traversal_names[tr], bad);
            tt_accel_destroy(a);
        }
        tt_accel_destroy(bf);
        tt_scene_destroy(s);
    }
}

static void test_validation(tt_context *ctx, const tt_scene *scene)
{
    tt_build_options o = compact(2, 4);
    o.rtree.layout = (tt_rtree_layout)7;
    tt_accel *a = NULL;
    CHECK(tt_accel_build(ctx, scene, &o, &a) == TT_ERR_INVALID_ARGUMENT && a == NULL);
    CHECK(strstr(tt_context_last_error(ctx), "layout") != NULL);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *bunny4 = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    test_check_detects(ctx, bunny4);
    test_tiny(ctx);
    test_validation(ctx, bunny4);
    tt_scene *bunny = tt_test_load_scene(ctx, "bun_zipper.ply");
    test_memory(ctx, bunny);
    tt_scene_destroy(bunny);
    tt_scene_destroy(bunny4);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
