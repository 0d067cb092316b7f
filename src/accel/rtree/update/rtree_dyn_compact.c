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
                rt_builder_put(b, child, d->tri_box + 6 * (size_t)id, id);
                b->triangles++;
            }
        } else {
            st = from_record(d, c, ref[i], &child);
            if (st != TT_OK) break;
        }
        rt_builder_put(b, n, zero, child);
    }
    *out = n;
    return st;
}

tt_status rt_dyn_from_compact(rt_dyn *d, tt_context *ctx, const tt_rtree_options *o,
                              const rtc_tree *t, const tt_scene *scene)
{
    memset(d, 0, sizeof *d);
    d->opt = *o;
    const tt_rtc *c = &t->c;
    /* Insertions follow the tree's strategy when it was built by insertion;
     * a bulk-loaded tree (no strategy of its own) takes the least surface
     * enlargement (TT_RTREE_MIN_SURFACE, the builder's SIMD path): on the
     * bunny's 1%-edits frames it costs 9.2 M instructions a frame against
     * 15.4 M for the RR*-tree's choice (whose overlap sums were half of
     * the frame), and after 100 frames its SAH cost is lower (68.1 against
     * 76.1; fresh build 19.8); after 10 frames 29.9 against 28.6. */
    tt_rtree_options oo = *o;
    if (o->build != TT_RTREE_BUILD_INSERT) oo.strategy = TT_RTREE_MIN_SURFACE;
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
    b->touch = rt_dyn_touch;
    b->touch_user = d;
    /* insertions by the SAH (rt_builder.sah_leaves). The bench's 1% edits
     * (bunny, 100 frames) left the tree at 3.33x a fresh build's SAH cost
     * with the least-surface choice: every added triangle joined a leaf,
     * growing it (leaf cost 9.2 -> 51). The SAH choice with new leaves
     * alone: 1.29x, but twice the leaves, splits, height 4 -> 6 and trace
     * 2.2x fresh; the split penalty keeps the level-1 nodes: SAH 1.24x,
     * trace 1.34x fresh (was 1.82x). Eight level-1 nodes searched give the
     * same tree as an unbounded search. */
    b->sah_leaves = 1;
    b->sah_split_cost = 1.0f;
    b->sah_max_evals = 8;
    /* at most six candidates off the search's heap: the eight level-1
     * evaluations bounded only those, and on the conference the interior
     * nodes the search opened on the way were most of its cost. bench D's
     * edits, 1% a frame (callgrind, frames 2-16 / 2-31): conference 46.6M
     * -> 38.6M instructions a frame, bunny 6.98M -> 7.03M; thread CPU,
     * 31 frames, 10 interleaved runs on the shared box: conference 17.2 /
     * 18.8 -> 14.9 / 16.6 ms (min / median), bunny 1.78 / 1.89 -> 1.73 /
     * 2.04 ms. After 100 frames: SAH cost against a fresh build bunny
     * 1.064x -> 1.067x, conference 0.91x -> 1.47x; traced (primary and
     * shadow, 1 thread, against a fresh build of the frame) bunny 1.22-1.23x
     * -> 1.24-1.31x, conference 1.52-1.61x -> 1.19-1.48x (the view's rays
     * follow the SAH cost little there). Four: conference 14.7 ms median,
     * but bunny 2.31 ms and SAH 1.11x */
    b->sah_max_pops = 6;
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
    tt_free(ctx, d->grp_of);
    tt_free(ctx, d->grp_hi);
    tt_free(ctx, d->free_grp);
    for (int k = 0; k < RT_DYN_REGION_CLASSES; k++) tt_free(ctx, d->free_reg[k]);
    tt_free(ctx, d->pend_grp);
    tt_free(ctx, d->pend_reg);
    tt_free(ctx, d->pend_slot);
    tt_free(ctx, d->touched);
    tt_free(ctx, d->touch_list);
    tt_free(ctx, d->ids);
    tt_free(ctx, d->lev_rec);
    memset(d, 0, sizeof *d);
}

