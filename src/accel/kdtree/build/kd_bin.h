/* The binned builder's split choice (kd_bin_split.c), shared by its serial
 * recursion and its tasks (kd_build_binned.c).
 *
 * A reference is a triangle with a box: its bounds intersected with every
 * cell on the way down (a straddler's box is cut at the plane, the
 * triangle is not clipped). The box always contains the triangle's part in
 * the cell, so every triangle is in every leaf its part reaches (what the
 * traversals need); it may also be in a few leaves its box touches but the
 * triangle does not (tt_kdtree.loose: the check then tests soundness
 * against the box, not the polygon). */
#ifndef TT_ACCEL_KDTREE_KD_BIN_H
#define TT_ACCEL_KDTREE_KD_BIN_H

#include "accel/kdtree/build/kd_build.h"

typedef struct kd_bref {
    float lo[3], hi[3];
    uint32_t tri, pad; /* 32 bytes: two references per cache line half */
} kd_bref;

/* The boxes' union (inside the node's cell), kept for each node by the
 * partition that made it: the bins span it, not the whole cell. */
typedef struct kd_bbox {
    float lo[3], hi[3];
} kd_bbox;

/* Bin counts of a range of references, all three axes. */
#define KD_BINS 32
typedef struct kd_bins {
    uint32_t start[3][KD_BINS], end[3][KD_BINS];
} kd_bins;

/* Where the bins of a node lie: origin and bins per unit on each axis,
 * and how many bins (fewer for small nodes: most nodes are small, and a
 * node of n references has at most 2 n distinct bounds per axis). */
typedef struct kd_bin_grid {
    float lo[3], scale[3];
    int bins;
} kd_bin_grid;

kd_bin_grid kd_bin_grid_of(const kd_bbox *bounds, uint32_t n);
/* Adds refs [0, n) to bins (zeroed by the caller). */
void kd_bin_count(const kd_bref *refs, uint32_t n, const kd_bin_grid *g, kd_bins *bins);

/* The cheapest split among the bin boundaries and the two planes that cut
 * off the empty space beside the boxes' union, by the counts of the bins
 * (an estimate): axis -1 if none lies strictly inside the cell. */
kd_split kd_bin_best(const kd_builder *b, const kd_bins *bins, const kd_bin_grid *g, uint32_t n,
                     const kd_bbox *bounds, const tt_aabb *cell);
/* The small nodes' split: every box bound is a candidate, counted exactly
 * (O(n^2) in vector loops, no sort), the same planar rule. */
kd_split kd_bin_exact_small(const kd_builder *b, const kd_bref *refs, uint32_t n, const tt_aabb *cell);
/* Nodes of at most this many references take kd_bin_exact_small (a
 * multiple of 4: its vector width). */
#define KD_BIN_SMALL 16

/* Counts the children of split s exactly (kd_classify on the boxes) and
 * prices it: what kd_should_split and the reference budget need. */
void kd_bin_count_sides(const kd_builder *b, const kd_bref *refs, uint32_t n, const tt_aabb *cell,
                        kd_split *s);
/* The SAH cost of split s with its counts (kd_sweep's formula). */
double kd_bin_cost(const kd_builder *b, const tt_aabb *cell, const kd_split *s);

#endif
