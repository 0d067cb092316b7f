/* Statistics of the packed R-tree, read back from the array.
 *
 * SAH cost: the standard surface area heuristic of a BVH with C_trav = 1
 * and C_isect = 1, areas relative to the root's:
 *   sah_cost = sum over interior nodes n of A(n)/A(root) * 1
 *            + sum over leaves f of A(f)/A(root) * 1 * triangles(f)
 * (one traversal step per interior node reached). sah_cost_boxes charges
 * an interior node one unit per child box instead, which is what an M-ary
 * traversal actually tests.
 * insert_s is the time to build the pointer tree, by insertion or by a bulk
 * loader (--build); pack_s the packing.
 * These are the tree-quality figures that compare the builders (insert,
 * str, hilbert, sah) on one scene, with leaf_fill (triangles per leaf) and
 * interior_fill (entries per interior node), averages over the real nodes.
 * levelL_overlap: the summed pairwise intersection volume of sibling boxes
 * (children of one node) on level L, relative to the root's volume — the
 * quantity the overlap-minimising strategies reduce; 0 when the root box is
 * flat. levelL_sah: level L's part of sah_cost (the levels' parts sum to
 * it), which shows where a tree lost quality against another (an updated
 * tree against a fresh build: tt_accel_update's deformations). */
#include <stdio.h>
#include <string.h>

#include "accel/rtree/rtree.h"
#include "accel/rtree/rtree_box.h"

typedef struct level_stats {
    double nodes, entries, overlap, sah;
} level_stats;

typedef struct acc {
    const tt_rtree_packed *p;
    level_stats level[TT_RT_MAX_LEVELS];
    double sah, sah_boxes, root_area;
} acc;

static void slot_box(const tt_rtree_packed *p, uint32_t n, float out[6])
{
    uint32_t pos;
    const float *g = tt_rt_group(p, n, &pos);
    for (int k = 0; k < 6; k++) out[k] = g[k * p->M + pos];
}

static void visit(acc *a, uint32_t n, uint32_t l)
{
    const tt_rtree_packed *p = a->p;
    float b[6];
    slot_box(p, n, b);
    const double rel = a->root_area > 0.0 ? rt_box_area(b) / a->root_area : 1.0;
    level_stats *ls = &a->level[l];
    ls->nodes += 1.0;
    if (l == 0) {
        uint32_t j = n - p->delta[0];
        uint32_t cnt = p->leaf_start[j + 1] - p->leaf_start[j];
        ls->entries += cnt;
        a->sah += rel * cnt;
        ls->sah += rel * cnt;
        a->sah_boxes += rel * cnt;
        return;
    }
    const uint32_t cnt = p->count[n], e = tt_rt_first_child(p, n, l);
    ls->entries += cnt;
    a->sah += rel;
    ls->sah += rel;
    a->sah_boxes += rel * cnt;
    float cb[TT_RT_MAX_M][6];
    for (uint32_t i = 0; i < cnt; i++) {
        slot_box(p, e + i, cb[i]);
        for (uint32_t k = 0; k < i; k++) a->level[l - 1].overlap += rt_box_overlap(cb[i], cb[k]);
        visit(a, e + i, l - 1);
    }
}

void rt_statistics(const rt_tree *t, tt_stat_fn fn, void *user)
{
    const tt_rtree_packed *p = &t->p;
    acc a;
    memset(&a, 0, sizeof a);
    a.p = p;
    float root[6];
    slot_box(p, 0, root);
    double root_volume = 0.0;
    if (p->triangles > 0) {
        a.root_area = rt_box_area(root);
        root_volume = rt_box_volume(root);
        visit(&a, 0, p->L);
    }
    double nodes = 0.0;
    for (uint32_t l = 0; l <= p->L; l++) nodes += a.level[l].nodes;
    fn(user, "triangles", p->triangles);
    fn(user, "M", p->M);
    fn(user, "m", t->m);
    fn(user, "height", p->L + 1);
    fn(user, "nodes", nodes);
    fn(user, "leaves", a.level[0].nodes);
    fn(user, "slots", p->slots);
    fn(user, "empty_slots", p->slots - nodes);
    fn(user, "empty_fraction", p->slots ? (p->slots - nodes) / p->slots : 0.0);
    fn(user, "memory_bytes", (double)rt_tree_bytes(t));
    double interior = 0.0, interior_entries = 0.0;
    for (uint32_t l = 1; l <= p->L; l++) {
        interior += a.level[l].nodes;
        interior_entries += a.level[l].entries;
    }
    fn(user, "leaf_fill", a.level[0].nodes > 0 ? a.level[0].entries / a.level[0].nodes : 0.0);
    fn(user, "interior_fill", interior > 0 ? interior_entries / interior : 0.0);
    fn(user, "sah_cost", a.sah);
    fn(user, "sah_cost_boxes", a.sah_boxes);
    fn(user, "insert_s", t->insert_s);
    fn(user, "pack_s", t->pack_s);
    for (uint32_t l = 0; l <= p->L; l++) {
        char key[64];
        const level_stats *ls = &a.level[l];
        snprintf(key, sizeof key, "level%u_nodes", l);
        fn(user, key, ls->nodes);
        snprintf(key, sizeof key, "level%u_sah", l);
        fn(user, key, ls->sah);
        snprintf(key, sizeof key, "level%u_fill", l);
        fn(user, key, ls->nodes > 0 ? ls->entries / ls->nodes : 0.0);
        snprintf(key, sizeof key, "level%u_overlap", l);
        fn(user, key, root_volume > 0.0 ? ls->overlap / root_volume : 0.0);
    }
}
