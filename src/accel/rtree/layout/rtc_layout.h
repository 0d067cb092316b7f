/* The R-tree's compact wide layout, shared by the CPU and GPU traversals:
 * only the tree's real nodes, in one array of fixed-size records, and the
 * leaves' triangles in SIMD blocks (geometry/tri_block.h). Against the
 * paper's complete level-order layout (rtree_packed.h), whose empty slots
 * are most of its memory, this costs memory in proportion to the triangles.
 *
 * A node is an interior node of the builder's tree (level >= 1); the
 * builder's leaves (level 0) are not nodes here but child references of
 * their level-1 parent. Node record n (`words` 32-bit words, a multiple of
 * 16, so records are 64-byte aligned like the array):
 *   floats [0, 6S):    the child boxes in structure of arrays, S = M
 *                      rounded up to a multiple of 4 (the narrowest SIMD
 *                      width): lo x[S], lo y[S], lo z[S], hi x[S], hi y[S],
 *                      hi z[S]. An unused child has all six bounds +inf,
 *                      the mark every slab test misses (as in
 *                      rtree_packed.h), so a SIMD kernel tests all S lanes.
 *   words [6S, 7S):    child references. Level >= 2: the child's node
 *                      index. Level 1: a leaf, its triangles lanes
 *                      [lane, lane + count) from the start of block `block`
 *                      (ref = block << 7 | (count - 1) << 3 | lane; 1 <=
 *                      count <= 16, so a leaf covers one or two blocks).
 *   word 7S:           the parent's node index (TT_INVALID_ID: the root).
 *   word 7S + 1:       entries (bits 0-7) and level (bits 8-15).
 * Node order: the root is node 0; the interior children of a node are
 * consecutive (so a node's position in its parent is its index minus the
 * parent's first child, which the stackless walk needs) and subtrees are
 * laid out depth first (a ray descending one subtree stays in one region).
 * Leaves are in the same depth-first order, packed into the blocks first
 * fit in that order: a leaf of up to 8 triangles goes into the lanes left
 * in the last block when they suffice (so small leaves share blocks), else
 * into fresh blocks. A block is always tested whole, so a leaf's test may
 * also test its neighbours' triangles: harmless, they are real triangles of
 * the scene (any hit found is a true hit, and the closest one is still
 * found in its own leaf), and SIMD pays for all 8 lanes anyway; what it
 * saves is the unused lanes' memory. */
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

/* A leaf reference's parts, and the blocks its lanes touch. */
#define TT_RTC_LEAF_BLOCK_BITS 25 /* blocks < 2^25: 2^28 triangle lanes */
TT_HD uint32_t tt_rtc_leaf_lane(uint32_t ref) { return ref & 7u; }
TT_HD uint32_t tt_rtc_leaf_count(uint32_t ref) { return ((ref >> 3) & 15u) + 1u; }
TT_HD uint32_t tt_rtc_leaf_ref(uint32_t block, uint32_t lane, uint32_t count)
{
    return block << 7 | (count - 1u) << 3 | lane;
}
TT_HD const tt_tri_block *tt_rtc_leaf_blocks(const tt_rtc *t, uint32_t ref, uint32_t *nblocks)
{
    *nblocks = (tt_rtc_leaf_lane(ref) + tt_rtc_leaf_count(ref) + TT_TRI_BLOCK_W - 1) /
               TT_TRI_BLOCK_W;
    return t->block + (ref >> 7);
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