size_t rt_dyn_bytes(const rt_dyn *d)
{
    const size_t cap = (size_t)d->b.cap;
    return (size_t)d->b.node_cap * (sizeof(rt_node_hdr) + cap * 7 * sizeof(float)) +
           d->id_cap * (6 * sizeof(float) + 2 * sizeof(uint32_t)) +
           (size_t)d->rec_cap * (3 * sizeof(uint32_t) + 2) + d->dirty_cap * sizeof(uint32_t) +
           (d->ids_cap + d->lev_cap) * sizeof(uint32_t) +
           /* the slack layout's room to grow, past what rtc_bytes counts */
           (d->slack ? (size_t)(d->lay_rec_cap - d->lay_rec_used) * d->lay_words * sizeof(float) +
                           (size_t)(d->lay_blk_cap - d->lay_blk_used) * sizeof(tt_tri_block)
                     : 0);
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

/* ------------------------------------------------- the slack layout */

#define REG_CLASS_SHIFT 26

static tt_status push(tt_context *ctx, uint32_t **a, uint32_t *count, uint32_t *cap, uint32_t v)
{
    if (*count == *cap) {
        const uint32_t nc = *cap ? 2 * *cap : 64;
        uint32_t *na = tt_realloc_array(ctx, *a, nc, sizeof *na);
        if (!na) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
        *a = na;
        *cap = nc;
    }
    (*a)[(*count)++] = v;
    return TT_OK;
}

void rt_dyn_touch(void *user, uint32_t n)
{
    rt_dyn *d = user;
    if (n >= d->touched_cap) {
        uint32_t cap = d->b.node_cap > n ? d->b.node_cap : n + 1;
        uint8_t *t = tt_realloc_array(d->b.ctx, d->touched, cap, 1);
        if (!t) {
            d->touch_oom = 1;
            return;
        }
        memset(t + d->touched_cap, 0, cap - d->touched_cap);
        d->touched = t;
        d->touched_cap = cap;
    }
    if (d->touched[n]) return;
    if (push(d->b.ctx, &d->touch_list, &d->touch_count, &d->touch_list_cap, n) != TT_OK) {
        d->touch_oom = 1;
        return;
    }
    d->touched[n] = 1;
}

void rt_dyn_release(rt_dyn *d, uint32_t n)
{
    if (n >= d->rec_cap) return; /* made in this update: nothing of it is laid out */
    const rt_builder *b = &d->b;
    /* a leaf's slot: its lanes cleared at the next sync */
    if (d->grp_of[n] != TT_INVALID_ID && d->slack && b->hdr[n].level == 0) {
        if (push(b->ctx, &d->pend_slot, &d->pend_slot_count, &d->pend_slot_cap,
                 d->grp_of[n] | (uint32_t)(d->grp_hi[n] - 1) << RT_DYN_SLOT_LANE_BITS) != TT_OK)
            d->touch_oom = 1; /* lost: the next sync compacts */
    } else if (d->grp_of[n] != TT_INVALID_ID && d->slack) {
        tt_status st = b->hdr[n].level >= 2
                           ? push(b->ctx, &d->pend_grp, &d->pend_grp_count, &d->pend_grp_cap,
                                  d->grp_of[n])
                           : push(b->ctx, &d->pend_reg, &d->pend_reg_count, &d->pend_reg_cap,
                                  d->grp_of[n] | (uint32_t)(d->grp_hi[n] & ~RT_DYN_REGION_FRESH)
                                                     << REG_CLASS_SHIFT);
        if (st != TT_OK) d->touch_oom = 1; /* lost: the next sync compacts */
    }
    d->grp_of[n] = d->rec_of[n] = TT_INVALID_ID;
    d->grp_hi[n] = 0;
    /* n's children, still listed, lose their places in the group (cleared
     * at the sync and perhaps handed to a node that takes them at the same
     * slots): so they are written again wherever they land */
    if (b->hdr[n].level < 2) return;
    const uint32_t *ch = rt_node_child(b, n);
    for (int i = 0; i < b->hdr[n].count; i++)
        if (ch[i] < d->rec_cap) d->rec_of[ch[i]] = TT_INVALID_ID;
}

/* Record r as the free mark every traversal skips and the check accepts
 * (tt_rtc_is_free): +inf boxes, no references, no parent, no entries. */
static void record_clear(const tt_rtc *c, uint32_t r)
{
    float *rec = (float *)tt_rtc_node(c, r);
    for (uint32_t i = 0; i < 6 * c->S; i++) rec[i] = TT_INF;
    uint32_t *w = (uint32_t *)(rec + 6 * c->S);
    for (uint32_t i = 0; i < c->S + 1; i++) w[i] = TT_INVALID_ID;
    for (uint32_t i = c->S + 1; i < c->words - 6 * c->S; i++) w[i] = 0;
}

static void lanes_clear(const tt_rtc *c, uint64_t first, uint64_t count)
{
    for (uint64_t g = first; g < first + count; g++) {
        tt_tri_block *bk = (tt_tri_block *)c->block + g / TT_TRI_BLOCK_W;
        const uint32_t l = (uint32_t)(g % TT_TRI_BLOCK_W);
        for (int q = 0; q < 9; q++) bk->v[q][l] = NAN;
        bk->prim[l] = TT_INVALID_ID;
    }
}

/* The arrays grown (by half, copied) to hold `records` and `blocks`. */
static tt_status lay_reserve(rt_dyn *d, rtc_tree *t, uint64_t records, uint64_t blocks)
{
    tt_context *ctx = d->b.ctx;
    tt_rtc *c = &t->c;
    if (records >= TT_RTC_LEAF_BIT || blocks >= (uint64_t)1 << TT_RTC_LEAF_BLOCK_BITS)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "rtree update: %llu records and %llu blocks are beyond 32-bit references",
                        (unsigned long long)records, (unsigned long long)blocks);
    if (records > d->lay_rec_cap) {
        const uint64_t cap = records + records / 2 + 16;
        const size_t rb = (size_t)c->words * sizeof(float);
        void *raw = tt_alloc(ctx, (size_t)cap * rb + 63);
        if (!raw) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
        float *node = (float *)(((uintptr_t)raw + 63) & ~(uintptr_t)63);
        if (c->node) memcpy(node, c->node, (size_t)c->nodes * rb);
        tt_free(ctx, t->node_mem);
        t->node_mem = raw;
        c->node = node;
        d->lay_rec_cap = (uint32_t)cap;
    }
    if (blocks > d->lay_blk_cap) {
        const uint64_t cap = blocks + blocks / 2 + 16;
        void *raw = tt_alloc(ctx, (size_t)cap * sizeof(tt_tri_block) + 63);
        if (!raw) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
        tt_tri_block *bk = (tt_tri_block *)(((uintptr_t)raw + 63) & ~(uintptr_t)63);
        if (c->block) memcpy(bk, c->block, (size_t)c->blocks * sizeof(tt_tri_block));
        tt_free(ctx, t->block_mem);
        t->block_mem = raw;
        c->block = bk;
        d->lay_blk_cap = (uint32_t)cap;
    }
    return TT_OK;
}

