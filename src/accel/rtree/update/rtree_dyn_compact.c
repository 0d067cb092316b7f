/* The pointer tree of a changing scene and the compact layout, both ways
 * (rtree_dyn.h): rebuilt from the compact layout at the first update,
 * repacked into it after a change of shape, or written into it in place
 * (moved triangles' lanes, refit boxes) when the shape stayed. Writes into
 * the layout go through the two writers at the end, so a change of the
 * node record touches only them. */
#include <math.h>
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/update/rtree_dyn.h"

static void map_all(rt_dyn *d, const tt_rtc *c);

/* Entry (e, c) appended to node n, parent links kept. */
static void put_entry(rt_builder *b, uint32_t n, const float e[6], uint32_t c)
{
    const int i = b->hdr[n].count++;
    rt_soa_put(rt_node_box(b, n), b->cap, i, e);
    rt_node_child(b, n)[i] = c;
    if (b->hdr[n].level > 0) {
        b->hdr[c].parent = n;
        b->hdr[c].slot = (uint8_t)i;
    } else {
        b->leaf_of[c] = n;
    }
}

/* Record r (and its subtree) as pointer-tree nodes; *out the node. Boxes
 * are recomputed afterwards (rt_dyn_refit_all) from the ids' boxes. */
static tt_status from_record(rt_dyn *d, const tt_rtc *c, uint32_t r, uint32_t *out)
{
    rt_builder *b = &d->b;
    const float *rec = tt_rtc_node(c, r);
    const uint32_t *ref = tt_rtc_child(c, rec);
    const uint32_t cnt = tt_rtc_count(c, rec), level = tt_rtc_level(c, rec);
    uint32_t n;
    tt_status st = rt_builder_new_node(b, (int)level, &n);
    const float zero[6] = {0, 0, 0, 0, 0, 0};
    for (uint32_t i = 0; i < cnt && st == TT_OK; i++) {
        uint32_t child;
        if (level == 1) {
            st = rt_builder_new_node(b, 0, &child);
            if (st != TT_OK) break;
            const uint64_t first =
                (uint64_t)tt_rtc_leaf_block(ref[i]) * TT_TRI_BLOCK_W + tt_rtc_leaf_lane(ref[i]);
            for (uint32_t k = 0; k < tt_rtc_leaf_count(ref[i]); k++) {
                const uint64_t g = first + k;
                const uint32_t id = c->block[g / TT_TRI_BLOCK_W].prim[g % TT_TRI_BLOCK_W];
                put_entry(b, child, d->tri_box + 6 * (size_t)id, id);
                b->triangles++;
            }
        } else {
            st = from_record(d, c, ref[i], &child);
            if (st != TT_OK) break;
        }
        put_entry(b, n, zero, child);
    }
    *out = n;
    return st;
}

