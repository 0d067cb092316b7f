/* The kd-tree's memory layout, shared by the CPU traversals and (later) the
 * CUDA tracer: plain arrays and TT_HD accessors only.
 *
 * Nodes are 8 bytes and stored in depth-first order, so the left child of an
 * interior node follows it directly and only the right child needs an index:
 *
 *   interior: u.split = split position (float)
 *             bits    = right child << 3 | augmented << 2 | axis (0, 1, 2)
 *   leaf:     u.first = index of its first triangle reference in refs[]
 *             bits    = reference count << 3 | 3
 *
 * An augmented node (Havran & Bittner: it carries a box and a link to the
 * nearest augmented ancestor) is followed by one extension slot whose u.first
 * is the index of its record in the separate aug[] array; its left child is
 * then at i + 2 instead of i + 1. Only interior nodes are augmented (as in
 * the paper, where the alternative to an augmented node is "a simple interior
 * node"); the root always is, with record 0, so aug[0] holds the scene box
 * every traversal clips against. Keeping the boxes out of line keeps the
 * common node at 8 bytes, and sparse boxes cost 8 + 32 bytes each. */
#ifndef TT_ACCEL_KDTREE_KD_LAYOUT_H
#define TT_ACCEL_KDTREE_KD_LAYOUT_H

#include <stdint.h>

#include "geometry/hd.h"

/* Deepest tree the builder makes; the traversal stacks hold one entry a
 * level, so TT_KD_STACK > TT_KD_MAX_DEPTH keeps them from overflowing. */
#define TT_KD_MAX_DEPTH 60
#define TT_KD_STACK 64

#ifndef TT_KD_SPARE
/* The budget of the exact stackless traversals' near-tie search per ray,
 * in descents (see tt_kd_budget in kd_trace_common.h). On the shared
 * scenes' views (800x600, primary and shadow rays) 98-100 % of the rays
 * need none, all but a few in 1e5 need fewer than 16 and none needs 256,
 * so none falls back (tests/accel/kdtree/test_fallback_views.c keeps
 * watch); on a scene 1e5 from the origin, whose split planes all lie
 * within one rounding band, nearly every ray would need thousands and
 * falls back instead. A fallback costs about one more traversal of the
 * ray, so a bigger budget gains nothing. */
#define TT_KD_SPARE 256u
#endif

#define TT_KD_LEAF 3u
#define TT_KD_AUG_BIT 4u
/* A node index must fit the 29 bits left above axis and flag. */
#define TT_KD_MAX_NODES (1u << 29)
#define TT_KD_NO_PARENT 0xFFFFFFFFu

typedef struct tt_kd_node {
    union {
        float split;
        uint32_t first;
    } u;
    uint32_t bits;
} tt_kd_node;

/* A sparse box: the node's cell, its nearest augmented ancestor (an index
 * into the same array, TT_KD_NO_PARENT for the root) and the node itself. */
typedef struct tt_kd_aug {
    float lo[3];
    float hi[3];
    uint32_t parent;
    uint32_t node;
} tt_kd_aug;

struct tt_tri_block; /* geometry/tri_block.h */
struct tt_kd_line;   /* kd_lines.h            */

/* Everything a traversal reads, as plain pointers (device pointers on the
 * GPU). tri is the scene's flat triangle array, 9 floats a triangle.
 *
 * blocks: NULL, except in the view the CPU's AVX2 / AVX-512 single-ray
 * kernels walk (kd_blocks.h): there `nodes` is a copy of the tree's nodes
 * whose leaves' u.first index blocks[] (each leaf's triangles, copied in
 * reference order) instead of refs[].
 *
 * lines: NULL, except in that view when its nodes are also regrouped into
 * cache lines (kd_lines.h), which those kernels' HTR walks instead. */
typedef struct tt_kd_view {
    const tt_kd_node *nodes;
    const uint32_t *refs;
    const float *tri;
    const tt_kd_aug *aug;
    uint32_t aug_count;
    int empty; /* no triangles: every ray misses                             */
    const struct tt_tri_block *blocks;
    const struct tt_kd_line *lines;
} tt_kd_view;

TT_HD int tt_kd_is_leaf(uint32_t bits) { return (bits & 3u) == TT_KD_LEAF; }
TT_HD int tt_kd_axis(uint32_t bits) { return (int)(bits & 3u); }
TT_HD uint32_t tt_kd_is_aug(uint32_t bits) { return (bits >> 2) & 1u; }
TT_HD uint32_t tt_kd_right(uint32_t bits) { return bits >> 3; }
TT_HD uint32_t tt_kd_left(uint32_t node, uint32_t bits) { return node + 1u + tt_kd_is_aug(bits); }
TT_HD uint32_t tt_kd_leaf_count(uint32_t bits) { return bits >> 3; }

/* The aug[] record of an augmented interior node. */
TT_HD uint32_t tt_kd_aug_index(const tt_kd_node *nodes, uint32_t node)
{
    return TT_LDG(&nodes[node + 1].u.first);
}

#endif