/* A group of M free records, from the free list or the array's end. */
static tt_status alloc_group(rt_dyn *d, rtc_tree *t, uint32_t *out)
{
    tt_rtc *c = &t->c;
    if (d->free_grp_count) {
        *out = d->free_grp[--d->free_grp_count];
        return TT_OK;
    }
    tt_status st = lay_reserve(d, t, (uint64_t)c->nodes + c->M, c->blocks);
    if (st != TT_OK) return st;
    *out = c->nodes;
    for (uint32_t i = 0; i < c->M; i++) record_clear(c, c->nodes + i);
    c->nodes += c->M;
    return TT_OK;
}

/* A region of 2^k unused blocks, from its class's free list or the end. */
static tt_status alloc_region(rt_dyn *d, rtc_tree *t, uint32_t k, uint32_t *out)
{
    tt_rtc *c = &t->c;
    if (d->free_reg_count[k]) {
        *out = d->free_reg[k][--d->free_reg_count[k]];
        d->free_reg_blocks -= 1u << k;
        return TT_OK;
    }
    tt_status st = lay_reserve(d, t, c->nodes, (uint64_t)c->blocks + (1u << k));
    if (st != TT_OK) return st;
    *out = c->blocks;
    lanes_clear(c, (uint64_t)c->blocks * TT_TRI_BLOCK_W, (uint64_t)TT_TRI_BLOCK_W << k);
    c->blocks += 1u << k;
    return TT_OK;
}

