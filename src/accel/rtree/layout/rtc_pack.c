/* Packing the builder's pointer tree (any builder: insertion or bulk
 * loading, they all fill rt_builder) into the compact layout
 * (rtc_layout.h); or the SAH loader's level form (rt_bulk_levels), which
 * the default build packs without making the pointer tree, by the same
 * walk into the same bytes. Boxes are copied verbatim from the pointer tree, never
 * recomputed, so the check (rtc_check.c) also verifies that the builder
 * kept every node box the exact union of its entries. */
#include <math.h>
#include <string.h>

#include "accel/rtree/rtc.h"
#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_bulk.h"

_Static_assert(TT_RT_MAX_M <= 16 && TT_TRI_BLOCK_W == 8,
               "a leaf reference holds a lane in a block (3 bits) and count - 1 (4 bits)");
_Static_assert(TT_RT_MAX_M <= 31, "entry masks are 32 bits");

size_t rtc_bytes(const rtc_tree *t)
{
    /* the allocations as made, alignment slack included */
    return (t->node_mem ? (size_t)t->c.nodes * t->c.words * sizeof(float) + 63 : 0) +
           (t->block_mem ? (size_t)t->c.blocks * sizeof(tt_tri_block) + 63 : 0);
}

void rtc_free(tt_context *ctx, rtc_tree *t)
{
    tt_free(ctx, t->node_mem);
    tt_free(ctx, t->block_mem);
    t->node_mem = t->block_mem = NULL;
    t->c.node = NULL;
    t->c.block = NULL;
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

/* First-fit placement of leaves into blocks, in leaf order (rtc_layout.h):
 * `blocks` opened so far, `used` lanes of the last one. Returns the first
 * global lane of a leaf of `count` triangles. */
typedef struct lanes_fill {
    uint64_t blocks;
    uint32_t used;
} lanes_fill;

static uint64_t place_leaf(lanes_fill *f, uint32_t count)
{
    if (count <= TT_TRI_BLOCK_W && f->blocks > 0 && f->used + count <= TT_TRI_BLOCK_W) {
        const uint64_t lane = (f->blocks - 1) * TT_TRI_BLOCK_W + f->used;
        f->used += count;
        return lane;
    }
    const uint64_t lane = f->blocks * TT_TRI_BLOCK_W;
    const uint32_t nb = tt_tri_block_count(count);
    f->blocks += nb;
    f->used = count - (nb - 1) * TT_TRI_BLOCK_W;
    return lane;
}

/* Interior nodes (level >= 1) under builder node n, and the blocks its
 * leaves fill, walking in the packer's order (depth first, children in
 * order). */
static void count_tree(const rt_builder *b, uint32_t n, uint64_t *nodes, lanes_fill *f)
{
    const rt_node_hdr *h = &b->hdr[n];
    if (h->level == 0) {
        if (h->count > 0) place_leaf(f, h->count);
        return;
    }
    (*nodes)++;
    const uint32_t *ch = rt_node_child(b, n);
    for (int i = 0; i < h->count; i++) count_tree(b, ch[i], nodes, f);
}

void rtc_set_boxes(const tt_rtc *c, float *rec, const float *box, uint32_t stride, uint32_t count)
{
    for (uint32_t k = 0; k < 6; k++)
        for (uint32_t i = 0; i < c->S; i++)
            rec[k * c->S + i] = i < count ? box[k * stride + i] : TT_INF;
}

typedef struct packer {
    const rt_builder *b;
    const float *scene_tri;
    tt_rtc *c;
    float *node;
    tt_tri_block *block;
    uint32_t next_node;
    lanes_fill fill;
} packer;

/* Empties record n's child rows (+inf: always missed) and references. */
static float *record_init(packer *pk, uint32_t n, uint32_t parent, uint32_t count, uint32_t level)
{
    const uint32_t S = pk->c->S;
    float *rec = pk->node + (size_t)n * pk->c->words;
    for (uint32_t i = 0; i < pk->c->words; i++) rec[i] = 0.0f;
    for (uint32_t i = 0; i < 6 * S; i++) rec[i] = TT_INF;
    uint32_t *w = (uint32_t *)(rec + 6 * S);
    for (uint32_t i = 0; i < S; i++) w[i] = TT_INVALID_ID;
    w[S] = parent;
    w[S + 1] = count | level << 8;
    return rec;
}

/* A leaf's triangles into the lanes place_leaf gives it (the blocks start
 * out as unused lanes: NaN, no id); returns its reference. Zero-area
 * triangles get NaN vertices, as tt_tri_block_pack gives them. */
static uint32_t put_leaf(packer *pk, const uint32_t *ids, uint32_t count)
{
    const uint64_t first = place_leaf(&pk->fill, count);
    for (uint32_t k = 0; k < count; k++) {
        const uint64_t g = first + k;
        tt_tri_block *b = &pk->block[g / TT_TRI_BLOCK_W];
        const uint32_t lane = (uint32_t)(g % TT_TRI_BLOCK_W);
        const float *v = pk->scene_tri + 9 * (size_t)ids[k];
        const int dead = tt_tri_is_degenerate(v, v + 3, v + 6);
        for (int q = 0; q < 9; q++) b->v[q][lane] = dead ? NAN : v[q];
        b->prim[lane] = ids[k];
    }
    return tt_rtc_leaf_ref((uint32_t)(first / TT_TRI_BLOCK_W),
                           (uint32_t)(first % TT_TRI_BLOCK_W), count);
}

/* Checks the tree's size against the layout's limits and allocates the
 * records and the blocks (every lane unused until a leaf takes it). */
static tt_status layout_alloc(tt_context *ctx, rtc_tree *t, uint32_t M, uint32_t height,
                              uint64_t nodes, uint64_t blocks, uint32_t triangles,
                              float **node_out, tt_tri_block **block_out)
{
    tt_rtc *c = &t->c;
    if (height * M > TT_RTC_STACK_SIZE || height > 255)
        return tt_error(ctx, TT_ERR_UNSUPPORTED,
                        "rtree compact layout: the tree has %u levels of %u entries; the "
                        "traversal stack holds %d", height + 1, M, TT_RTC_STACK_SIZE);
    if (nodes >= TT_RTC_LEAF_BIT || blocks >= (uint64_t)1 << TT_RTC_LEAF_BLOCK_BITS)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "rtree compact layout: %llu nodes and %llu triangle blocks are beyond "
                        "32-bit references", (unsigned long long)nodes,
                        (unsigned long long)blocks);
    c->M = M;
    c->S = (M + 3u) & ~3u;
    c->words = tt_rtc_words(M);
    c->nodes = (uint32_t)nodes;
    c->blocks = (uint32_t)blocks;
    c->triangles = triangles;
    c->height = height;
    float *node = alloc_aligned(ctx, nodes, (size_t)c->words * sizeof(float), &t->node_mem);
    tt_tri_block *block = alloc_aligned(ctx, blocks, sizeof(tt_tri_block), &t->block_mem);
    if (!node || !block)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "rtree compact layout: out of memory for %llu nodes and %llu triangle "
                        "blocks (%.1f MB)", (unsigned long long)nodes,
                        (unsigned long long)blocks,
                        ((double)nodes * c->words * 4.0 + (double)blocks * 320.0) / 1e6);
    for (uint64_t j = 0; j < blocks; j++) /* every lane unused until a leaf takes it */
        for (int i = 0; i < TT_TRI_BLOCK_W; i++) {
            for (int q = 0; q < 9; q++) block[j].v[q][i] = NAN;
            block[j].prim[i] = TT_INVALID_ID;
        }
    c->node = *node_out = node;
    c->block = *block_out = block;
    return TT_OK;
}

