/* Helpers for the kd-tree tests: building with given options, comparing two
 * trees node by node, collecting the tree's split planes. */
#ifndef TT_TEST_KD_TESTING_H
#define TT_TEST_KD_TESTING_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accel/kdtree/kd_blocks.h"
#include "accel/kdtree/kd_tree.h"
#include "io/scene.h"
#include "check.h"

static inline tt_accel *kd_build_with(tt_context *ctx, const tt_scene *scene, tt_kd_builder builder,
                                      int dmin, tt_kd_traversal traversal)
{
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = "kdtree";
    o.kdtree.builder = builder;
    o.kdtree.dmin = dmin;
    o.kdtree.traversal = traversal;
    tt_accel *a = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &o, &a));
    return a;
}

/* Four views of one built tree, one per traversal: copies of the accel
 * struct sharing its tree (impl), so a test need not build the same tree
 * four times. Only the original may be destroyed. */
static inline void kd_traversal_views(const tt_accel *a, tt_accel views[4])
{
    for (int tr = TT_KD_HTR; tr <= TT_KD_SEQ; tr++) {
        views[tr] = *a;
        views[tr].options.kdtree.traversal = (tt_kd_traversal)tr;
    }
}

static const char *const kd_traversal_names[] = {"htr", "btr", "sltr", "seq"};

/* The ISAs this CPU and build run (tt_test_isa_runs: those compiled in but
 * not runnable are announced and make the program a visible skip), scalar
 * first. */
static inline size_t kd_isas(tt_isa out[TT_ISA_AVX512 + 1])
{
    size_t n = 0;
    for (int i = TT_ISA_SCALAR; i <= TT_ISA_AVX512; i++)
        if (tt_test_isa_runs((tt_isa)i)) out[n++] = (tt_isa)i;
    return n;
}

/* A view of kd-tree accel `a` running the fast kernels of `isa`: copies of
 * the accel and tree structs sharing the tree's arrays, as a build with
 * options.isa = isa would have them (tt_kd_cpu_kernels), with leaf blocks
 * of its own (kd_blocks.h) where the kernels read them. Only `a` may be
 * destroyed; free the view with kd_isa_view_free. */
static inline tt_accel *kd_isa_view(const tt_accel *a, tt_isa isa)
{
    tt_accel *v = malloc(sizeof *v);
    tt_kdtree *t = malloc(sizeof *t);
    if (!v || !t) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    *v = *a;
    *t = *tt_kdtree_of(a);
    t->block_nodes = NULL;
    t->block_mem = NULL;
    t->fast = tt_kd_cpu_kernels(isa, tt_scene_triangle_count(a->scene));
    t->fast_view = t->view;
    if (t->fast.blocks) {
        if (tt_kdtree_blocks_build(a->ctx, t, a->scene->tri) != TT_OK) {
            fprintf(stderr, "out of memory\n");
            exit(1);
        }
        t->fast_view = t->block_view;
    }
    v->impl = t;
    v->isa = isa;
    return v;
}

static inline void kd_isa_view_free(tt_accel *v)
{
    if (!v) return;
    tt_kdtree *t = v->impl;
    tt_free(v->ctx, t->block_nodes);
    tt_free(v->ctx, t->block_mem);
    free(t);
    free(v);
}

/* Walks both trees in parallel; returns 1 if they are the same tree (every
 * node's kind, split axis and position, augmentation and box, every leaf's
 * triangles), else prints the first difference and returns 0. */
static inline int kd_same_node(const tt_kdtree *a, const tt_kdtree *b, uint32_t na, uint32_t nb)
{
    tt_kd_node x = a->nodes[na], y = b->nodes[nb];
    if (tt_kd_is_leaf(x.bits) != tt_kd_is_leaf(y.bits)) {
        fprintf(stderr, "node %u: leaf in one tree, interior in the other\n", na);
        return 0;
    }
    if (tt_kd_is_leaf(x.bits)) {
        uint32_t n = tt_kd_leaf_count(x.bits);
        if (n != tt_kd_leaf_count(y.bits) ||
            (n && memcmp(a->refs + x.u.first, b->refs + y.u.first, n * sizeof(uint32_t)) != 0)) {
            fprintf(stderr, "node %u: leaves hold different triangles (%u vs %u)\n", na, n,
                    tt_kd_leaf_count(y.bits));
            return 0;
        }
        return 1;
    }
    if (tt_kd_axis(x.bits) != tt_kd_axis(y.bits) || x.u.split != y.u.split) {
        fprintf(stderr, "node %u: split axis %d at %.9g vs axis %d at %.9g\n", na,
                tt_kd_axis(x.bits), x.u.split, tt_kd_axis(y.bits), y.u.split);
        return 0;
    }
    if (tt_kd_is_aug(x.bits) != tt_kd_is_aug(y.bits)) {
        fprintf(stderr, "node %u: augmented in one tree only\n", na);
        return 0;
    }
    if (tt_kd_is_aug(x.bits)) {
        const tt_kd_aug *p = &a->aug[tt_kd_aug_index(a->nodes, na)];
        const tt_kd_aug *q = &b->aug[tt_kd_aug_index(b->nodes, nb)];
        if (memcmp(p->lo, q->lo, sizeof p->lo) || memcmp(p->hi, q->hi, sizeof p->hi) ||
            p->parent != q->parent) {
            fprintf(stderr, "node %u: boxes or parent links differ\n", na);
            return 0;
        }
    }
    return kd_same_node(a, b, tt_kd_left(na, x.bits), tt_kd_left(nb, y.bits)) &&
           kd_same_node(a, b, tt_kd_right(x.bits), tt_kd_right(y.bits));
}

static inline int kd_same_tree(const tt_kdtree *a, const tt_kdtree *b)
{
    if (a->node_slots != b->node_slots || a->ref_count != b->ref_count ||
        a->aug_count != b->aug_count) {
        fprintf(stderr, "trees differ in size: %u/%u slots, %zu/%zu refs, %u/%u boxes\n",
                a->node_slots, b->node_slots, a->ref_count, b->ref_count, a->aug_count,
                b->aug_count);
        return 0;
    }
    return kd_same_node(a, b, 0, 0);
}

/* A split plane of the tree, with the cell of its node. */
typedef struct kd_plane {
    int axis;
    float pos;
    float lo[3], hi[3];
} kd_plane;

static inline size_t kd_collect(const tt_kdtree *t, uint32_t node, float lo[3], float hi[3],
                                kd_plane *out, size_t n, size_t cap)
{
    tt_kd_node x = t->nodes[node];
    if (tt_kd_is_leaf(x.bits)) return n;
    int axis = tt_kd_axis(x.bits);
    if (n < cap) {
        out[n].axis = axis;
        out[n].pos = x.u.split;
        memcpy(out[n].lo, lo, 3 * sizeof(float));
        memcpy(out[n].hi, hi, 3 * sizeof(float));
        n++;
    }
    float l_hi[3], r_lo[3];
    memcpy(l_hi, hi, sizeof l_hi);
    memcpy(r_lo, lo, sizeof r_lo);
    l_hi[axis] = r_lo[axis] = x.u.split;
    n = kd_collect(t, tt_kd_left(node, x.bits), lo, l_hi, out, n, cap);
    return kd_collect(t, tt_kd_right(x.bits), r_lo, hi, out, n, cap);
}

#endif
