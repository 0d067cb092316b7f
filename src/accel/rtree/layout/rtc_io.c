/* The compact layout (rtc_layout.h) in a saved file: its scalar fields as
 * one array of words, the node records and the triangle blocks verbatim.
 * Written generically (header words + the two arrays), so a change of the
 * record only needs RT_IO_COMPACT_VERSION bumped. Loading uses both arrays
 * in place from the mapping (both sections are 64-byte aligned, as the
 * kernels' aligned loads need) after checking every reference. */
#include <math.h>
#include <string.h>

#include "accel/accel_io.h"
#include "accel/rtree/rtree_io.h"

enum { H_M, H_S, H_WORDS, H_NODES, H_BLOCKS, H_TRIANGLES, H_HEIGHT, H_COUNT };

tt_status rtc_io_save(tt_context *ctx, const rtc_tree *t, tt_af_writer *w)
{
    uint32_t h[H_COUNT];
    const tt_rtc *c = &t->c;
    h[H_M] = c->M;
    h[H_S] = c->S;
    h[H_WORDS] = c->words;
    h[H_NODES] = c->nodes;
    h[H_BLOCKS] = c->blocks;
    h[H_TRIANGLES] = c->triangles;
    h[H_HEIGHT] = c->height;
    w->layout = RT_IO_LAYOUT_COMPACT;
    w->layout_version = RT_IO_COMPACT_VERSION;
    tt_status st = tt_af_add_copy(ctx, w, TT_AF_SEC_RTC_HEADER, 4, H_COUNT, h);
    if (st == TT_OK)
        st = tt_af_add(ctx, w, TT_AF_SEC_RTC_NODES, 4, (uint64_t)c->nodes * c->words, c->node);
    if (st == TT_OK)
        st = tt_af_add(ctx, w, TT_AF_SEC_RTC_BLOCKS, sizeof(tt_tri_block), c->blocks, c->block);
    return st;
}

static int is_pos_inf(float x) { return isinf(x) && x > 0.0f; }

/* Record n: its counts, levels, references and unused slots. A tree
 * updated in place (rtree/update/) is saved in its slack layout: free
 * records (tt_rtc_is_free) between the used ones, and a node's group of
 * children may lie before it. Levels fall by one along every reference
 * and every child names its parent, so no walk can cycle. */
static tt_status check_node(tt_context *ctx, const tt_af_file *f, const tt_rtc *c, uint32_t n)
{
    const float *rec = tt_rtc_node(c, n);
    const uint32_t *ref = tt_rtc_child(c, rec);
    const uint32_t count = tt_rtc_count(c, rec), level = tt_rtc_level(c, rec);
    const uint32_t parent = tt_rtc_parent(c, rec);
    if (n != 0 && tt_rtc_is_free(c, rec)) return TT_OK;
    if (count > c->M || level < 1 || level > c->height)
        return tt_af_bad(ctx, f, "node %u: %u entries on level %u (M = %u, height %u)", n, count,
                         level, c->M, c->height);
    if (n == 0 ? (parent != TT_INVALID_ID || level != c->height) : (parent >= c->nodes || parent == n))
        return tt_af_bad(ctx, f, "node %u: parent %u / level %u out of range", n, parent, level);
    for (uint32_t i = count; i < c->S; i++)
        for (uint32_t k = 0; k < 6; k++)
            if (!is_pos_inf(rec[k * c->S + i]))
                return tt_af_bad(ctx, f, "node %u: unused slot %u has a finite box", n, i);
    for (uint32_t i = 0; i < count; i++) {
        if (level >= 2) {
            const uint32_t ch = ref[i];
            if (ch == 0 || ch >= c->nodes || ch != ref[0] + i)
                return tt_af_bad(ctx, f, "node %u: child %u is node %u (of %u), out of order",
                                 n, i, ch, c->nodes);
            const float *crec = tt_rtc_node(c, ch);
            if (tt_rtc_level(c, crec) != level - 1 || tt_rtc_parent(c, crec) != n)
                return tt_af_bad(ctx, f, "node %u: child %u's level or parent is wrong", n, ch);
        } else {
            if (!tt_rtc_is_leaf(ref[i]))
                return tt_af_bad(ctx, f, "node %u: entry %u on level 1 is not a leaf", n, i);
            const uint32_t block = tt_rtc_leaf_block(ref[i]);
            uint32_t nb;
            (void)tt_rtc_leaf_blocks(c, ref[i], &nb);
            if ((uint64_t)block + nb > c->blocks)
                return tt_af_bad(ctx, f, "node %u: leaf %u reaches block %u of %u", n, i,
                                 block + nb - 1, c->blocks);
        }
    }
    return TT_OK;
}

tt_status rtc_io_load(tt_context *ctx, const tt_af_file *f, uint32_t triangles, rtc_tree *t)
{
    if (f->h->layout_version != RT_IO_COMPACT_VERSION)
        return tt_error(ctx, TT_ERR_UNSUPPORTED,
                        "%s: compact R-tree records of version %u; this library reads version %u: "
                        "rebuild the structure", f->name, f->h->layout_version,
                        RT_IO_COMPACT_VERSION);
    const uint32_t *h;
    tt_status st = tt_af_get_n(ctx, f, TT_AF_SEC_RTC_HEADER, 4, H_COUNT, (const void **)&h);
    if (st != TT_OK) return st;
    tt_rtc *c = &t->c;
    memset(c, 0, sizeof *c);
    c->M = h[H_M];
    c->S = h[H_S];
    c->words = h[H_WORDS];
    c->nodes = h[H_NODES];
    c->blocks = h[H_BLOCKS];
    c->triangles = h[H_TRIANGLES];
    c->height = h[H_HEIGHT];
    if (c->M < 4 || c->M > TT_RT_MAX_M || c->S != ((c->M + 3u) & ~3u) ||
        c->words != tt_rtc_words(c->M))
        return tt_af_bad(ctx, f, "M = %u, stride %u, %u words a record: not this library's "
                         "compact layout", c->M, c->S, c->words);
    if (c->nodes < 1 || c->triangles != triangles || c->height < 1 || c->height > 255 ||
        c->height * c->M > TT_RTC_STACK_SIZE ||
        c->blocks >= (uint32_t)1 << TT_RTC_LEAF_BLOCK_BITS)
        return tt_af_bad(ctx, f, "%u nodes, %u blocks, %u triangles, height %u: out of range",
                         c->nodes, c->blocks, c->triangles, c->height);
    const void *node, *block;
    st = tt_af_get_n(ctx, f, TT_AF_SEC_RTC_NODES, 4, (uint64_t)c->nodes * c->words, &node);
    if (st == TT_OK)
        st = tt_af_get_n(ctx, f, TT_AF_SEC_RTC_BLOCKS, sizeof(tt_tri_block), c->blocks, &block);
    if (st != TT_OK) return st;
    c->node = node;
    c->block = block;
    for (uint32_t n = 0; n < c->nodes && st == TT_OK; n++) st = check_node(ctx, f, c, n);
    uint64_t lanes = 0;
    for (uint32_t b = 0; b < c->blocks && st == TT_OK; b++)
        for (int i = 0; i < TT_TRI_BLOCK_W; i++) {
            lanes += c->block[b].prim[i] != TT_INVALID_ID;
            if (c->block[b].prim[i] >= triangles && c->block[b].prim[i] != TT_INVALID_ID) {
                st = tt_af_bad(ctx, f, "block %u lane %d: triangle %u of %u", b, i,
                               c->block[b].prim[i], triangles);
                break;
            }
        }
    /* more references than triangles: built with split references */
    t->split = lanes > c->triangles;
    return st;
}
