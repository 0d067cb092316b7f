/* The binary tree (wbvh_build.c) collapsed into M-wide mixed records
 * (wbvh.h, rtc_layout.h): a record starts from a binary interior node's two
 * children and repeatedly opens the interior child of largest surface area
 * (the one a ray is likeliest to enter) until it holds M entries or only
 * leaves; its interior entries become records in turn. Records are numbered
 * depth first, a record's node children consecutive, as rtc_pack.c numbers
 * them. The walk runs twice with the same choices: once to count records
 * and blocks, once to write them. */
#include "accel/wbvh/wbvh.h"

#include <math.h>
#include <string.h>

#include "accel/rtree/rtree_box.h"

typedef struct packer {
    const wbvh_bin_tree *b;
    const float *scene_tri;
    tt_rtc *c;
    float *node;         /* NULL on the counting pass */
    tt_tri_block *block; /* NULL on the counting pass */
    uint32_t next_node, height;
    uint64_t blocks; /* blocks opened so far        */
    uint32_t used;   /* lanes used of the last one  */
} packer;

/* The entries of the record made from binary interior node n. */
static uint32_t collapse(const wbvh_bin_tree *b, uint32_t n, uint32_t M, uint32_t *e)
{
    uint32_t k = 0;
    e[k++] = b->node[n].a;
    e[k++] = b->node[n].b;
    while (k < M) {
        int best = -1;
        float best_area = -1.0f;
        for (uint32_t i = 0; i < k; i++) {
            const wbvh_bin_node *d = &b->node[e[i]];
            if (d->count) continue;
            const float a = rt_box_area(d->box);
            if (a > best_area) {
                best_area = a;
                best = (int)i;
            }
        }
        if (best < 0) break;
        const wbvh_bin_node *d = &b->node[e[best]];
        e[best] = d->a;
        e[k++] = d->b;
    }
    return k;
}

/* First-fit placement as rtc_pack.c's (rtc_layout.h): a leaf of at most a
 * block shares the last block when its lanes suffice. Returns the first
 * global lane. */
static uint64_t place_leaf(packer *pk, uint32_t count)
{
    if (count <= TT_TRI_BLOCK_W && pk->blocks > 0 && pk->used + count <= TT_TRI_BLOCK_W) {
        const uint64_t lane = (pk->blocks - 1) * TT_TRI_BLOCK_W + pk->used;
        pk->used += count;
        return lane;
    }
    const uint64_t lane = pk->blocks * TT_TRI_BLOCK_W;
    const uint32_t nb = tt_tri_block_count(count);
    pk->blocks += nb;
    pk->used = count - (nb - 1) * TT_TRI_BLOCK_W;
    return lane;
}

/* Binary leaf d's triangles into their lanes; returns its reference. */
static uint32_t put_leaf(packer *pk, const wbvh_bin_node *d)
{
    const uint64_t first = place_leaf(pk, d->count);
    for (uint32_t k = 0; pk->block && k < d->count; k++) {
        const uint64_t g = first + k;
        tt_tri_block *bk = &pk->block[g / TT_TRI_BLOCK_W];
        const uint32_t lane = (uint32_t)(g % TT_TRI_BLOCK_W);
        const uint32_t id = pk->b->order[d->a + k];
        const float *v = pk->scene_tri + 9 * (size_t)id;
        const int dead = tt_tri_is_degenerate(v, v + 3, v + 6);
        for (int q = 0; q < 9; q++) bk->v[q][lane] = dead ? NAN : v[q];
        bk->prim[lane] = id;
    }
    return tt_rtc_leaf_ref((uint32_t)(first / TT_TRI_BLOCK_W),
                           (uint32_t)(first % TT_TRI_BLOCK_W), d->count);
}

/* Record n (when writing) with entries e[0 .. k): leaves first, then the
 * node entries, which get consecutive indices; those are returned in
 * kids[0 .. *nk) (binary node ids) from index *first. */
static void put_record(packer *pk, uint32_t n, uint32_t parent, const uint32_t *e, uint32_t k,
                       uint32_t *kids, uint32_t *nk, uint32_t *first)
{
    const wbvh_bin_tree *b = pk->b;
    const tt_rtc *c = pk->c;
    uint32_t ord[TT_RT_MAX_M], ref[TT_RT_MAX_M], nl = 0;
    *nk = 0;
    for (uint32_t i = 0; i < k; i++)
        if (b->node[e[i]].count) ord[nl++] = e[i];
    for (uint32_t i = 0; i < k; i++)
        if (!b->node[e[i]].count) kids[(*nk)++] = e[i];
    for (uint32_t i = 0; i < *nk; i++) ord[nl + i] = kids[i];
    for (uint32_t i = 0; i < nl; i++) ref[i] = put_leaf(pk, &b->node[ord[i]]);
    *first = pk->next_node;
    for (uint32_t i = 0; i < *nk; i++) ref[nl + i] = *first + i;
    pk->next_node += *nk;
    if (!pk->node) return;
    float *rec = pk->node + (size_t)n * c->words;
    for (uint32_t i = 0; i < c->words; i++) rec[i] = 0.0f;
    float soa[6 * TT_RT_MAX_M];
    for (uint32_t i = 0; i < k; i++)
        for (int q = 0; q < 6; q++) soa[q * TT_RT_MAX_M + i] = b->node[ord[i]].box[q];
    rtc_set_boxes(c, rec, soa, TT_RT_MAX_M, k);
    uint32_t *w = (uint32_t *)(rec + 6 * c->S);
    for (uint32_t i = 0; i < c->S; i++) w[i] = i < k ? ref[i] : TT_INVALID_ID;
    w[c->S] = parent;
    w[c->S + 1] = k; /* level 0: mixed */
}

