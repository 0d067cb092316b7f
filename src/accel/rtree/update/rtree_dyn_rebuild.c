/* Local rebuilds of the pointer tree under edits (rtree_dyn.h).
 *
 * Insertion puts an added triangle into a level-1 node that exists: no
 * insertion makes a level-1 node for a new cluster, so the bench's added
 * triangles (copies shifted off the surface) grow the level-1 boxes they
 * join. After 100 frames of 1% edits on the bunny the level-1 boxes' areas
 * summed to 1.67x a fresh build's while the leaves' cost was that of a
 * fresh build. A level-2 node's subtree rebuilt by the SAH loader regroups
 * its triangles into leaves and level-1 nodes as a fresh build would; the
 * nodes above keep their places, so the rest of the layout stays. */
#include <string.h>

#include "accel/rtree/build/rtree_bulk.h"
#include "accel/rtree/rtree_box.h"
#include "accel/rtree/update/rtree_dyn.h"

static float half_area(const float b[6])
{
    const float x = b[3] - b[0], y = b[4] - b[1], z = b[5] - b[2];
    return x * y + y * z + z * x;
}

/* How far level-2 node p's children spread: the sum of their half areas
 * over p's own (a ray that enters p tests each child it enters). */
static float spread(const rt_builder *b, uint32_t p)
{
    const float *s = rt_node_box(b, p);
    const int cap = b->cap, cnt = b->hdr[p].count;
    float sum = 0.0f, nb[6];
    rt_box_empty(nb);
    for (int i = 0; i < cnt; i++) {
        float e[6];
        rt_soa_get(s, cap, i, e);
        sum += half_area(e);
        rt_box_grow(nb, e);
    }
    const float a = half_area(nb);
    return a > 0.0f ? sum / a : 0.0f;
}

/* Level-2 node p's subtree rebuilt by the SAH loader with height 2 (its
 * level-1 nodes become p's entries); left as it is where the loader would
 * not give 2 .. M level-1 nodes. The triangles and so p's box stay. */
static tt_status rebuild(rt_dyn *d, uint32_t p, int *done)
{
    rt_builder *b = &d->b;
    tt_context *ctx = b->ctx;
    uint32_t T = 0;
    const uint32_t *pc = rt_node_child(b, p);
    for (int i = 0; i < b->hdr[p].count; i++) {
        const uint32_t *cc = rt_node_child(b, pc[i]);
        for (int j = 0; j < b->hdr[pc[i]].count; j++) T += b->hdr[cc[j]].count;
    }
    const uint64_t MM = (uint64_t)b->M * (uint64_t)b->M;
    *done = 0;
    if (T <= MM || T > MM * (uint64_t)b->M) return TT_OK; /* the loader's height is not 2 */
    uint32_t *ids = tt_alloc_array(ctx, T, sizeof *ids);
    float *box = tt_alloc_array(ctx, T, 6 * sizeof *box);
    if (!ids || !box) {
        tt_free(ctx, ids);
        tt_free(ctx, box);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory (rebuild)");
    }
    T = 0;
    for (int i = 0; i < b->hdr[p].count; i++) {
        const uint32_t *cc = rt_node_child(b, pc[i]);
        for (int j = 0; j < b->hdr[pc[i]].count; j++) {
            const uint32_t *tc = rt_node_child(b, cc[j]);
            for (int k = 0; k < b->hdr[cc[j]].count; k++) {
                ids[T] = tc[k];
                memcpy(box + 6 * (size_t)T, d->tri_box + 6 * (size_t)tc[k], 6 * sizeof *box);
                T++;
            }
        }
    }
    tt_rtree_options o = d->opt; /* the loader's node sizes: the tree's */
    o.m = b->m;
    o.M = b->M;
    rt_bulk_levels lv;
    tt_status st = rt_bulk_sah_levels(&lv, ctx, &o, box, T);
    if (st == TT_OK && lv.height == 2 && lv.count[1] >= 2 && lv.count[1] <= (uint32_t)b->M) {
        /* the old level-1 nodes and leaves out (leaves first, as the
         * condense step frees a subtree), then the loader's in p */
        for (int i = 0; i < b->hdr[p].count; i++) {
            const uint32_t c = pc[i];
            const uint32_t *cc = rt_node_child(b, c);
            for (int j = 0; j < b->hdr[c].count; j++) rt_dyn_free_node(d, cc[j]);
            rt_dyn_free_node(d, c);
        }
        b->hdr[p].count = 0;
        rt_builder_touch(b, p);
        for (uint32_t j = 0; j < lv.count[1] && st == TT_OK; j++) {
            uint32_t n1;
            st = rt_builder_new_node(b, 1, &n1);
            for (uint32_t k = lv.first[1][j]; k < lv.first[1][j + 1] && st == TT_OK; k++) {
                uint32_t leaf;
                st = rt_builder_new_node(b, 0, &leaf);
                if (st != TT_OK) break;
                for (uint32_t q = lv.first[0][k]; q < lv.first[0][k + 1]; q++) {
                    const uint32_t id = ids[lv.order[q]];
                    rt_builder_put(b, leaf, d->tri_box + 6 * (size_t)id, id);
                }
                rt_builder_put(b, n1, lv.box[0] + 6 * (size_t)k, leaf);
            }
            if (st == TT_OK) rt_builder_put(b, p, lv.box[1] + 6 * (size_t)j, n1);
        }
        if (st == TT_OK) st = rt_dyn_node_arrays(d);
        *done = 1;
    }
    rt_bulk_levels_free(ctx, &lv);
    tt_free(ctx, ids);
    tt_free(ctx, box);
    return st;
}

#define REBUILD_TRIES 4 /* the most spread nodes tried, in order */

tt_status rt_dyn_rebuild_worst(rt_dyn *d)
{
    const rt_builder *b = &d->b;
    if (b->hdr[b->root].level < 2) return TT_OK;
    /* the level-2 nodes, by a walk from the root (a few hundred nodes);
     * the most spread ones, most first (one whose subtree the loader
     * would not give height 2 is passed over for the next) */
    uint32_t stack[TT_RT_BUILD_LEVELS * TT_RT_CAP];
    uint32_t top[REBUILD_TRIES];
    float top_s[REBUILD_TRIES];
    int sp = 0, nt = 0;
    stack[sp++] = b->root;
    while (sp) {
        const uint32_t n = stack[--sp];
        if (b->hdr[n].level == 2) {
            const float s = spread(b, n);
            int j = nt < REBUILD_TRIES ? nt++ : REBUILD_TRIES;
            if (j == REBUILD_TRIES && !(s > top_s[REBUILD_TRIES - 1])) continue;
            if (j == REBUILD_TRIES) j--;
            for (; j > 0 && top_s[j - 1] < s; j--) {
                top[j] = top[j - 1];
                top_s[j] = top_s[j - 1];
            }
            top[j] = n;
            top_s[j] = s;
            continue;
        }
        const uint32_t *ch = rt_node_child(b, n);
        for (int i = 0; i < b->hdr[n].count; i++) stack[sp++] = ch[i];
    }
    int done = 0;
    tt_status st = TT_OK;
    for (int k = 0; k < nt && !done && st == TT_OK; k++) st = rebuild(d, top[k], &done);
    return st;
}