tt_status rtc_pack(tt_context *ctx, const rt_builder *b, const float *scene_tri, rtc_tree *t)
{
    tt_rtc *c = &t->c;
    memset(c, 0, sizeof *c);
    const uint32_t M = (uint32_t)b->M;
    const rt_node_hdr *root = &b->hdr[b->root];
    uint64_t nodes = 0;
    lanes_fill fill = {0, 0};
    count_tree(b, b->root, &nodes, &fill);
    const uint64_t blocks = fill.blocks;
    if (root->level == 0) nodes = 1; /* a leaf root gets a node above it */
    const uint32_t height = root->level == 0 ? 1u : root->level;
    float *node;
    tt_tri_block *block;
    tt_status st = layout_alloc(ctx, t, M, height, nodes, blocks, b->triangles, &node, &block);
    if (st != TT_OK) return st;
    packer pk = {b, scene_tri, c, node, block, 1, {0, 0}};

    if (root->level == 0) {
        float *rec = record_init(&pk, 0, TT_INVALID_ID, root->count > 0, 1);
        if (root->count > 0) {
            float rb[6];
            rt_node_bounds(b, b->root, rb);
            rtc_set_boxes(c, rec, rb, 1, 1);
            ((uint32_t *)tt_rtc_child(c, rec))[0] = put_leaf(&pk, rt_node_child(b, b->root),
                                                             root->count);
        }
    } else {
        /* depth first; a node's interior children get consecutive indices
         * when the node is written, then their subtrees follow in order */
        uint32_t st_node[TT_RT_BUILD_LEVELS * TT_RT_CAP], st_index[TT_RT_BUILD_LEVELS * TT_RT_CAP];
        uint32_t st_parent[TT_RT_BUILD_LEVELS * TT_RT_CAP];
        int sp = 0;
        st_node[sp] = b->root;
        st_index[sp] = 0;
        st_parent[sp++] = TT_INVALID_ID;
        while (sp > 0) {
            sp--;
            const uint32_t bn = st_node[sp], n = st_index[sp];
            const rt_node_hdr *h = &b->hdr[bn];
            const float *soa = rt_node_box(b, bn);
            const uint32_t *ch = rt_node_child(b, bn);
            float *rec = record_init(&pk, n, st_parent[sp], h->count, h->level);
            uint32_t *ref = (uint32_t *)tt_rtc_child(c, rec);
            rtc_set_boxes(c, rec, soa, (uint32_t)b->cap, h->count);
            if (h->level == 1) {
                for (int i = 0; i < h->count; i++) {
                    const rt_node_hdr *leaf = &b->hdr[ch[i]];
                    ref[i] = put_leaf(&pk, rt_node_child(b, ch[i]), leaf->count);
                }
                continue;
            }
            const uint32_t first = pk.next_node;
            pk.next_node += h->count;
            for (int i = 0; i < h->count; i++) ref[i] = first + (uint32_t)i;
            for (int i = h->count - 1; i >= 0; i--) {
                st_node[sp] = ch[i];
                st_index[sp] = first + (uint32_t)i;
                st_parent[sp++] = n;
            }
        }
    }
    if (pk.next_node != c->nodes || pk.fill.blocks != c->blocks)
        return tt_error(ctx, TT_ERR_INTERNAL,
                        "rtree compact layout: wrote %u of %u nodes and %llu of %u blocks",
                        pk.next_node, c->nodes, (unsigned long long)pk.fill.blocks, c->blocks);
    return TT_OK;
}

