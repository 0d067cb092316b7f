/* The engine's leaf blocks: for the CPU's AVX2 / AVX-512 single-ray kernels,
 * every non-empty leaf's triangles are copied, in reference order, into
 * triangle blocks of its own (geometry/tri_block.h: 8 lanes, structure of
 * arrays, zero-area triangles and unused lanes NaN), so a leaf is tested
 * with plain vector loads from one or a few contiguous blocks instead of
 * reading each triangle through refs[] (a dependent load a triangle, and
 * an 8x8 transpose a group of eight). The kernels walk a copy of the nodes
 * whose leaves' u.first is the index of their first block (kd_layout.h's
 * tt_kd_view.blocks).
 *
 * Only those kernels read them: the counting variants (the papers'
 * statistics), the scalar and SSE4.2 kernels, packets, the GPU and the
 * saved file keep nodes[] and refs[] as they are; a loaded tree rebuilds
 * the blocks. The cost: 320 bytes a block (36 a triangle, 4 an id, lanes
 * padded to 8 per leaf) and a node copy, several times the tree itself. */
#ifndef TT_ACCEL_KDTREE_KD_BLOCKS_H
#define TT_ACCEL_KDTREE_KD_BLOCKS_H

#include <stddef.h>

#include "accel/kdtree/kd_tree.h"

/* Sets t->fast to isa's kernels and t->fast_view to what they walk,
 * building the blocks (from the scene's triangles tri) when the kernels
 * test leaves as blocks. t->view must be set. */
tt_status tt_kdtree_use_isa(tt_context *ctx, tt_kdtree *t, tt_isa isa, const float *tri,
                            size_t triangle_count);

/* Builds the block copy (t->block_nodes, block_mem, block_view) if t has
 * none. */
tt_status tt_kdtree_blocks_build(tt_context *ctx, tt_kdtree *t, const float *tri);

/* Frees the block copy; t->fast_view falls back to t->view, with the
 * scalar kernels if t->fast needed the blocks. */
void tt_kdtree_blocks_free(tt_context *ctx, tt_kdtree *t);

/* Bytes of the block copy (0 without one). */
size_t tt_kdtree_blocks_memory(const tt_kdtree *t);

#endif