/* Region `v` (block | class << REG_CLASS_SHIFT) cleared and free. */
static tt_status free_region(rt_dyn *d, const tt_rtc *c, uint32_t v)
{
    const uint32_t k = v >> REG_CLASS_SHIFT, blk = v & ((1u << REG_CLASS_SHIFT) - 1);
    lanes_clear(c, (uint64_t)blk * TT_TRI_BLOCK_W, (uint64_t)TT_TRI_BLOCK_W << k);
    d->free_reg_blocks += 1u << k;
    return push(d->b.ctx, &d->free_reg[k], &d->free_reg_count[k], &d->free_reg_cap[k], blk);
}

static uint32_t class_of(uint32_t blocks)
{
    uint32_t k = 0;
    while ((1u << k) < blocks) k++;
    return k;
}

/* Level-1 node n's region fits its leaves' slots: exchanged for one of
 * the right class when too small or four times too big (the old one freed
 * now: its leaves are all placed and written again, RT_DYN_REGION_FRESH). */
static tt_status fit_region(rt_dyn *d, rtc_tree *t, uint32_t n)
{
    const uint32_t k = class_of(rt_dyn_region_need(d, &t->c, n));
    if (d->grp_of[n] != TT_INVALID_ID) {
        const uint32_t have = d->grp_hi[n] & ~RT_DYN_REGION_FRESH;
        if (k <= have && (have == 0 || k + 2 > have)) return TT_OK;
        tt_status st = free_region(d, &t->c, d->grp_of[n] | have << REG_CLASS_SHIFT);
        d->grp_of[n] = TT_INVALID_ID;
        if (st != TT_OK) return st;
    }
    d->grp_hi[n] = (uint8_t)(k | RT_DYN_REGION_FRESH);
    return alloc_region(d, t, k, &d->grp_of[n]);
}

/* Where interior node n's record is now: its slot in its parent's group. */
static uint32_t lay_pos(const rt_dyn *d, uint32_t n)
{
    const rt_builder *b = &d->b;
    return n == b->root ? 0 : d->grp_of[b->hdr[n].parent] + b->hdr[n].slot;
}

/* rtc_set_boxes's result (the entries' rows, the free mark past cnt) in
 * straight row copies the compiler vectorises: the general loop, a branch
 * per slot, was a seventh of an edits frame's sync. The free mark only on
 * slots [cnt, old): every record, used or free, already holds it past its
 * count field (old), as this writer and record_clear leave it. */
static void set_boxes(const tt_rtc *c, float *rec, const float *box, uint32_t stride,
                      uint32_t cnt, uint32_t old)
{
    const uint32_t S = c->S;
    for (uint32_t k = 0; k < 6; k++) {
        float *row = rec + k * S;
        memcpy(row, box + k * stride, cnt * sizeof(float));
        for (uint32_t i = cnt; i < old; i++) row[i] = TT_INF;
    }
}

/* Interior node n's record at its place: header, boxes, references; a
 * level-1 node's region written whole; children records elsewhere than
 * their slot in n's group are touched (written later in the same sync). */
