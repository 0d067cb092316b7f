/* The built kd-tree as the library holds it: the arrays of kd_layout.h plus
 * what the build decided (effective parameters) and measured (statistics).
 * Tests include this header to walk the tree directly (comparing the two
 * builders node by node, aiming rays at actual split planes). */
#ifndef TT_ACCEL_KDTREE_KD_TREE_H
#define TT_ACCEL_KDTREE_KD_TREE_H

#include <stddef.h>

#include "accel/accel.h"
#include "accel/kdtree/kd_layout.h"
#include "accel/kdtree/trace/kd_trace_cpu.h"

typedef struct tt_kdtree {
    tt_kd_node *nodes;
    uint32_t node_slots; /* entries of nodes[], extension slots included    */
    uint32_t *refs;      /* triangle ids, leaf by leaf, ascending per leaf  */
    size_t ref_count;
    tt_kd_aug *aug;
    uint32_t aug_count;
    tt_kd_view view;

    /* The parameters the tree was built with (validated, auto resolved). */
    int dmin;      /* < 0: only the root is augmented                     */
    int max_depth; /* the depth limit the builder enforced                */
    int ref_budget_hit; /* some split was refused by the reference budget */
    /* A leaf may hold a triangle whose bounding box touches its cell but
     * whose polygon does not (the binned builder, kd_bin.h). */
    int loose_refs;
    double cost_traversal, cost_intersect, empty_factor;

    /* Shape, counted once after the build. */
    uint32_t nodes_total, interior, leaves, empty_leaves;
    int depth_max;
    double depth_mean; /* over leaves                                      */
    double sah_cost;   /* C_T sum SA(interior) + C_I sum n SA(leaf), / SA(root) */

    /* The fast traversal entry points of the accel's ISA, set by the
     * structure once built (kd_vtable.c, kd_io.c: tt_kdtree_use_isa);
     * scalar until then. They walk fast_view: `view` itself, or for the
     * kernels that test leaves as blocks (fast.blocks) block_view, the
     * block copy of kd_blocks.h, whose arrays the tree owns (block_nodes,
     * block_mem; all zero without one). */
    tt_kd_kernels fast;
    tt_kd_view fast_view;
    tt_kd_view block_view;
    tt_kd_node *block_nodes;
    void *block_mem;      /* blocks' allocation (64-byte aligned inside) */
    uint32_t block_count; /* tt_tri_block's in fast_view.blocks          */
    /* The block copy's nodes regrouped into cache lines for HTR
     * (kd_lines.h; block_view.lines points inside line_mem), or none. */
    void *line_mem;
    uint32_t line_count;
    uint32_t line_small; /* tt_kd_block4's after the lines               */
} tt_kdtree;

/* Builds the tree for accel->scene with accel->options.kdtree (validated
 * here; errors name the option). */
tt_status tt_kdtree_build(tt_context *ctx, const tt_scene *scene, const tt_kdtree_options *opt,
                          tt_kdtree **out);
void tt_kdtree_destroy(tt_context *ctx, tt_kdtree *tree);
size_t tt_kdtree_memory(const tt_kdtree *tree);
/* The invariants of tt_accel_check; reports the first broken one. */
tt_status tt_kdtree_check(tt_context *ctx, const tt_scene *scene, const tt_kdtree *tree);
/* The deepest augmented node (its aug[] index) whose box contains p, or
 * TT_INVALID_ID when p is outside the scene box. */
uint32_t tt_kdtree_locate(const tt_kdtree *tree, const float *p);

/* The tree behind a kd-tree accel (NULL for other structures). */
const tt_kdtree *tt_kdtree_of(const tt_accel *accel);

#endif