tt_status rt_dyn_from_compact(rt_dyn *d, tt_context *ctx, const tt_rtree_options *o,
                              const rtc_tree *t, const tt_scene *scene)
{
    memset(d, 0, sizeof *d);
    const tt_rtc *c = &t->c;
    /* Insertions follow the tree's strategy when it was built by insertion;
     * a bulk-loaded tree (no strategy of its own) takes the RR*-tree's
     * choice: on the bunny's 1%-edits frames it kept the SAH cost lower
     * (28.7 against 30.1 for R*-surface after 10 frames) in 0.7x the CPU
     * time). */
    tt_rtree_options oo = *o;
    if (o->build != TT_RTREE_BUILD_INSERT) oo.strategy = TT_RTREE_RRSTAR;
    tt_status st = rt_builder_init(&d->b, ctx, &oo, NULL, (uint32_t)scene->triangle_count);
    if (st != TT_OK) return st;
    d->b.free_count = 0;
    d->b.node_count = 0; /* init's empty root leaf is not wanted */
    st = rt_dyn_reserve_ids(d, scene->triangle_count ? scene->triangle_count : 1);
    if (st != TT_OK) return st;
    /* the boxes the tree was built with: from the layout's own copy of the
     * vertices (the scene may have moved them since), or the scene's for a
     * lane without them (a zero-area triangle is stored as NaN) */
    for (size_t id = 0; id < scene->triangle_count; id++) {
        const float *v = scene->tri + 9 * id;
        float *bx = d->tri_box + 6 * id;
        for (int k = 0; k < 3; k++) {
            bx[k] = rt_min(rt_min(v[k], v[3 + k]), v[6 + k]);
            bx[k + 3] = rt_max(rt_max(v[k], v[3 + k]), v[6 + k]);
        }
    }
    for (uint64_t g = 0; g < (uint64_t)c->blocks * TT_TRI_BLOCK_W; g++) {
        const tt_tri_block *bk = &c->block[g / TT_TRI_BLOCK_W];
        const uint32_t l = (uint32_t)(g % TT_TRI_BLOCK_W), id = bk->prim[l];
        if (id == TT_INVALID_ID || id >= scene->triangle_count || isnan(bk->v[0][l])) continue;
        float *bx = d->tri_box + 6 * (size_t)id;
        for (int k = 0; k < 3; k++) {
            bx[k] = rt_min(rt_min(bk->v[k][l], bk->v[3 + k][l]), bk->v[6 + k][l]);
            bx[k + 3] = rt_max(rt_max(bk->v[k][l], bk->v[3 + k][l]), bk->v[6 + k][l]);
        }
    }
    uint32_t root;
    st = from_record(d, c, 0, &root);
    if (st != TT_OK) return st;
    rt_builder *b = &d->b;
    b->root = root;
    b->hdr[root].parent = TT_INVALID_ID;
    if (b->hdr[root].count == 0) { /* empty: a leaf root, as a fresh builder has */
        b->hdr[root].level = 0;
    } else if (b->hdr[root].count == 1) { /* a leaf root packs as a record above it */
        b->root = rt_node_child(b, root)[0];
        b->hdr[b->root].parent = TT_INVALID_ID;
        /* the record node stays unused in the pool; the free list is sized
         * by the first update's node arrays, so it is simply left out */
    }
    rt_dyn_refit_all(d);
    st = rt_dyn_node_arrays(d);
    if (st != TT_OK) return st;
    map_all(d, c);
    /* the tree now holds the scene's boxes, the layout the old ones */
    d->must_repack = 1;
    return TT_OK;
}

void rt_dyn_free(tt_context *ctx, rt_dyn *d)
{
    d->b.leaf_of = NULL;
    d->b.free_node = NULL;
    rt_builder_free(&d->b);
    tt_free(ctx, d->tri_box);
    tt_free(ctx, d->leaf_of);
    tt_free(ctx, d->lane_of);
    tt_free(ctx, d->rec_of);
    tt_free(ctx, d->dirty);
    tt_free(ctx, d->free_node);
    tt_free(ctx, d->dirty_list);
    tt_free(ctx, d->orphan_box);
    tt_free(ctx, d->orphan_child);
    tt_free(ctx, d->orphan_level);
    memset(d, 0, sizeof *d);
}

size_t rt_dyn_bytes(const rt_dyn *d)
{
    const size_t cap = (size_t)d->b.cap;
    return (size_t)d->b.node_cap * (sizeof(rt_node_hdr) + cap * 7 * sizeof(float)) +
           d->id_cap * (6 * sizeof(float) + 2 * sizeof(uint32_t)) +
           (size_t)d->rec_cap * (2 * sizeof(uint32_t) + 1) + d->dirty_cap * sizeof(uint32_t);
}

/* ---------------------------------------------------- the maps, repack */

static void map_leaf(rt_dyn *d, uint32_t leaf, uint32_t ref)
{
    const rt_builder *b = &d->b;
    const uint64_t first = (uint64_t)tt_rtc_leaf_block(ref) * TT_TRI_BLOCK_W + tt_rtc_leaf_lane(ref);
    const uint32_t *ch = rt_node_child(b, leaf);
    for (int k = 0; k < b->hdr[leaf].count; k++) d->lane_of[ch[k]] = (uint32_t)(first + (uint64_t)k);
    d->rec_of[leaf] = TT_INVALID_ID;
}

/* rtc_pack writes depth first, children in order: the same walk over both
 * trees pairs each node with its record. */
