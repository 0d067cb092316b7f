/* Packing the builder's pointer tree (any builder: insertion or bulk
 * loading, they all fill rt_builder) into the compact layout
 * (rtc_layout.h). Boxes are quantised from the pointer tree's, never
 * recomputed, so the check (rtc_check.c) also verifies that the builder
 * kept every node box the exact union of its entries (each decoded child
 * box is the tightest around the exact one, and each node's frame starts
 * at its exact box). */
#include <math.h>
#include <string.h>

#include "accel/rtree/rtc.h"
#include "accel/rtree/rtree_box.h"

_Static_assert(TT_RT_MAX_M <= 16 && TT_TRI_BLOCK_W == 8,
               "a leaf reference holds a lane in a block (3 bits) and count - 1 (4 bits)");
_Static_assert(TT_RT_MAX_M <= 32, "entry masks are 32 bits");

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

/* ------------------------------------------------------- quantisation */

/* The frame of an axis whose node box is [lo, hi]: origin lo, and the
 * least scale (tried upwards from the quotient) with which 255 decodes to
 * hi or beyond. Flat: scale 0. The quotient is taken in double so that a
 * box spanning most of the float range does not overflow. */
static float axis_scale(float lo, float hi)
{
    if (!(hi > lo)) return 0.0f;
    float s = (float)(((double)hi - (double)lo) / 255.0);
    if (!(s > 0.0f)) s = 1e-45f; /* the smallest subnormal */
    for (int k = 0; tt_rtc_decode(lo, s, 255) < hi; k++)
        s = k < 8 ? nextafterf(s, TT_INF) : 2.0f * s;
    return s;
}

/* The tightest q whose decoding is at most v (lo bounds) or at least v (hi
 * bounds), v within the frame. */
static uint8_t quant_lo(float o, float s, float v)
{
    if (s == 0.0f) return 0;
    double g = floor(((double)v - (double)o) / (double)s);
    int q = g < 0.0 ? 0 : g > 255.0 ? 255 : (int)g;
    while (q > 0 && tt_rtc_decode(o, s, (uint32_t)q) > v) q--;
    while (q < 255 && tt_rtc_decode(o, s, (uint32_t)q + 1) <= v) q++;
    return (uint8_t)q;
}

static uint8_t quant_hi(float o, float s, float v)
{
    if (s == 0.0f) return 0;
    double g = ceil(((double)v - (double)o) / (double)s);
    int q = g < 0.0 ? 0 : g > 255.0 ? 255 : (int)g;
    while (q < 255 && tt_rtc_decode(o, s, (uint32_t)q) < v) q++;
    while (q > 0 && tt_rtc_decode(o, s, (uint32_t)q - 1) >= v) q--;
    return (uint8_t)q;
}

void rtc_set_boxes(const tt_rtc *c, float *rec, const float *box, uint32_t stride, uint32_t count)
{
    const uint32_t S = c->S;
    float node[6];
    rt_box_empty(node);
    for (uint32_t i = 0; i < count; i++)
        for (uint32_t a = 0; a < 3; a++) {
            node[a] = rt_min(node[a], box[a * stride + i]);
            node[a + 3] = rt_max(node[a + 3], box[(a + 3) * stride + i]);
        }
    uint8_t *q = (uint8_t *)(rec + TT_RTC_QBOX);
    for (uint32_t a = 0; a < 3; a++) {
        const float o = count ? node[a] : 0.0f;
        const float s = count ? axis_scale(node[a], node[a + 3]) : 0.0f;
        rec[TT_RTC_ORIGIN + a] = o;
        rec[TT_RTC_SCALE + a] = s;
        for (uint32_t i = 0; i < S; i++) {
            q[a * S + i] = i < count ? quant_lo(o, s, box[a * stride + i]) : 255;
            q[(a + 3) * S + i] = i < count ? quant_hi(o, s, box[(a + 3) * stride + i]) : 0;
        }
    }
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

/* Empties record n: no entries (quantised lo 255, hi 0; no reference),
 * the header. */
static float *record_init(packer *pk, uint32_t n, uint32_t parent, uint32_t count, uint32_t level)
{
    const uint32_t S = pk->c->S;
    float *rec = pk->node + (size_t)n * pk->c->words;
    for (uint32_t i = 0; i < pk->c->words; i++) rec[i] = 0.0f;
    uint8_t *q = (uint8_t *)(rec + TT_RTC_QBOX);
    memset(q, 255, 3 * S);
    uint32_t *w = (uint32_t *)rec;
    w[TT_RTC_PARENT] = parent;
    w[TT_RTC_HEADER] = count | level << 8;
    uint32_t *ref = (uint32_t *)tt_rtc_child(pk->c, rec);
    for (uint32_t i = 0; i < S; i++) ref[i] = TT_INVALID_ID;
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
    c->triangles = b->triangles;
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
    c->node = node;
    c->block = block;
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
