/* The engine's leaf blocks (see kd_blocks.h). */
#include "accel/kdtree/kd_blocks.h"

#include "accel/kdtree/kd_lines.h"

#include <stdint.h>
#include <math.h>
#include <string.h>

#include "core/context.h"
#include "geometry/tri_block.h"

/* Calls fn(ctx, i) for every real node slot i (extension slots skipped):
 * nodes are depth first, and an augmented interior node's extension slot
 * follows it directly. */
#define KD_FOR_NODES(t, i, body)                                                                 \
    for (uint32_t i = 0; i < (t)->node_slots; i += 1u + (!tt_kd_is_leaf((t)->nodes[i].bits) &&  \
                                                         tt_kd_is_aug((t)->nodes[i].bits))) {    \
        body                                                                                     \
    }

void tt_kdtree_blocks_free(tt_context *ctx, tt_kdtree *t)
{
    tt_kdtree_lines_free(ctx, t);
    tt_free(ctx, t->block_nodes);
    tt_free(ctx, t->block_mem);
    t->block_nodes = NULL;
    t->block_mem = NULL;
    t->block_count = 0;
    memset(&t->block_view, 0, sizeof t->block_view);
    if (t->fast.blocks) t->fast = tt_kd_cpu_kernels(TT_ISA_SCALAR, 0);
    t->fast_view = t->view;
}

size_t tt_kdtree_blocks_memory(const tt_kdtree *t)
{
    if (!t->block_nodes) return 0;
    return (size_t)t->node_slots * sizeof(tt_kd_node) +
           (size_t)t->block_count * sizeof(tt_tri_block) +
           (size_t)t->line_count * sizeof(tt_kd_line);
}

/* Where a leaf of c triangles starts in the lanes, the next free lane
 * being `next`: right there when the leaf then still touches no more
 * blocks than tt_tri_block_count(c) (so no leaf costs more block tests than
 * in blocks of its own), else at the next block. */
static uint64_t kd_lane_start(uint64_t next, uint32_t c)
{
    const uint64_t in = next % TT_TRI_BLOCK_W;
    if (in + c > (uint64_t)TT_TRI_BLOCK_W * tt_tri_block_count(c)) return next - in + TT_TRI_BLOCK_W;
    return next;
}

/* Lane `lane` of the blocks gets triangle id (tt_tri_block_pack's rules:
 * zero-area triangles NaN). */
static void kd_lane_put(tt_tri_block *blocks, uint64_t lane, const float *tri, uint32_t id)
{
    tt_tri_block *b = &blocks[lane / TT_TRI_BLOCK_W];
    const uint32_t i = (uint32_t)(lane % TT_TRI_BLOCK_W);
    const float *v = tri + 9 * (size_t)id;
    const int dead = tt_tri_is_degenerate(v, v + 3, v + 6);
    for (int c = 0; c < 9; c++) b->v[c][i] = dead ? NAN : v[c];
    b->prim[i] = id;
}

tt_status tt_kdtree_blocks_build(tt_context *ctx, tt_kdtree *t, const float *tri)
{
    if (t->block_nodes) return TT_OK;
    uint64_t lanes = 0;
    KD_FOR_NODES(t, i, {
        const tt_kd_node n = t->nodes[i];
        const uint32_t c = tt_kd_is_leaf(n.bits) ? tt_kd_leaf_count(n.bits) : 0u;
        if (c) lanes = kd_lane_start(lanes, c) + c;
    })
    const uint64_t count = (lanes + TT_TRI_BLOCK_W - 1) / TT_TRI_BLOCK_W;
    if (lanes > UINT32_MAX)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree: %llu leaf block lanes are too many",
                        (unsigned long long)lanes);
    tt_kd_node *nodes = tt_alloc_array(ctx, t->node_slots, sizeof *nodes);
    void *mem = count < SIZE_MAX / sizeof(tt_tri_block)
                    ? tt_alloc(ctx, (size_t)count * sizeof(tt_tri_block) + 63)
                    : NULL;
    if (!nodes || !mem) {
        tt_free(ctx, nodes);
        tt_free(ctx, mem);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree: out of memory for leaf blocks");
    }
    /* The kernels load blocks with aligned loads. */
    tt_tri_block *blocks = (tt_tri_block *)(((uintptr_t)mem + 63) & ~(uintptr_t)63);
    /* Lanes no leaf takes: NaN, never hit (and masked off anyway). */
    for (uint64_t j = 0; j < count; j++) {
        for (int c = 0; c < 9; c++)
            for (int i = 0; i < TT_TRI_BLOCK_W; i++) blocks[j].v[c][i] = NAN;
        for (int i = 0; i < TT_TRI_BLOCK_W; i++) blocks[j].prim[i] = TT_INVALID_ID;
    }
    memcpy(nodes, t->nodes, (size_t)t->node_slots * sizeof *nodes);
    uint64_t next = 0;
    KD_FOR_NODES(t, i, {
        const tt_kd_node n = t->nodes[i];
        if (!tt_kd_is_leaf(n.bits)) continue;
        const uint32_t c = tt_kd_leaf_count(n.bits);
        nodes[i].u.first = 0u;
        if (c == 0) continue; /* (an empty scene has no refs[] at all) */
        next = kd_lane_start(next, c);
        nodes[i].u.first = (uint32_t)next;
        for (uint32_t j = 0; j < c; j++) kd_lane_put(blocks, next + j, tri, t->refs[n.u.first + j]);
        next += c;
    })
    t->block_nodes = nodes;
    t->block_mem = mem;
    t->block_count = (uint32_t)count;
    t->block_view = t->view;
    t->block_view.nodes = nodes;
    t->block_view.blocks = blocks;
    return tt_kdtree_lines_build(ctx, t);
}

tt_status tt_kdtree_use_isa(tt_context *ctx, tt_kdtree *t, tt_isa isa, const float *tri,
                            size_t triangle_count)
{
    const tt_kd_kernels k = tt_kd_cpu_kernels(isa, triangle_count);
    if (!k.blocks) {
        tt_kdtree_blocks_free(ctx, t);
    } else {
        const tt_status st = tt_kdtree_blocks_build(ctx, t, tri);
        if (st != TT_OK) return st;
    }
    t->fast = k;
    t->fast_view = k.blocks ? t->block_view : t->view;
    return TT_OK;
}