static void map_walk(rt_dyn *d, const tt_rtc *c, uint32_t n, uint32_t r)
{
    const rt_builder *b = &d->b;
    d->rec_of[n] = r;
    const uint32_t *ref = tt_rtc_child(c, tt_rtc_node(c, r));
    const uint32_t *ch = rt_node_child(b, n);
    for (int i = 0; i < b->hdr[n].count; i++) {
        if (b->hdr[n].level == 1) map_leaf(d, ch[i], ref[i]);
        else map_walk(d, c, ch[i], ref[i]);
    }
}

static void map_all(rt_dyn *d, const tt_rtc *c)
{
    const rt_builder *b = &d->b;
    if (b->hdr[b->root].level == 0) {
        if (b->hdr[b->root].count > 0) map_leaf(d, b->root, tt_rtc_child(c, tt_rtc_node(c, 0))[0]);
        return;
    }
    map_walk(d, c, b->root, 0);
}

tt_status rt_dyn_repack(rt_dyn *d, tt_context *ctx, rtc_tree *t, const tt_scene *scene)
{
    rtc_tree fresh;
    memset(&fresh, 0, sizeof fresh);
    tt_status st = rtc_pack(ctx, &d->b, scene->tri, &fresh);
    if (st != TT_OK) {
        rtc_free(ctx, &fresh);
        return st;
    }
    fresh.m = t->m;
    fresh.trace = t->trace;
    fresh.trace_stats = t->trace_stats;
    rtc_free(ctx, t);
    *t = fresh;
    map_all(d, &t->c);
    d->repacks++;
    return TT_OK;
}

/* ---------------------------------------------------- in-place writers */

void rt_dyn_write_lane(rt_dyn *d, rtc_tree *t, const tt_scene *scene, uint32_t id)
{
    const uint32_t g = d->lane_of[id];
    tt_tri_block *bk = (tt_tri_block *)t->c.block + g / TT_TRI_BLOCK_W;
    const uint32_t l = g % TT_TRI_BLOCK_W;
    const float *v = scene->tri + 9 * (size_t)id;
    const int dead = tt_tri_is_degenerate(v, v + 3, v + 6); /* as rtc_pack writes it */
    for (int q = 0; q < 9; q++) bk->v[q][l] = dead ? NAN : v[q];
}

void rt_dyn_write_box(rt_dyn *d, rtc_tree *t, uint32_t n)
{
    const rt_builder *b = &d->b;
    const tt_rtc *c = &t->c;
    if (n == b->root) {
        if (b->hdr[n].level != 0 || b->hdr[n].count == 0) return; /* no box of its own */
        float box[6];
        rt_node_bounds(b, n, box); /* a leaf root: entry 0 of record 0 */
        rtc_set_boxes(c, (float *)tt_rtc_node(c, 0), box, 1, 1);
        return;
    }
    /* the parent's record, all its entries from the parent's boxes (the
     * record's format stays behind rtc_set_boxes) */
    const uint32_t p = b->hdr[n].parent;
    rtc_set_boxes(c, (float *)tt_rtc_node(c, d->rec_of[p]), rt_node_box(b, p), (uint32_t)b->cap,
                  b->hdr[p].count);
}

static void write_boxes(rt_dyn *d, const tt_rtc *c, uint32_t n)
{
    const rt_builder *b = &d->b;
    if (b->hdr[n].level == 0) return;
    rtc_set_boxes(c, (float *)tt_rtc_node(c, d->rec_of[n]), rt_node_box(b, n), (uint32_t)b->cap,
                  b->hdr[n].count);
    const uint32_t *ch = rt_node_child(b, n);
    for (int i = 0; i < b->hdr[n].count; i++) write_boxes(d, c, ch[i]);
}

void rt_dyn_write_all_boxes(rt_dyn *d, rtc_tree *t, int threads)
{
    const rt_builder *b = &d->b;
    const uint32_t root = b->root;
    if (b->hdr[root].level == 0) {
        rt_dyn_write_box(d, t, root);
        return;
    }
    const tt_rtc *c = &t->c;
    rtc_set_boxes(c, (float *)tt_rtc_node(c, d->rec_of[root]), rt_node_box(b, root),
                  (uint32_t)b->cap, b->hdr[root].count);
    const uint32_t *ch = rt_node_child(b, root);
    const int cnt = b->hdr[root].count;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int i = 0; i < cnt; i++) write_boxes(d, c, ch[i]);
}
