/* The engine's leaf blocks (see kd_blocks.h). */
#include "accel/kdtree/kd_blocks.h"

#include "accel/kdtree/kd_lines.h"
#include "accel/kdtree/build/kd_memory.h"

#include <stdint.h>
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
           (size_t)t->line_count * sizeof(tt_kd_line) +
           (size_t)t->line_small * sizeof(tt_kd_block4);
}

tt_status tt_kdtree_blocks_build(tt_context *ctx, tt_kdtree *t, const float *tri)
{
    if (t->block_nodes) return TT_OK;
    uint64_t count = 0;
    KD_FOR_NODES(t, i, {
        const tt_kd_node n = t->nodes[i];
        if (tt_kd_is_leaf(n.bits)) count += tt_tri_block_count(tt_kd_leaf_count(n.bits));
    })
    if (count > UINT32_MAX)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree: %llu leaf blocks are too many",
                        (unsigned long long)count);
    tt_kd_node *nodes = tt_alloc_array(ctx, t->node_slots, sizeof *nodes);
    void *mem = count < SIZE_MAX / sizeof(tt_tri_block)
                    ? tt_alloc(ctx, (size_t)count * sizeof(tt_tri_block) + 63)
                    : NULL;
    /* the leaves to pack, listed first so that threads can pack them */
    uint32_t *leaf = tt_alloc_array(ctx, t->leaves ? t->leaves : 1, sizeof *leaf);
    if (!nodes || !mem || !leaf) {
        tt_free(ctx, nodes);
        tt_free(ctx, mem);
        tt_free(ctx, leaf);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree: out of memory for leaf blocks");
    }
    kd_advise_huge(mem, (size_t)count * sizeof(tt_tri_block) + 63);
    /* The kernels load blocks with aligned loads. */
    tt_tri_block *blocks = (tt_tri_block *)(((uintptr_t)mem + 63) & ~(uintptr_t)63);
    memcpy(nodes, t->nodes, (size_t)t->node_slots * sizeof *nodes);
    /* The blocks' places first (a prefix count), then the packing, which
     * ran alone on one thread at the end of every build: leaves are
     * packed on the context's threads, each into its own place, so the
     * blocks are the same. (A leaf past t->leaves, were the count ever
     * short, is packed here.) */
    uint32_t next = 0, packs = 0;
    KD_FOR_NODES(t, i, {
        const tt_kd_node n = t->nodes[i];
        if (!tt_kd_is_leaf(n.bits)) continue;
        const uint32_t c = tt_kd_leaf_count(n.bits);
        nodes[i].u.first = c ? next : 0u;
        if (c == 0) continue; /* (an empty scene has no refs[] at all) */
        if (packs < t->leaves) leaf[packs++] = i;
        else tt_tri_block_pack(tri, t->refs + n.u.first, c, blocks + next);
        next += tt_tri_block_count(c);
    })
#pragma omp parallel for schedule(dynamic, 1024) num_threads(tt_context_team(ctx)) if (packs > 8192)
    for (uint32_t j = 0; j < packs; j++) {
        const tt_kd_node n = t->nodes[leaf[j]];
        tt_tri_block_pack(tri, t->refs + n.u.first, tt_kd_leaf_count(n.bits), blocks + nodes[leaf[j]].u.first);
    }
    tt_free(ctx, leaf);
    t->block_nodes = nodes;
    t->block_mem = mem;
    t->block_count = next;
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
