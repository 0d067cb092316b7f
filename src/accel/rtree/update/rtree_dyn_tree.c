/* The pointer tree's in-place operations for a changing scene: deletion with
 * Guttman's condense step, insertion through the insertion builder, and the
 * bottom-up refit of moved boxes (rtree_dyn.h). */
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/update/rtree_dyn.h"

#define NODE_FREE 1u /* rt_node_hdr.pad: the node is on the free list */

tt_status rt_dyn_reserve_ids(rt_dyn *d, size_t ids)
{
    if (ids <= d->id_cap) return TT_OK;
    size_t cap = d->id_cap * 2 > ids ? d->id_cap * 2 : ids;
    tt_context *ctx = d->b.ctx;
    float *box = tt_realloc_array(ctx, d->tri_box, cap, 6 * sizeof(float));
    if (box) d->tri_box = box;
    uint32_t *leaf = box ? tt_realloc_array(ctx, d->leaf_of, cap, sizeof(uint32_t)) : NULL;
    if (leaf) d->leaf_of = leaf;
    uint32_t *lane = leaf ? tt_realloc_array(ctx, d->lane_of, cap, sizeof(uint32_t)) : NULL;
    if (lane) d->lane_of = lane;
    if (!lane) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
    for (size_t i = d->id_cap; i < cap; i++) leaf[i] = lane[i] = TT_INVALID_ID;
    d->id_cap = cap;
    d->b.tri_box = d->tri_box;
    d->b.leaf_of = d->leaf_of;
    return TT_OK;
}

/* Per-node arrays follow the pool (which only the builder grows). */
tt_status rt_dyn_node_arrays(rt_dyn *d)
{
    const uint32_t need = d->b.node_cap;
    if (need <= d->rec_cap) return TT_OK;
    tt_context *ctx = d->b.ctx;
    uint32_t *rec = tt_realloc_array(ctx, d->rec_of, need, sizeof *rec);
    if (rec) d->rec_of = rec;
    uint8_t *dirty = rec ? tt_realloc_array(ctx, d->dirty, need, 1) : NULL;
    if (dirty) d->dirty = dirty;
    uint32_t *fr = dirty ? tt_realloc_array(ctx, d->free_node, need, sizeof *fr) : NULL;
    if (fr) {
        d->free_node = fr;
        d->b.free_node = fr;
    }
    uint32_t *grp = fr ? tt_realloc_array(ctx, d->grp_of, need, sizeof *grp) : NULL;
    if (grp) d->grp_of = grp;
    uint8_t *hi = grp ? tt_realloc_array(ctx, d->grp_hi, need, 1) : NULL;
    if (!hi) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
    d->grp_hi = hi;
    for (uint32_t i = d->rec_cap; i < need; i++) {
        rec[i] = grp[i] = TT_INVALID_ID;
        dirty[i] = hi[i] = 0;
    }
    d->rec_cap = need;
    return TT_OK;
}

