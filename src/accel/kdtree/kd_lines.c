/* The engine's cache-line node layout (see kd_lines.h). */
#include "accel/kdtree/kd_lines.h"

#include <string.h>

#include "core/context.h"
#include "geometry/tri_block.h"

typedef struct kd_lines_builder {
    const tt_kd_node *nodes; /* the block copy's: leaves index blocks      */
    tt_kd_line *lines;
    uint32_t count, cap;
    const tt_tri_block *blocks; /* the block copy's 8-lane blocks           */
    tt_kd_block4 *small;        /* the 4-lane blocks, after the lines       */
    uint32_t small_count, small_cap;
    int overflow; /* a leaf the encoding cannot name                        */
} kd_lines_builder;

static uint32_t kd_lines_leaf(kd_lines_builder *b, uint32_t slot)
{
    const tt_kd_node n = b->nodes[slot];
    const uint32_t c = tt_kd_leaf_count(n.bits);
    if (c == 0) return TT_KD_LINE_EMPTY;
    const uint32_t blocks = tt_tri_block_count(c);
    if (c <= TT_KD_SMALL_W && b->small_count < b->small_cap) {
        tt_kd_block4 *q = &b->small[b->small_count++];
        const tt_tri_block *src = &b->blocks[n.u.first];
        for (int k = 0; k < 9; k++)
            for (uint32_t i = 0; i < TT_KD_SMALL_W; i++) q->v[k][i] = src->v[k][i];
        for (uint32_t i = 0; i < TT_KD_SMALL_W; i++) q->prim[i] = src->prim[i];
        const uint32_t at = (uint32_t)(((const char *)q - (const char *)b->lines) >> 5);
        return TT_KD_LINE_LEAF | TT_KD_LINE_SMALL << 27 | at;
    }
    if (blocks <= TT_KD_LINE_NMAX && n.u.first < TT_KD_LINE_INDEX)
        return TT_KD_LINE_LEAF | blocks << 27 | n.u.first;
    if (slot >= TT_KD_LINE_INDEX) {
        b->overflow = 1;
        return TT_KD_LINE_EMPTY;
    }
    return TT_KD_LINE_LEAF | slot;
}

/* Fills line `at` with the three levels below node slot `root`, then the
 * lines of its interior exits, each followed by its own subtree's lines
 * (depth first: 0-2% faster than a line's child lines side by side,
 * in-process A/B). */
static void kd_lines_fill(kd_lines_builder *b, uint32_t at, uint32_t root)
{
    uint32_t pos[15]; /* node slot at each position, UINT32_MAX: none      */
    tt_kd_line *L = &b->lines[at];
    memset(L, 0, sizeof *L);
    for (int h = 0; h < 15; h++) pos[h] = UINT32_MAX;
    pos[0] = root;
    for (uint32_t h = 0; h < 7; h++) {
        const uint32_t i = pos[h];
        if (i != UINT32_MAX && !tt_kd_is_leaf(b->nodes[i].bits)) {
            const tt_kd_node n = b->nodes[i];
            L->split[h] = n.u.split;
            L->axes |= (uint32_t)tt_kd_axis(n.bits) << (2u * h);
            pos[2 * h + 1] = tt_kd_left(i, n.bits);
            pos[2 * h + 2] = tt_kd_right(n.bits);
        } else {
            /* No plane: the walk passes on to the left child. */
            L->axes |= 3u << (2u * h);
            pos[2 * h + 1] = i;
        }
    }
    uint32_t child[8];
    for (int x = 0; x < 8; x++) {
        const uint32_t i = pos[7 + x];
        child[x] = UINT32_MAX;
        if (i == UINT32_MAX) L->exit[x] = TT_KD_LINE_EMPTY;
        else if (tt_kd_is_leaf(b->nodes[i].bits)) L->exit[x] = kd_lines_leaf(b, i);
        else child[x] = 0;
    }
    for (int x = 0; x < 8; x++)
        if (child[x] != UINT32_MAX) {
            L->exit[x] = child[x] = b->count++;
            kd_lines_fill(b, child[x], pos[7 + x]);
        }
}

void tt_kdtree_lines_free(tt_context *ctx, tt_kdtree *t)
{
    tt_free(ctx, t->line_mem);
    t->line_mem = NULL;
    t->line_count = 0;
    t->line_small = 0;
    t->block_view.lines = NULL;
    if (t->fast_view.blocks) t->fast_view.lines = NULL;
}

tt_status tt_kdtree_lines_build(tt_context *ctx, tt_kdtree *t)
{
    if (t->line_mem || !t->block_nodes) return TT_OK;
    if (t->view.empty) return TT_OK;
    /* Every line holds at least one interior node (or the one leaf of a
     * tree that is a leaf), and the walk counts lines in 27 bits. */
    uint64_t cap = 1, small = 0;
    for (uint32_t i = 0; i < t->node_slots; i++) {
        const uint32_t bits = t->nodes[i].bits;
        if (tt_kd_is_leaf(bits)) {
            const uint32_t c = tt_kd_leaf_count(bits);
            small += c > 0 && c <= TT_KD_SMALL_W;
            continue;
        }
        cap++;
        i += tt_kd_is_aug(bits); /* its extension slot */
    }
    if (cap >= TT_KD_LINE_INDEX || t->block_count >= TT_KD_LINE_INDEX) return TT_OK;
    /* The 4-lane blocks' offsets (32-byte units) must fit the index bits
     * below TT_KD_LINE_INDEX (which, with n 15, is EMPTY); without room
     * the small leaves keep their 8-lane blocks. */
    if ((cap * sizeof(tt_kd_line) + small * sizeof(tt_kd_block4)) >> 5 >= TT_KD_LINE_INDEX)
        small = 0;
    void *mem = tt_alloc(ctx, (size_t)cap * sizeof(tt_kd_line) +
                                  (size_t)small * sizeof(tt_kd_block4) + 63);
    if (!mem) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree: out of memory for node lines");
    tt_kd_line *lines = (tt_kd_line *)(((uintptr_t)mem + 63) & ~(uintptr_t)63);
    kd_lines_builder b = {t->block_nodes, lines, 1u, (uint32_t)cap,
                          t->block_view.blocks, (tt_kd_block4 *)(lines + cap), 0u,
                          (uint32_t)small, 0};
    kd_lines_fill(&b, 0, 0);
    if (b.overflow) {
        tt_free(ctx, mem);
        return TT_OK;
    }
    t->line_mem = mem;
    /* The 4-lane blocks were written after all cap lines: move them up to
     * the lines in use, and their exits' offsets with them. */
    if (b.small_count && b.count < cap) {
        memmove(lines + b.count, b.small, (size_t)b.small_count * sizeof(tt_kd_block4));
        const uint32_t delta = (uint32_t)((cap - b.count) * (sizeof(tt_kd_line) >> 5));
        for (uint32_t l = 0; l < b.count; l++)
            for (int x = 0; x < 8; x++) {
                const uint32_t e = lines[l].exit[x];
                if (e != TT_KD_LINE_EMPTY && (e & TT_KD_LINE_LEAF) &&
                    ((e >> 27) & 15u) == TT_KD_LINE_SMALL)
                    lines[l].exit[x] = e - delta;
            }
    }
    t->line_count = b.count;
    t->line_small = b.small_count;
    t->block_view.lines = b.lines;
    return TT_OK;
}
