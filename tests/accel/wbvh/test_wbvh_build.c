/* The wide BVH's builder and collapse, white box: the binary tree's
 * invariants (every triangle in exactly one leaf of 1..max_leaf, exact
 * boxes, the depth bound on a degenerate input), the records' (through the
 * shared compact check) and that the packed tree does not depend on the
 * number of threads (a scene large enough for the parallel path). */
#include <math.h>
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "accel/wbvh/wbvh.h"
#include "check.h"

static uint32_t rng = 12345u;
static float frand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 16777216.0f;
}

/* T triangles: small ones scattered, a dense cluster, some long thin ones;
 * identical ones when `same`. */
static float *make_tris(uint32_t T, int same)
{
    float *v = malloc((size_t)T * 9 * sizeof *v);
    for (uint32_t i = 0; i < T; i++) {
        float c[3], s = i % 7 == 0 ? 0.001f : 0.02f;
        for (int k = 0; k < 3; k++) c[k] = same ? 0.5f : i % 5 == 0 ? 0.5f + 0.01f * frand() : frand();
        for (int q = 0; q < 3; q++)
            for (int k = 0; k < 3; k++)
                v[9 * i + 3 * q + k] = c[k] + (same ? 0.01f * (float)(q == k) : s * (frand() - 0.5f)) +
                                       (i % 11 == 0 && k == 0 && q == 1 ? 0.5f : 0.0f);
    }
    return v;
}

static float *boxes_of(const float *v, uint32_t T)
{
    float *b = malloc((size_t)T * 6 * sizeof *b);
    for (uint32_t i = 0; i < T; i++)
        for (int k = 0; k < 3; k++) {
            const float *t = v + 9 * (size_t)i;
            b[6 * i + k] = rt_min(rt_min(t[k], t[3 + k]), t[6 + k]);
            b[6 * i + k + 3] = rt_max(rt_max(t[k], t[3 + k]), t[6 + k]);
        }
    return b;
}

/* Walks node n: boxes exact, leaves 1..max_leaf; marks the leaves' order
 * positions; returns the depth below n. */
static uint32_t walk(const wbvh_bin_tree *b, const float *tb, uint32_t n, uint32_t max_leaf,
                     uint8_t *pos_seen, int *bad)
{
    const wbvh_bin_node *d = &b->node[n];
    float u[6];
    rt_box_empty(u);
    uint32_t depth = 0;
    if (d->count) {
        if (d->count > max_leaf) (*bad)++;
        for (uint32_t i = d->a; i < d->a + d->count; i++) {
            if (pos_seen[i]++) (*bad)++;
            rt_box_grow(u, tb + 6 * (size_t)b->order[i]);
        }
    } else {
        const uint32_t da = walk(b, tb, d->a, max_leaf, pos_seen, bad);
        const uint32_t db = walk(b, tb, d->b, max_leaf, pos_seen, bad);
        depth = 1 + (da > db ? da : db);
        rt_box_grow(u, b->node[d->a].box);
        rt_box_grow(u, b->node[d->b].box);
    }
    if (!rt_box_equal(u, d->box)) (*bad)++;
    return depth;
}

static void binary_invariants(tt_context *ctx, uint32_t T, int same, uint32_t max_leaf)
{
    float *v = make_tris(T, same), *tb = boxes_of(v, T);
    wbvh_bin_tree b;
    REQUIRE_OK(ctx, wbvh_build_binary(ctx, tb, T, max_leaf, 1, &b));
    uint8_t *seen = calloc(T, 1), *ids = calloc(T, 1);
    int bad = 0;
    const uint32_t depth = walk(&b, tb, 0, max_leaf, seen, &bad);
    CHECK_MSG(bad == 0, "T=%u same=%d max_leaf=%u: %d broken boxes / leaves", T, same, max_leaf,
              bad);
    for (uint32_t i = 0; i < T; i++) {
        CHECK_MSG(seen[i] == 1, "position %u in %u leaves", i, seen[i]);
        if (b.order[i] < T) ids[b.order[i]]++;
    }
    for (uint32_t i = 0; i < T; i++) CHECK_MSG(ids[i] == 1, "triangle %u stored %u times", i, ids[i]);
    CHECK_MSG(depth <= 48 + 32, "depth %u", depth);
    CHECK(b.nodes <= 2 * T - 1);
    /* the collapse: the compact check on the records */
    rtc_tree t;
    memset(&t, 0, sizeof t);
    t.m = 1;
    for (uint32_t M = 4; M <= 16; M *= 2) {
        if (max_leaf > M) continue;
        tt_status st = wbvh_pack(ctx, &b, v, T, M, &t);
        CHECK_MSG(st == TT_OK, "pack M=%u: %s", M, tt_context_last_error(ctx));
        tt_scene *scene = NULL;
        uint32_t *idx = malloc((size_t)T * 3 * sizeof *idx);
        for (uint32_t i = 0; i < 3 * T; i++) idx[i] = i;
        REQUIRE_OK(ctx, tt_scene_create(ctx, v, 3 * (size_t)T, idx, T, &scene));
        if (st == TT_OK) CHECK_OK(ctx, rtc_check(ctx, &t, scene));
        tt_scene_destroy(scene);
        free(idx);
        rtc_free(ctx, &t);
    }
    wbvh_bin_free(ctx, &b);
    free(seen);
    free(ids);
    free(v);
    free(tb);
}

/* The same records and blocks from one thread and from two. */
static void threads_agree(tt_context *ctx)
{
    const uint32_t T = 300000; /* above RT_BULK_PARALLEL_MIN */
    float *v = make_tris(T, 0), *tb = boxes_of(v, T);
    rtc_tree t[2];
    memset(t, 0, sizeof t);
    for (int k = 0; k < 2; k++) {
        wbvh_bin_tree b;
        REQUIRE_OK(ctx, wbvh_build_binary(ctx, tb, T, 16, k + 1, &b));
        REQUIRE_OK(ctx, wbvh_pack(ctx, &b, v, T, 16, &t[k]));
        wbvh_bin_free(ctx, &b);
    }
    CHECK(t[0].c.nodes == t[1].c.nodes && t[0].c.blocks == t[1].c.blocks);
    if (t[0].c.nodes == t[1].c.nodes && t[0].c.blocks == t[1].c.blocks) {
        CHECK(memcmp(t[0].c.node, t[1].c.node, (size_t)t[0].c.nodes * t[0].c.words * 4) == 0);
        CHECK(memcmp(t[0].c.block, t[1].c.block, (size_t)t[0].c.blocks * sizeof(tt_tri_block)) ==
              0);
    }
    rtc_free(ctx, &t[0]);
    rtc_free(ctx, &t[1]);
    free(v);
    free(tb);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    binary_invariants(ctx, 1, 0, 16);
    binary_invariants(ctx, 2, 0, 4);
    binary_invariants(ctx, 3000, 0, 16);
    binary_invariants(ctx, 3000, 0, 4);
    binary_invariants(ctx, 1000, 1, 8); /* identical triangles: halved ranges */
    threads_agree(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
