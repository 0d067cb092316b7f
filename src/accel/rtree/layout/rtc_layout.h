/* The R-tree's compact wide layout, shared by the CPU and GPU traversals:
 * only the tree's real nodes, in one array of fixed-size records, and the
 * leaves' triangles in SIMD blocks (geometry/tri_block.h). Against the
 * paper's complete level-order layout (rtree_packed.h), whose empty slots
 * are most of its memory, this costs memory in proportion to the triangles.
 * Announced to the other traversals in notes/rtc-format.md: read a record
 * through the accessors below.
 *
 * A node is an interior node of the builder's tree; the builder's leaves
 * are not nodes here but tagged child references. Node record n (`words`
 * 32-bit words, a multiple of 16, so records are 64-byte aligned like the
 * array):
 *   floats [0, 6S):    the child boxes in structure of arrays, S = M
 *                      rounded up to a multiple of 4 (the narrowest SIMD
 *                      width): lo x[S], lo y[S], lo z[S], hi x[S], hi y[S],
 *                      hi z[S]. An unused child has all six bounds +inf,
 *                      the mark every slab test misses (as in
 *                      rtree_packed.h), so a SIMD kernel tests all S lanes.
 *   words [6S, 7S):    child references: a node index (bit 31 clear), or a
 *                      leaf (bit 31 set): its triangles are lanes [lane,
 *                      lane + count) from the start of block `block` (ref =
 *                      1 << 31 | block << 7 | (count - 1) << 3 | lane; 1 <=
 *                      count <= 16, so a leaf covers one or two blocks);
 *                      TT_INVALID_ID for an unused entry.
 *   word 7S:           the parent's node index (TT_INVALID_ID: the root).
 *   word 7S + 1:       entries (bits 0-7) and level (bits 8-15: 1 + the
 *                      height of the node's subtree above its leaves; every
 *                      child of a level-1 node is a leaf).
 * Every leaf is on one level (an R-tree): the children of a level-1 node
 * are all leaves, those of the others all nodes, and the traversals go by
 * the level; the tag lets a reference say what it is on its own (the
 * check, and code that walks references without levels).
 *
 * Quantised child boxes (8-bit offsets in the node's box, 192 bytes a
 * record instead of 512 for M = 16) were built and measured (commit
 * 962eb8f, notes/rtree.md): single rays were 23-27% slower on Sibenik. A
 * ray's walk is a chain of dependent node tests, and decoding adds its
 * latency to every link, while the float records mostly come from the
 * caches anyway.
 *
 * Node order: the root is node 0; the interior children of a node are
 * consecutive (so a node's entry position in its parent is its index
 * minus the parent's first child's, which the stackless walk needs) and
 * subtrees are laid out depth first (a ray descending one subtree stays in
 * one region). Leaves are in the same depth-first order, packed into the
 * blocks first fit in that order: a leaf of up to 8 triangles goes into
 * the lanes left in the last block when they suffice (so small leaves
 * share blocks), else into fresh blocks; a node's leaves lie within 2 M
 * blocks from its first leaf entry's, which is the lowest. A block is
 * always tested whole, so a leaf's test may also test its neighbours'
 * triangles: harmless, they are real triangles of the scene (any hit found
 * is a true hit, and the closest one is still found in its own leaf), and
 * SIMD pays for all 8 lanes anyway; what it saves is the unused lanes'
 * memory. */
#ifndef TT_ACCEL_RTREE_RTC_LAYOUT_H
#define TT_ACCEL_RTREE_RTC_LAYOUT_H

#include <stdint.h>

#include "accel/rtree/layout/rtree_packed.h" /* the box test, TT_RT_MAX_M, TT_RT_INLINE */
#include "geometry/tri_block.h"

/* Entries of a traversal stack: a node's M - 1 farther children wait per
 * level, and the builder has at most 32 levels (the packer checks). */
#define TT_RTC_STACK_SIZE 512

typedef struct tt_rtc {
    uint32_t M;      /* entries per node                                   */
    uint32_t S;      /* SoA row stride: M rounded up to 4                  */
    uint32_t words;  /* 32-bit words per node record                       */
    uint32_t nodes;  /* records (>= 1: an empty tree is a root without entries) */
    uint32_t blocks;
    uint32_t triangles;
    uint32_t height; /* the root's level (>= 1)                            */
    const float *node;           /* nodes * words words, 64-byte aligned   */
    const tt_tri_block *block;   /* 64-byte aligned                        */
} tt_rtc;

