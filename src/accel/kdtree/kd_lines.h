/* The engine's cache-line node layout: for the CPU's AVX2 / AVX-512 HTR
 * kernels, the tree's interior nodes are regrouped into treelets of three
 * levels, one 64-byte line each, so a ray's chain of dependent node loads
 * (about 37 interior nodes a primary ray on sibenik) touches a new line
 * every three levels instead of at nearly every far child of the depth-
 * first array. Built from the block copy of kd_blocks.h (its leaves are
 * encoded as block ranges), beside it: BTR, SLTR, SEQ, rays with a zero
 * direction component, the counting variants, scalar, packets, GPU and the
 * saved file keep the papers' 8-byte nodes.
 *
 * A line holds positions 0..6 in heap order (position h's children are
 * 2h + 1 and 2h + 2); children 7..14 are the line's exits, exit[h - 7].
 * Position h holds a plane (axis in bits 2h..2h+1 of `axes`, 0..2, and
 * split[h]) or none (axis 3: a leaf reached above the bottom level, or an
 * unused position): a walk passes through such a position to its left
 * child, so a leaf at position h sits at the exit below its leftmost
 * descendant. An exit is
 *   TT_KD_LINE_EMPTY                an empty leaf (or nothing)
 *   bit 31 clear                    the line the subtree continues in
 *   bit 31 set, n = bits 27..30     a leaf: 0 < n <= 14: its n blocks start
 *                                   at block bits 0..26; n == 15: a leaf of
 *                                   at most four triangles, its 4-lane
 *                                   block (tt_kd_block4) at byte offset
 *                                   (bits 0..26) << 5 from the lines' start;
 *                                   n == 0: bits 0..26 index the leaf in
 *                                   the block copy's nodes (a big or far
 *                                   leaf)
 * Lines are in depth-first order of the treelets; the 4-lane blocks follow
 * them in the same allocation, in the order the walk's build met them.
 *
 * The 4-lane blocks: most leaves a conference ray meets hold one or two
 * triangles (shadow rays: 57% of the 8-lane blocks tested), and their
 * 8-lane block is 320 bytes over five cache lines for 36 bytes of triangle.
 * The 4-lane copy (lanes 0..3 of the leaf's 8-lane block, NaN padding
 * included) is 160 bytes. Only the single-ray line walks read it; packets
 * and the node walks keep reading the 8-lane blocks. */
#ifndef TT_ACCEL_KDTREE_KD_LINES_H
#define TT_ACCEL_KDTREE_KD_LINES_H

#include <stdint.h>

#include "accel/kdtree/kd_tree.h"

#define TT_KD_LINE_EMPTY 0xFFFFFFFFu
#define TT_KD_LINE_LEAF 0x80000000u
#define TT_KD_LINE_INDEX 0x07FFFFFFu /* bits 0..26                         */
#define TT_KD_LINE_NMAX 14u          /* blocks an inline leaf can name     */
#define TT_KD_LINE_SMALL 15u         /* n of a leaf in a 4-lane block      */
#define TT_KD_SMALL_W 4u             /* lanes of a tt_kd_block4            */

typedef struct tt_kd_line {
    float split[7];
    uint32_t axes;
    uint32_t exit[8];
} tt_kd_line; /* 64 bytes; arrays of lines are allocated 64-byte aligned */

/* A leaf of at most four triangles: lanes 0..3 of its tt_tri_block. */
typedef struct tt_kd_block4 {
    float v[9][TT_KD_SMALL_W];
    uint32_t prim[TT_KD_SMALL_W];
} tt_kd_block4; /* 160 bytes, at 32-byte offsets from the lines' start */

/* Builds t->lines (and points t->block_view.lines at them) from the block
 * copy, which must exist. A tree the encoding cannot hold (over 2^27
 * blocks or node slots) simply gets none: the kernels then walk the block
 * copy's nodes. */
tt_status tt_kdtree_lines_build(tt_context *ctx, tt_kdtree *t);
void tt_kdtree_lines_free(tt_context *ctx, tt_kdtree *t);

#endif