/* The depth-first walk; on the counting pass pk->node is NULL. */
static tt_status walk(tt_context *ctx, packer *pk, uint32_t M)
{
    const wbvh_bin_tree *b = pk->b;
    pk->next_node = 1;
    pk->height = 1;
    pk->blocks = 0;
    pk->used = 0;
    const wbvh_bin_node *root = &b->node[0];
    if (root->count || b->nodes <= 1) {
        /* a leaf root (or none) gets a record above it */
        const uint32_t e = 0, k = root->count ? 1u : 0u;
        uint32_t kids[TT_RT_MAX_M], nk, first;
        put_record(pk, 0, TT_INVALID_ID, &e, k, kids, &nk, &first);
        return TT_OK;
    }
    /* (binary node, record, parent record, depth) of the records to write */
    const size_t cap = (size_t)b->nodes + 1;
    uint32_t *st = tt_alloc_array(ctx, cap, 4 * sizeof(uint32_t));
    if (!st) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "wbvh: out of memory (packing)");
    size_t sp = 0;
    st[0] = 0, st[1] = 0, st[2] = TT_INVALID_ID, st[3] = 1;
    sp = 1;
    while (sp > 0) {
        sp--;
        const uint32_t bn = st[4 * sp], n = st[4 * sp + 1], parent = st[4 * sp + 2];
        const uint32_t depth = st[4 * sp + 3];
        if (depth > pk->height) pk->height = depth;
        uint32_t e[TT_RT_MAX_M], kids[TT_RT_MAX_M], nk, first;
        const uint32_t k = collapse(b, bn, M, e);
        put_record(pk, n, parent, e, k, kids, &nk, &first);
        for (uint32_t i = nk; i-- > 0;) {
            uint32_t *q = st + 4 * sp++;
            q[0] = kids[i], q[1] = first + i, q[2] = n, q[3] = depth + 1;
        }
    }
    tt_free(ctx, st);
    return TT_OK;
}

/* 64-byte aligned storage for count items of size bytes (at least one). */
static void *alloc_aligned(tt_context *ctx, size_t count, size_t size, void **raw)
{
    if (count == 0) count = 1;
    if (count > (SIZE_MAX - 64) / size) return *raw = NULL;
    *raw = tt_alloc(ctx, count * size + 63);
    if (!*raw) return NULL;
    return (void *)(((uintptr_t)*raw + 63) & ~(uintptr_t)63);
}

tt_status wbvh_pack(tt_context *ctx, const wbvh_bin_tree *b, const float *scene_tri, uint32_t T,
                    uint32_t M, rtc_tree *t)
{
    tt_rtc *c = &t->c;
    memset(c, 0, sizeof *c);
    c->M = M;
    c->S = (M + 3u) & ~3u;
    c->words = tt_rtc_words(M);
    c->triangles = T;
    packer pk = {b, scene_tri, c, NULL, NULL, 0, 0, 0, 0};
    tt_status st = walk(ctx, &pk, M);
    if (st != TT_OK) return st;
    if ((M - 1) * pk.height > TT_WBVH_STACK_SIZE || pk.height > 255)
        return tt_error(ctx, TT_ERR_UNSUPPORTED,
                        "wbvh: the tree is %u records deep; the traversal stack holds %d entries "
                        "(M - 1 a record)", pk.height, TT_WBVH_STACK_SIZE);
    if (pk.next_node >= TT_RTC_LEAF_BIT || pk.blocks >= (uint64_t)1 << TT_RTC_LEAF_BLOCK_BITS)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "wbvh: %u records and %llu triangle blocks are beyond 32-bit references",
                        pk.next_node, (unsigned long long)pk.blocks);
    c->nodes = pk.next_node;
    c->blocks = (uint32_t)pk.blocks;
    c->height = pk.height;
    float *node = alloc_aligned(ctx, c->nodes, (size_t)c->words * sizeof(float), &t->node_mem);
    tt_tri_block *block = alloc_aligned(ctx, c->blocks, sizeof(tt_tri_block), &t->block_mem);
    if (!node || !block)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "wbvh: out of memory for %u records and %u triangle blocks", c->nodes,
                        c->blocks);
    for (uint32_t j = 0; j < c->blocks; j++) /* every lane unused until a leaf takes it */
        for (int i = 0; i < TT_TRI_BLOCK_W; i++) {
            for (int q = 0; q < 9; q++) block[j].v[q][i] = NAN;
            block[j].prim[i] = TT_INVALID_ID;
        }
    c->node = node;
    c->block = block;
    const uint32_t nodes = c->nodes, blocks = c->blocks;
    pk.node = node;
    pk.block = block;
    st = walk(ctx, &pk, M);
    if (st == TT_OK && (pk.next_node != nodes || pk.blocks != blocks))
        return tt_error(ctx, TT_ERR_INTERNAL, "wbvh: wrote %u of %u records and %llu of %u blocks",
                        pk.next_node, nodes, (unsigned long long)pk.blocks, blocks);
    return st;
}