static tt_status write_node(rt_dyn *d, const tt_rtc *c, const tt_scene *scene, uint32_t n)
{
    const rt_builder *b = &d->b;
    const uint32_t r = lay_pos(d, n), cnt = b->hdr[n].count, level = b->hdr[n].level;
    const int moved = d->rec_of[n] != r;
    d->rec_of[n] = r;
    float *rec = (float *)tt_rtc_node(c, r);
    uint32_t *ref = (uint32_t *)(rec + 6 * c->S);
    /* the count the record at r holds now (a free record's is 0) */
    const uint32_t was = ref[c->S + 1] & 0xffu, old = was < c->S ? was : c->S;
    set_boxes(c, rec, rt_node_box(b, n), (uint32_t)b->cap, cnt, old);
    ref[c->S] = n == b->root ? TT_INVALID_ID : lay_pos(d, b->hdr[n].parent);
    ref[c->S + 1] = cnt | level << 8;
    d->last_records++;
    if (level >= 2) {
        const uint32_t g = d->grp_of[n], *ch = rt_node_child(b, n);
        for (uint32_t i = 0; i < cnt; i++) {
            ref[i] = g + i;
            if (d->rec_of[ch[i]] != g + i) rt_dyn_touch(d, ch[i]);
            else if (moved) /* the child stays, its parent link follows n */
                ((uint32_t *)tt_rtc_child(c, tt_rtc_node(c, g + i)))[c->S] = r;
        }
        for (uint32_t i = cnt; i < d->grp_hi[n]; i++) record_clear(c, g + i);
        d->grp_hi[n] = (uint8_t)cnt;
    } else {
        tt_status st = rt_dyn_region_write(d, c, scene, n, ref);
        if (st != TT_OK) return st;
    }
    for (uint32_t i = cnt; i < old; i++) ref[i] = TT_INVALID_ID;
    return TT_OK;
}

/* A compaction: fresh arrays sized to the tree (with a quarter to grow
 * into), every interior node touched in depth-first order, so that the
 * groups and regions are handed out in that order. */
static tt_status lay_start_full(rt_dyn *d, rtc_tree *t)
{
    rt_builder *b = &d->b;
    tt_context *ctx = b->ctx;
    const uint32_t M = (uint32_t)b->M;
    for (uint32_t k = 0; k < d->touch_count; k++) d->touched[d->touch_list[k]] = 0;
    d->touch_count = 0;
    uint64_t groups = 0, blocks = 0;
    uint32_t stack[TT_RT_BUILD_LEVELS * TT_RT_CAP];
    int sp = 0;
    stack[sp++] = b->root;
    while (sp > 0) {
        const uint32_t n = stack[--sp];
        rt_dyn_touch(d, n);
        groups += b->hdr[n].level >= 2;
        if (b->hdr[n].level == 1) {
            blocks += 1u << class_of(rt_dyn_region_need(d, NULL, n));
            continue;
        }
        const uint32_t *ch = rt_node_child(b, n);
        for (int i = b->hdr[n].count - 1; i >= 0; i--) stack[sp++] = ch[i];
    }
    if (d->touch_oom) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
    for (uint32_t n = 0; n < d->rec_cap; n++) {
        d->rec_of[n] = d->grp_of[n] = TT_INVALID_ID;
        d->grp_hi[n] = 0;
    }
    d->free_grp_count = d->pend_grp_count = d->pend_reg_count = d->pend_slot_count = 0;
    for (int k = 0; k < RT_DYN_REGION_CLASSES; k++) d->free_reg_count[k] = 0;
    d->free_reg_blocks = 0;
    rtc_tree fresh;
    memset(&fresh, 0, sizeof fresh);
    fresh.c.M = M;
    fresh.c.S = (M + 3u) & ~3u;
    fresh.c.words = tt_rtc_words(M);
    fresh.c.nodes = 1; /* the root's record */
    d->lay_rec_cap = d->lay_blk_cap = 0;
    const uint64_t recs = 1 + groups * M;
    tt_status st = lay_reserve(d, &fresh, recs + recs / 8, blocks + blocks / 8);
    if (st != TT_OK) {
        rtc_free(ctx, &fresh);
        d->slack = 0;
        return st;
    }
    record_clear(&fresh.c, 0);
    fresh.m = t->m;
    fresh.trace = t->trace;
    fresh.trace_stats = t->trace_stats;
    fresh.packet = t->packet;
    fresh.packet_stats = t->packet_stats;
    rtc_free(ctx, t);
    *t = fresh;
    d->slack = 1;
    d->compactions++;
    return TT_OK;
}

