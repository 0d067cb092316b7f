/* What the parallel builds share. A node of at least kd_par_cutoff
 * triangles is split by the task that holds it (its sweep over the three
 * axes in parallel), and each child goes to a task of its own; smaller
 * nodes are built by the serial recursion, each subtree into arrays of its
 * own. Every task's result is a kd_sub. When all are done, kd_replay walks
 * them depth first and emits every node into the builder exactly as the
 * serial recursion would have (same order, indices, references, sparse
 * boxes), so the tree does not depend on the number of threads.
 *
 * The reference budget is the one decision that depends on the order of
 * the whole build (kd_should_split: every split before the node counts).
 * A parallel build never refuses a split for it; it sums G, how much each
 * split adds to the references as its sweep counts them (never less than
 * the split really adds). In the serial order the count at any node is at
 * most m + G (m: the root's references), so while m + G stays within the
 * budget the serial build would refuse no split either and the trees are
 * equal. Once m + G passes it, the parallel build stops and the serial one
 * builds the tree instead: only scenes that come near the budget pay. */
#ifndef TT_ACCEL_KDTREE_KD_BUILD_PAR_H
#define TT_ACCEL_KDTREE_KD_BUILD_PAR_H

#include "accel/kdtree/build/kd_build.h"

struct kd_par {
    size_t m;      /* references at the root                           */
    size_t growth; /* G, updated atomically                            */
    int abort;     /* m + G passed the budget: stop, build serially    */
};

/* Smallest node split by a task (and smallest scene built in parallel).
 * Tests lower it to run the parallel path on small scenes. */
extern uint32_t kd_par_cutoff;

/* The threads a build of the context uses: 1 means serial. */
int kd_par_threads(tt_context *ctx);

/* kd_should_split's rule while a parallel build runs: adds the split's
 * growth to G and flags the abort when m + G passes the budget. */
int kd_par_account(kd_builder *b, uint32_t n, const kd_split *best);
int kd_par_aborted(const kd_builder *b);
/* What a builder returns when it stopped for the abort. */
#define KD_ABORTED TT_ERR_INTERNAL

/* A task's result: a node split by tasks (split.axis >= 0, its children in
 * kid) or a subtree built serially into out (local indices; its boxes and
 * links are rebuilt by the replay). */
typedef struct kd_sub {
    kd_split split;
    struct kd_sub *kid[2];
    kd_builder out;
    tt_status st;
} kd_sub;

/* A new empty result whose out has b's parameters. NULL: out of memory. */
kd_sub *kd_sub_new(const kd_builder *b);
void kd_sub_free(tt_context *ctx, kd_sub *sub);
/* The place of a node's children (kd_emit_interior's rule). */
kd_place kd_child_place(const kd_builder *b, const kd_place *here);
/* Emits the results into b depth first, as the serial build would. */
tt_status kd_replay(kd_builder *b, kd_sub *root, const tt_aabb *cell);

#endif
