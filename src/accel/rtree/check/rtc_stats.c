/* Statistics of the compact layout, read back from the arrays: node and
 * leaf counts, fill per level, bytes per triangle and how full the triangle
 * blocks are (the lanes a leaf leaves unused cost memory and SIMD work),
 * and the tree-quality figures of rtree_stats.c, defined the same way
 * (sah_cost, sah_cost_boxes, leaf_fill, interior_fill, levelL_sah), so
 * the builders compare in either layout. */
#include <stdio.h>
#include <string.h>

#include "accel/rtree/rtc.h"
#include "accel/rtree/rtree_box.h"

typedef struct acc {
    double records, leaves, leaf_triangles, level_nodes[256], level_entries[256], level_sah[256];
    double sah, sah_boxes, root_area;
} acc;

/* The area of `box` relative to the root's, as rtree_stats.c weighs it. */
static double rel_area(const acc *a, const float box[6])
{
    return a->root_area > 0.0 ? rt_box_area(box) / a->root_area : 1.0;
}

static void visit(const tt_rtc *c, acc *a, uint32_t n, const float box[6])
{
    const float *rec = tt_rtc_node(c, n);
    const uint32_t cnt = tt_rtc_count(c, rec), l = tt_rtc_level(c, rec);
    const uint32_t *ref = tt_rtc_child(c, rec);
    a->records += 1.0;
    a->level_nodes[l] += 1.0;
    a->level_entries[l] += cnt;
    a->sah += rel_area(a, box);
    a->level_sah[l] += rel_area(a, box);
    a->sah_boxes += rel_area(a, box) * cnt;
    for (uint32_t i = 0; i < cnt; i++) {
        float cb[6];
        rtc_child_box(c, rec, i, cb);
        if (!tt_rtc_is_leaf(ref[i])) {
            visit(c, a, ref[i], cb);
            continue;
        }
        const uint32_t cnt_leaf = tt_rtc_leaf_count(ref[i]);
        a->leaves += 1.0;
        a->level_nodes[0] += 1.0;
        a->leaf_triangles += cnt_leaf;
        a->level_entries[0] += cnt_leaf;
        a->sah += rel_area(a, cb) * cnt_leaf;
        a->level_sah[0] += rel_area(a, cb) * cnt_leaf;
        a->sah_boxes += rel_area(a, cb) * cnt_leaf;
    }
}

void rtc_statistics(const rtc_tree *t, tt_stat_fn fn, void *user)
{
    const tt_rtc *c = &t->c;
    acc a;
    acc *ap = &a;
    memset(ap, 0, sizeof *ap);
    /* the root's box: the union of its children's */
    const float *root = tt_rtc_node(c, 0);
    float rb[6];
    rt_box_empty(rb);
    const uint32_t rc = tt_rtc_count(c, root);
    for (uint32_t i = 0; i < rc; i++) {
        float cb[6];
        rtc_child_box(c, root, i, cb);
        rt_box_grow(rb, cb);
    }
    ap->root_area = rc ? rt_box_area(rb) : 0.0;
    visit(c, ap, 0, rb);
    double interior_entries = 0.0;
    for (uint32_t l = 1; l <= c->height && l < 256; l++) interior_entries += ap->level_entries[l];
    const double bytes = (double)rtc_bytes(t);
    fn(user, "layout_compact", 1.0);
    fn(user, "triangles", c->triangles);
    /* leaf entries: more than the triangles when built with split references */
    fn(user, "references", ap->leaf_triangles);
    fn(user, "M", c->M);
    fn(user, "m", t->m);
    fn(user, "height", c->height + 1);
    fn(user, "nodes", ap->records + ap->leaves);
    fn(user, "interior_nodes", ap->records);
    fn(user, "leaves", ap->leaves);
    fn(user, "triangle_blocks", c->blocks);
    fn(user, "node_bytes", (double)c->words * 4.0);
    fn(user, "memory_bytes", bytes);
    fn(user, "bytes_per_triangle", c->triangles ? bytes / c->triangles : 0.0);
    fn(user, "leaf_fill", ap->leaves > 0 ? ap->leaf_triangles / ap->leaves : 0.0);
    fn(user, "interior_fill", ap->records > 0 ? interior_entries / ap->records : 0.0);
    fn(user, "sah_cost", rc ? ap->sah : 0.0);
    fn(user, "sah_cost_boxes", rc ? ap->sah_boxes : 0.0);
    fn(user, "block_fill", c->blocks ? ap->leaf_triangles / (c->blocks * TT_TRI_BLOCK_W) : 0.0);
    for (uint32_t l = 0; l <= c->height; l++) {
        char key[64];
        snprintf(key, sizeof key, "level%u_nodes", l);
        fn(user, key, ap->level_nodes[l]);
        snprintf(key, sizeof key, "level%u_sah", l);
        fn(user, key, rc ? ap->level_sah[l] : 0.0);
        snprintf(key, sizeof key, "level%u_fill", l);
        fn(user, key, ap->level_nodes[l] > 0 ? ap->level_entries[l] / ap->level_nodes[l] : 0.0);
    }
}
