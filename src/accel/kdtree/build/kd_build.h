/* What the two kd-tree builders share: the cost model, the sweep over sorted
 * split candidates, the classification of triangles against a split, and
 * the emission of nodes (augmentation included). Both builders call exactly
 * these functions in the same order with equal inputs, which is why they
 * produce the same tree; they differ only in how they obtain the sorted
 * candidate lists (sorting at every node, or sorting once and splitting the
 * sorted lists). */
#ifndef TT_ACCEL_KDTREE_KD_BUILD_H
#define TT_ACCEL_KDTREE_KD_BUILD_H

#include <stdint.h>

#include "accel/kdtree/build/kd_events.h"
#include "accel/kdtree/kd_tree.h"
#include "geometry/aabb.h"

enum { KD_SIDE_LEFT = 1, KD_SIDE_RIGHT = 2, KD_SIDE_BOTH = 3 };

typedef struct kd_split {
    int axis;        /* -1: none found                                    */
    float pos;
    int planar_left; /* triangles lying in the plane go left (1) or right */
    double cost;
    /* The children's triangle counts as the sweep sees them: the
     * straddlers in both. Re-clipping may drop some, never add. */
    uint32_t n_left, n_right;
} kd_split;

/* Where a node sits: depth, distance to its nearest augmented ancestor (in
 * levels) and that ancestor's aug[] record. */
typedef struct kd_place {
    int depth;
    int aug_dist;
    uint32_t parent_aug;
} kd_place;

typedef struct kd_par kd_par;

typedef struct kd_builder {
    tt_context *ctx;
    const float *tri;
    uint32_t tri_count;
    double ct, ci, empty_factor;
    int max_depth, dmin;
    /* The reference budget (see kd_should_split): `live` counts the
     * references emitted plus those of the nodes still to be built, exactly
     * (kd_account_split keeps it). */
    size_t ref_budget, live;
    int budget_hit;
    /* Set while a parallel build runs (kd_build_par.h): the budget is then
     * checked against a bound instead of `live` (see kd_should_split). */
    kd_par *par;
    /* output, grown as the depth-first recursion emits nodes */
    tt_kd_node *nodes;
    uint32_t node_count, node_cap;
    uint32_t *refs;
    size_t ref_count, ref_cap;
    tt_kd_aug *aug;
    uint32_t aug_count, aug_cap;
} kd_builder;

/* Keeps a candidate split in *best when it is strictly cheaper (the first
 * of equal costs wins, which keeps every builder deterministic). */
static inline void kd_split_offer(kd_split *best, double cost, int axis, float pos,
                                  int planar_left, uint32_t n_left, uint32_t n_right)
{
    if (cost < best->cost) {
        best->cost = cost;
        best->axis = axis;
        best->pos = pos;
        best->planar_left = planar_left;
        best->n_left = n_left;
        best->n_right = n_right;
    }
}

/* Sweeps one axis' sorted events (Wald & Havran's planar-aware sweep) and
 * keeps the cheapest split strictly inside the cell in *best. n is the
 * number of triangles in the node. */
void kd_sweep(const kd_builder *b, const uint64_t *ev, size_t n_ev, uint32_t n,
              const tt_aabb *cell, int axis, kd_split *best);

/* Whether the best split pays (cost below the leaf's C_I * n) at this depth,
 * and its children fit the reference budget. */
int kd_should_split(kd_builder *b, uint32_t n, int depth, const kd_split *best);
/* Records that a node of n triangles was split into children of nl and nr. */
void kd_account_split(kd_builder *b, uint32_t n, uint32_t nl, uint32_t nr);
/* The budget of references for a scene of n triangles. */
size_t kd_ref_budget(uint32_t n);

/* Side of a triangle whose clipped bounds on the split axis are [lo, hi]. */
static inline int kd_classify(float lo, float hi, const kd_split *s)
{
    if (lo == hi && lo == s->pos) return s->planar_left ? KD_SIDE_LEFT : KD_SIDE_RIGHT;
    if (hi <= s->pos) return KD_SIDE_LEFT;
    if (lo >= s->pos) return KD_SIDE_RIGHT;
    return KD_SIDE_BOTH;
}

/* The children's cells. */
void kd_split_cell(const tt_aabb *cell, const kd_split *s, tt_aabb *left, tt_aabb *right);

/* Emits a leaf with the given triangle ids (sorted here, in place). */
tt_status kd_emit_leaf(kd_builder *b, uint32_t *ids, uint32_t n);
/* Emits an interior node (augmenting it if the d_min rule says so) and
 * returns its index and the places of its children. */
tt_status kd_emit_interior(kd_builder *b, const kd_split *s, const tt_aabb *cell,
                           const kd_place *here, uint32_t *node, kd_place *child);
/* Links an interior node to its right child, about to be emitted next. */
void kd_link_right(kd_builder *b, uint32_t node);

/* The builders: each fills b's arrays for the whole scene. The binned
 * one (kd_build_binned.c) approximates the others' tree. */
tt_status kd_build_nlogn(kd_builder *b, const tt_aabb *root);
tt_status kd_build_nlog2n(kd_builder *b, const tt_aabb *root);
tt_status kd_build_binned(kd_builder *b, const tt_aabb *root);

/* Sets the context's error message; safe from concurrent tasks. */
tt_status kd_fail(kd_builder *b, tt_status st, const char *fmt, ...);
tt_status kd_oom(kd_builder *b);

#endif