/* The same walk as rtc_pack's over the level form: a node is (level,
 * number on its level); its children are numbers first[l][j] .. first[l][j
 * + 1] - 1 on the level below, whose boxes lie consecutively in box[l - 1]. */
tt_status rtc_pack_levels(tt_context *ctx, const rt_bulk_levels *lv, const float *scene_tri,
                          rtc_tree *t)
{
    tt_rtc *c = &t->c;
    memset(c, 0, sizeof *c);
    const uint32_t M = lv->M, L = lv->height;
    if (L < 1 || L >= TT_RT_BUILD_LEVELS)
        return tt_error(ctx, TT_ERR_INTERNAL, "rtree compact layout: level form of height %u", L);
    uint64_t nodes = 0;
    for (uint32_t l = 1; l <= L; l++) nodes += lv->count[l];
    lanes_fill fill = {0, 0};
    for (uint32_t j = 0; j < lv->count[0]; j++) /* leaves in depth-first order */
        place_leaf(&fill, lv->first[0][j + 1] - lv->first[0][j]);
    float *node;
    tt_tri_block *block;
    tt_status st = layout_alloc(ctx, t, M, L, nodes, fill.blocks, lv->triangles, &node, &block);
    if (st != TT_OK) return st;
    packer pk = {NULL, scene_tri, c, node, block, 1, {0, 0}};
    const uint32_t S = c->S;
    uint32_t st_level[TT_RT_BUILD_LEVELS * TT_RT_CAP], st_j[TT_RT_BUILD_LEVELS * TT_RT_CAP];
    uint32_t st_index[TT_RT_BUILD_LEVELS * TT_RT_CAP], st_parent[TT_RT_BUILD_LEVELS * TT_RT_CAP];
    int sp = 0;
    st_level[sp] = L;
    st_j[sp] = 0;
    st_index[sp] = 0;
    st_parent[sp++] = TT_INVALID_ID;
    while (sp > 0) {
        sp--;
        const uint32_t l = st_level[sp], j = st_j[sp], n = st_index[sp];
        const uint32_t c0 = lv->first[l][j], count = lv->first[l][j + 1] - c0;
        float *rec = record_init(&pk, n, st_parent[sp], count, l);
        uint32_t *ref = (uint32_t *)tt_rtc_child(c, rec);
        const float *cb = lv->box[l - 1] + 6 * (size_t)c0;
        for (uint32_t k = 0; k < 6; k++)
            for (uint32_t i = 0; i < count; i++) rec[k * S + i] = cb[6 * i + k];
        if (l == 1) {
            for (uint32_t i = 0; i < count; i++) {
                const uint32_t a = lv->first[0][c0 + i], e = lv->first[0][c0 + i + 1];
                ref[i] = put_leaf(&pk, lv->order + a, e - a);
            }
            continue;
        }
        const uint32_t first = pk.next_node;
        pk.next_node += count;
        for (uint32_t i = 0; i < count; i++) ref[i] = first + i;
        for (uint32_t i = count; i-- > 0;) {
            st_level[sp] = l - 1;
            st_j[sp] = c0 + i;
            st_index[sp] = first + i;
            st_parent[sp++] = n;
        }
    }
    if (pk.next_node != c->nodes || pk.fill.blocks != c->blocks)
        return tt_error(ctx, TT_ERR_INTERNAL,
                        "rtree compact layout: wrote %u of %u nodes and %llu of %u blocks",
                        pk.next_node, c->nodes, (unsigned long long)pk.fill.blocks, c->blocks);
    return TT_OK;
}