/* Record n's start (its child boxes). */
TT_HD const float *tt_rtc_node(const tt_rtc *t, uint32_t n)
{
    return t->node + (size_t)n * t->words;
}
/* The child boxes' rows: bound k (lo x, lo y, lo z, hi x, hi y, hi z) of
 * child i is rows[k S + i]. */
TT_HD const float *tt_rtc_boxes(const float *rec) { return rec; }
TT_HD const uint32_t *tt_rtc_child(const tt_rtc *t, const float *rec)
{
    return (const uint32_t *)(rec + 6 * t->S);
}
TT_HD uint32_t tt_rtc_parent(const tt_rtc *t, const float *rec)
{
    return TT_LDG((const uint32_t *)(rec + 7 * t->S));
}
TT_HD uint32_t tt_rtc_count(const tt_rtc *t, const float *rec)
{
    return TT_LDG((const uint32_t *)(rec + 7 * t->S) + 1) & 0xffu;
}
TT_HD uint32_t tt_rtc_level(const tt_rtc *t, const float *rec)
{
    return (TT_LDG((const uint32_t *)(rec + 7 * t->S) + 1) >> 8) & 0xffu;
}
/* The mask of a record's used entries (bit i: entry i). */
TT_HD uint32_t tt_rtc_used(const tt_rtc *t, const float *rec)
{
    return (uint32_t)(((uint64_t)1 << tt_rtc_count(t, rec)) - 1u);
}

/* Child i's box (lo x y z, hi x y z). */
TT_HD void tt_rtc_child_box(const tt_rtc *t, const float *rec, uint32_t i, float out[6])
{
    for (uint32_t k = 0; k < 6; k++) out[k] = TT_LDG(rec + k * t->S + i);
}

/* A child reference: a leaf (bit 31) or a node index. */
#define TT_RTC_LEAF_BIT 0x80000000u
#define TT_RTC_LEAF_BLOCK_BITS 24 /* blocks < 2^24: 2^27 triangle lanes */
TT_HD int tt_rtc_is_leaf(uint32_t ref) { return (ref & TT_RTC_LEAF_BIT) != 0; }
TT_HD uint32_t tt_rtc_leaf_lane(uint32_t ref) { return ref & 7u; }
TT_HD uint32_t tt_rtc_leaf_count(uint32_t ref) { return ((ref >> 3) & 15u) + 1u; }
TT_HD uint32_t tt_rtc_leaf_block(uint32_t ref) { return (ref & ~TT_RTC_LEAF_BIT) >> 7; }
TT_HD uint32_t tt_rtc_leaf_ref(uint32_t block, uint32_t lane, uint32_t count)
{
    return TT_RTC_LEAF_BIT | block << 7 | (count - 1u) << 3 | lane;
}
TT_HD const tt_tri_block *tt_rtc_leaf_blocks(const tt_rtc *t, uint32_t ref, uint32_t *nblocks)
{
    *nblocks = (tt_rtc_leaf_lane(ref) + tt_rtc_leaf_count(ref) + TT_TRI_BLOCK_W - 1) /
               TT_TRI_BLOCK_W;
    return t->block + tt_rtc_leaf_block(ref);
}

/* A free record, which no reference names: the slack of a layout updated
 * in place (rtree/update/rtree_dyn.h keeps groups of M records per node).
 * Every child box +inf, every reference and the parent TT_INVALID_ID, no
 * entries, level 0 (a used record's level is >= 1). */
static inline int tt_rtc_is_free(const tt_rtc *t, const float *rec)
{
    const uint32_t *w = (const uint32_t *)(rec + 6 * t->S);
    if (w[t->S] != TT_INVALID_ID || w[t->S + 1] != 0) return 0;
    for (uint32_t i = 0; i < t->S; i++)
        if (w[i] != TT_INVALID_ID) return 0;
    for (uint32_t i = 0; i < 6 * t->S; i++)
        if (!(rec[i] == TT_INF)) return 0;
    return 1;
}

/* The record size for M entries: 7 S + 2 words rounded up to 16 words. */
static inline uint32_t tt_rtc_words(uint32_t M)
{
    const uint32_t S = (M + 3u) & ~3u;
    return (7u * S + 2u + 15u) & ~15u;
}

/* The closing step of every compact traversal: *hit gets the closest hit
 * (h) unless this is an any-hit query. */
TT_HD int tt_rtc_finish(int any, const tt_hit *h, tt_hit *hit)
{
    if (!any) {
        hit->t = h->prim == TT_INVALID_ID ? TT_INF : h->t;
        hit->u = h->u;
        hit->v = h->v;
        hit->prim = h->prim;
    }
    return h->prim != TT_INVALID_ID;
}

#endif