tt_status rt_dyn_sync(rt_dyn *d, tt_context *ctx, rtc_tree *t, const tt_scene *scene)
{
    rt_builder *b = &d->b;
    tt_status st = rt_dyn_node_arrays(d);
    if (st != TT_OK) return st;
    /* the refit's marks are touches too (moved triangles, grown boxes) */
    for (uint32_t j = 0; j < d->dirty_count; j++) rt_dyn_touch(d, d->dirty_list[j]);
    d->last_records = d->last_blocks = 0;
    const uint32_t root = b->root, height = b->hdr[root].level;
    if (height == 0) { /* a lone leaf: the packer's record above it */
        for (uint32_t k = 0; k < d->touch_count; k++) d->touched[d->touch_list[k]] = 0;
        d->touch_count = 0;
        d->slack = 0;
        return rt_dyn_repack(d, ctx, t, scene);
    }
    const tt_rtc *c = &t->c;
    const int fragmented =
        (uint64_t)d->free_grp_count * c->M * RT_DYN_COMPACT_FREE > c->nodes + 4u * c->M ||
        d->free_reg_blocks * RT_DYN_COMPACT_FREE > c->blocks + 64u;
    if (!d->slack || d->touch_oom || fragmented) {
        d->touch_oom = 0;
        st = lay_start_full(d, t);
        if (st != TT_OK) return st;
    } else { /* freed leaves' slots, groups and regions cleared, then free */
        /* a new root (the old one split, or gave way to its only child):
         * its record is record 0, written in place like any other; the
         * old root, if it stays, moves into the new root's group, and its
         * children's parent links follow (write_node). This was a
         * compaction: on the conference's 1% edits one a hundred frames,
         * ~95 ms of ~1.4 s */
        if (root != d->lay_root || height != d->lay_height) rt_dyn_touch(d, root);
        for (uint32_t k = 0; k < d->pend_slot_count; k++) rt_dyn_slot_clear(c, d->pend_slot[k]);
        d->pend_slot_count = 0;
        for (uint32_t k = 0; k < d->pend_grp_count && st == TT_OK; k++) {
            for (uint32_t i = 0; i < c->M; i++) record_clear(c, d->pend_grp[k] + i);
            st = push(ctx, &d->free_grp, &d->free_grp_count, &d->free_grp_cap, d->pend_grp[k]);
        }
        for (uint32_t k = 0; k < d->pend_reg_count && st == TT_OK; k++)
            st = free_region(d, c, d->pend_reg[k]);
        d->pend_grp_count = d->pend_reg_count = 0;
        if (st != TT_OK) return st;
    }
    /* 1. closure (a touched node's box in its parent changed), a group for
     *    every touched node above level 1 without one, a region of the
     *    right size for every touched level-1 node */
    for (uint32_t k = 0; k < d->touch_count && st == TT_OK; k++) {
        const uint32_t n = d->touch_list[k];
        if (n >= d->rec_cap || b->hdr[n].pad) continue; /* freed */
        if (n != root && b->hdr[n].parent != TT_INVALID_ID) rt_dyn_touch(d, b->hdr[n].parent);
        if (b->hdr[n].level >= 2 && d->grp_of[n] == TT_INVALID_ID)
            st = alloc_group(d, t, &d->grp_of[n]);
        else if (b->hdr[n].level == 1)
            st = fit_region(d, t, n);
    }
    /* 2. the touched nodes' records (children that moved join the list) */
    for (uint32_t k = 0; k < d->touch_count && st == TT_OK; k++) {
        const uint32_t n = d->touch_list[k];
        if (n >= d->rec_cap || b->hdr[n].pad || b->hdr[n].level == 0) continue;
        st = write_node(d, &t->c, scene, n);
    }
    for (uint32_t k = 0; k < d->touch_count; k++) d->touched[d->touch_list[k]] = 0;
    d->touch_count = 0;
    if (st == TT_OK && d->touch_oom)
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
    if (st != TT_OK) {
        d->slack = 0; /* the next update starts the layout over */
        return st;
    }
    t->c.height = height;
    t->c.triangles = b->triangles;
    d->lay_root = root;
    d->lay_height = height;
    d->lay_rec_used = t->c.nodes;
    d->lay_blk_used = t->c.blocks;
    d->lay_words = t->c.words;
    return TT_OK;
}