static tt_status mark(rt_dyn *d, uint32_t n)
{
    tt_status st = rt_dyn_node_arrays(d);
    if (st != TT_OK) return st;
    if (d->dirty[n]) return TT_OK;
    if (d->dirty_count == d->dirty_cap) {
        uint32_t cap = d->dirty_cap ? 2 * d->dirty_cap : 256;
        uint32_t *l = tt_realloc_array(d->b.ctx, d->dirty_list, cap, sizeof *l);
        if (!l) return tt_error(d->b.ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
        d->dirty_list = l;
        d->dirty_cap = cap;
    }
    d->dirty[n] = 1;
    d->dirty_list[d->dirty_count++] = n;
    return TT_OK;
}

void rt_dyn_free_node(rt_dyn *d, uint32_t n)
{
    rt_dyn_release(d, n);
    d->b.hdr[n].pad = NODE_FREE;
    d->b.hdr[n].count = 0;
    d->b.hdr[n].parent = TT_INVALID_ID;
    d->b.free_node[d->b.free_count++] = n; /* node_arrays sized it to the pool */
}

/* Takes entry i out of node n (the last entry fills its place). */
static void remove_entry(rt_builder *b, uint32_t n, int i)
{
    const int last = --b->hdr[n].count;
    rt_builder_touch(b, n);
    if (i == last) return;
    float e[6];
    float *s = rt_node_box(b, n);
    rt_soa_get(s, b->cap, last, e);
    rt_soa_put(s, b->cap, i, e);
    uint32_t *ch = rt_node_child(b, n);
    ch[i] = ch[last];
    if (b->hdr[n].level > 0) b->hdr[ch[i]].slot = (uint8_t)i;
}

static tt_status add_orphan(rt_dyn *d, const float e[6], uint32_t c, int level)
{
    if (d->orphan_count == d->orphan_cap) {
        size_t cap = d->orphan_cap ? 2 * d->orphan_cap : 64;
        tt_context *ctx = d->b.ctx;
        float *bx = tt_realloc_array(ctx, d->orphan_box, cap, 6 * sizeof(float));
        if (bx) d->orphan_box = bx;
        uint32_t *ch = bx ? tt_realloc_array(ctx, d->orphan_child, cap, sizeof *ch) : NULL;
        if (ch) d->orphan_child = ch;
        uint8_t *lv = ch ? tt_realloc_array(ctx, d->orphan_level, cap, 1) : NULL;
        if (!lv) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
        d->orphan_level = lv;
        d->orphan_cap = cap;
    }
    memcpy(d->orphan_box + 6 * d->orphan_count, e, 6 * sizeof(float));
    d->orphan_child[d->orphan_count] = c;
    d->orphan_level[d->orphan_count++] = (uint8_t)level;
    return TT_OK;
}

/* The triangles under node n, as level-0 orphans; n's subtree freed. */
static tt_status orphan_triangles(rt_dyn *d, uint32_t n)
{
    rt_builder *b = &d->b;
    const uint32_t *ch = rt_node_child(b, n);
    tt_status st = TT_OK;
    for (int i = 0; i < b->hdr[n].count && st == TT_OK; i++) {
        if (b->hdr[n].level == 0) {
            d->leaf_of[ch[i]] = TT_INVALID_ID;
            st = add_orphan(d, d->tri_box + 6 * (size_t)ch[i], ch[i], 0);
        } else {
            st = orphan_triangles(d, ch[i]);
        }
    }
    rt_dyn_free_node(d, n);
    return st;
}

tt_status rt_dyn_delete(rt_dyn *d, uint32_t id)
{
    rt_builder *b = &d->b;
    tt_status st = rt_dyn_node_arrays(d);
    if (st != TT_OK) return st;
    uint32_t n = d->leaf_of[id];
    const uint32_t *ch = rt_node_child(b, n);
    int i = 0;
    while (i < b->hdr[n].count && ch[i] != id) i++;
    if (i == b->hdr[n].count)
        return tt_error(b->ctx, TT_ERR_INTERNAL, "rtree update: triangle %u is not in its leaf",
                        id);
    remove_entry(b, n, i);
    d->leaf_of[id] = TT_INVALID_ID;
    b->triangles--;
    d->orphan_count = 0;
    /* condense: an underfull node leaves the tree, its entries become
     * orphans for their own level; the others' boxes shrink to fit. A
     * leaf is underfull only when empty (lazy deletion at the leaves; the
     * updated tree's compact layout is checked with fill minimum 1): with
     * the SAH loader's leaves of ~2 triangles nearly every deletion
     * emptied a leaf below m = 2 and reinserted its other triangle. On
     * the bunny's 1%-edits frames 8.44 M -> 6.90 M instructions, and the
     * SAH cost after 30 / 100 frames 48.5 / 68.1 -> 43.9 / 66.0 (the
     * orphans' reinsertion grew other leaves). Interior nodes keep m. */
    while (n != b->root && st == TT_OK) {
        const uint32_t p = b->hdr[n].parent;
        if (b->hdr[n].count < (b->hdr[n].level == 0 ? 1 : b->m)) {
            const int level = b->hdr[n].level;
            const uint32_t *nc = rt_node_child(b, n);
            const float *ns = rt_node_box(b, n);
            for (int k = 0; k < b->hdr[n].count && st == TT_OK; k++) {
                float e[6];
                rt_soa_get(ns, b->cap, k, e);
                if (level == 0) d->leaf_of[nc[k]] = TT_INVALID_ID;
                st = add_orphan(d, e, nc[k], level);
            }
            remove_entry(b, p, b->hdr[n].slot);
            rt_dyn_free_node(d, n);
        } else {
            /* n keeps its place; its box shrinks in p. When it does not
             * change, nothing above does (counts change only through an
             * underflow below): the climb stops */
            float nb[6], old[6];
            rt_node_bounds(b, n, nb);
            float *ps = rt_node_box(b, p);
            rt_soa_get(ps, b->cap, b->hdr[n].slot, old);
            if (rt_box_equal(old, nb)) break;
            rt_soa_put(ps, b->cap, b->hdr[n].slot, nb);
            rt_builder_touch(b, p);
        }
        n = p;
    }
    if (st != TT_OK) return st;
    /* a root left without entries above the leaves cannot take orphans of
     * its subtrees' levels: the tree starts over from a leaf and the
     * orphans' triangles go in one by one */
    if (b->hdr[b->root].level > 0 && b->hdr[b->root].count == 0) {
        const size_t k0 = d->orphan_count;
        for (size_t k = 0; k < k0 && st == TT_OK; k++)
            if (d->orphan_level[k] > 0) st = orphan_triangles(d, d->orphan_child[k]);
        size_t w = 0; /* keep the level-0 orphans only */
        for (size_t k = 0; k < d->orphan_count; k++) {
            if (d->orphan_level[k] != 0) continue;
            memmove(d->orphan_box + 6 * w, d->orphan_box + 6 * k, 6 * sizeof(float));
            d->orphan_child[w] = d->orphan_child[k];
            d->orphan_level[w++] = 0;
        }
        d->orphan_count = w;
        rt_dyn_free_node(d, b->root);
        uint32_t r;
        if (st == TT_OK) st = rt_builder_new_node(b, 0, &r);
        if (st != TT_OK) return st;
        b->root = r;
    }
    /* orphans back in at their level (subtrees whole), deepest last */
    for (size_t k = 0; k < d->orphan_count && st == TT_OK; k++)
        st = rt_builder_insert_entry(b, d->orphan_box + 6 * k, d->orphan_child[k],
                                     d->orphan_level[k]);
    if (st != TT_OK) return st;
    /* a root with one child above the leaves: the child is the root */
    while (b->hdr[b->root].level > 0 && b->hdr[b->root].count == 1) {
        const uint32_t old = b->root;
        b->root = rt_node_child(b, old)[0];
        b->hdr[b->root].parent = TT_INVALID_ID;
        b->hdr[b->root].slot = 0;
        rt_dyn_free_node(d, old);
    }
    return rt_dyn_node_arrays(d);
}

tt_status rt_dyn_insert(rt_dyn *d, uint32_t id)
{
    tt_status st = rt_builder_insert_entry(&d->b, d->tri_box + 6 * (size_t)id, id, 0);
    if (st == TT_OK) d->b.triangles++;
    if (st == TT_OK) st = rt_dyn_node_arrays(d);
    return st;
}

tt_status rt_dyn_set_box(rt_dyn *d, uint32_t id)
{
    rt_builder *b = &d->b;
    const uint32_t n = d->leaf_of[id];
    const uint32_t *ch = rt_node_child(b, n);
    for (int i = 0; i < b->hdr[n].count; i++)
        if (ch[i] == id) {
            rt_soa_put(rt_node_box(b, n), b->cap, i, d->tri_box + 6 * (size_t)id);
            return mark(d, n);
        }
    return tt_error(b->ctx, TT_ERR_INTERNAL, "rtree update: triangle %u is not in its leaf", id);
}

tt_status rt_dyn_refit(rt_dyn *d)
{
    rt_builder *b = &d->b;
    /* level by level from the leaves: a node's box is written into its
     * parent once all of its children are final */
    const int top = b->hdr[b->root].level;
    for (int l = 0; l < top; l++) {
        for (uint32_t k = 0; k < d->dirty_count; k++) {
            const uint32_t n = d->dirty_list[k];
            if (b->hdr[n].level != l || b->hdr[n].pad == NODE_FREE) continue;
            const uint32_t p = b->hdr[n].parent;
            if (p == TT_INVALID_ID) continue;
            float nb[6], old[6];
            rt_node_bounds(b, n, nb);
            float *ps = rt_node_box(b, p);
            rt_soa_get(ps, b->cap, b->hdr[n].slot, old);
            if (rt_box_equal(old, nb)) continue;
            rt_soa_put(ps, b->cap, b->hdr[n].slot, nb);
            tt_status st = mark(d, p);
            if (st != TT_OK) return st;
        }
    }
    return TT_OK;
}

/* Node n's entries from its children (leaves: from the ids' boxes). */
static void refit_node(rt_dyn *d, uint32_t n)
{
    rt_builder *b = &d->b;
    const uint32_t *ch = rt_node_child(b, n);
    float *s = rt_node_box(b, n);
    if (b->hdr[n].level == 0) {
        for (int i = 0; i < b->hdr[n].count; i++)
            rt_soa_put(s, b->cap, i, d->tri_box + 6 * (size_t)ch[i]);
        return;
    }
    for (int i = 0; i < b->hdr[n].count; i++) {
        float cb[6];
        refit_node(d, ch[i]);
        rt_node_bounds(b, ch[i], cb);
        rt_soa_put(s, b->cap, i, cb);
    }
}

void rt_dyn_refit_all(rt_dyn *d) { rt_dyn_refit_all_par(d, 1); }

void rt_dyn_refit_all_par(rt_dyn *d, int threads)
{
    rt_builder *b = &d->b;
    const uint32_t root = b->root;
    if (b->hdr[root].level < 2 || threads < 2) {
        refit_node(d, root);
        return;
    }
    /* the root's subtrees are disjoint: one per thread at a time */
    const uint32_t *ch = rt_node_child(b, root);
    const int cnt = b->hdr[root].count;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int i = 0; i < cnt; i++) refit_node(d, ch[i]);
    float *s = rt_node_box(b, root);
    for (int i = 0; i < cnt; i++) {
        float cb[6];
        rt_node_bounds(b, ch[i], cb);
        rt_soa_put(s, b->cap, i, cb);
    }
}
