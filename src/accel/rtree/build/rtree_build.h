/* The R-tree while it is being built: a pointer tree (indices into a node
 * pool) grown by successive insertion of triangles, as in Guttman (1984) and
 * the R*-tree of Beckmann et al. (1990), in 3D. It is packed into the
 * paper's level-order array afterwards (rtree_pack.h) and then freed.
 *
 * Levels count from the leaves (level 0) up to the root, so a node keeps its
 * level when the tree grows a new root; forced reinsertion re-inserts ejected
 * entries "at their level" by that number. */
#ifndef TT_ACCEL_RTREE_BUILD_H
#define TT_ACCEL_RTREE_BUILD_H

#include <stdint.h>

#include "accel/rtree/layout/rtree_packed.h"
#include "core/context.h"

#define TT_RT_CAP (TT_RT_MAX_M + 1) /* an overflowing node holds M + 1 */
/* Levels the builder supports; the packer's own limit is far lower. */
#define TT_RT_BUILD_LEVELS 32

typedef struct rt_node_hdr {
    uint32_t parent; /* node index; TT_INVALID_ID for the root             */
    uint8_t slot;    /* this node's entry position within its parent        */
    uint8_t count;   /* entries in use (up to M + 1 while overflowing)      */
    uint8_t level;   /* 0: leaf, its entries are triangles                  */
    uint8_t pad;
} rt_node_hdr;

struct rt_overlap_keys; /* rtree_choose_overlap.h */

typedef struct rt_builder {
    tt_context *ctx;
    /* options */
    int m, M, cap; /* cap = M + 1 entries per node in the pool             */
    tt_rtree_strategy strategy;
    tt_rtree_split split;
    int reinsert, reinsert_count, reinsert_far;

    /* node pool: header, boxes as six arrays of cap floats per node
     * (lo x, lo y, lo z, hi x, hi y, hi z: structure of arrays, so one
     * bound of all entries is contiguous), children (node index, or the
     * triangle id in a leaf). */
    uint32_t node_count, node_cap;
    rt_node_hdr *hdr;
    float *box;
    uint32_t *child;
    uint32_t root;

    const float *tri_box; /* 6 floats a triangle: lo xyz, hi xyz            */
    uint32_t triangles;   /* inserted so far                                */

    /* levels that already had their forced reinsert during the current
     * top-level insertion (bit l for level l) */
    uint32_t reinserted_levels;

    /* Dynamic updates (rtree/update/; all NULL / 0 for a one-shot build):
     * leaf_of[id] is the leaf node holding triangle id, kept by every
     * insertion, split and reinsert; free_node the pool nodes deletion gave
     * back, which new nodes take first. */
    uint32_t *leaf_of;
    uint32_t *free_node;
    uint32_t free_count;
    /* touch(touch_user, n): node n's entries or their boxes changed (an
     * entry added, removed, moved within n, or a box grown or tightened),
     * so the dynamic update rewrites what the compact layout holds of it
     * (rtree_dyn_compact.c); NULL for a one-shot build */
    void (*touch)(void *user, uint32_t n);
    void *touch_user;
    /* Dynamic updates (0 for one-shot builds: the strategy's choice): a
     * triangle goes where the tree's SAH cost grows least. The level-1
     * nodes are searched best first by the area their path's boxes grow
     * (Bittner et al. 2013's insertion search), up to sah_max_evals of
     * them; in each, joining leaf i costs A(leaf i + t) (count + 1) -
     * A(leaf i) count, a new leaf of its own A(t), and an option that
     * splits a full node (a new leaf in it, or a full leaf's split) also
     * sah_split_cost x the node's area (one more node to visit). The
     * search also stops after sah_max_pops candidates (interior or
     * level-1) taken off its heap (0: no such bound). */
    int sah_leaves, sah_max_evals, sah_max_pops;
    float sah_split_cost;
    /* the overlap criterion's kernel for this CPU (rtree_choose_overlap.h);
     * NULL: the baseline one */
    void (*overlap_keys)(const float *s, int cap, int cnt, const float e[6],
                         struct rt_overlap_keys *k);
} rt_builder;

/* Tells the dynamic update that node n changed (rt_builder.touch). */
static inline void rt_builder_touch(const rt_builder *b, uint32_t n)
{
    if (b->touch) b->touch(b->touch_user, n);
}

/* The six bound arrays of node n: b[k * cap + i] is bound k of entry i. */
static inline float *rt_node_box(const rt_builder *b, uint32_t n)
{
    return b->box + (size_t)n * 6 * (size_t)b->cap;
}
static inline uint32_t *rt_node_child(const rt_builder *b, uint32_t n)
{
    return b->child + (size_t)n * (size_t)b->cap;
}

/* Sets up an empty tree (one empty leaf as root) for the options, which the
 * caller has validated. tri_box must outlive the builder. */
tt_status rt_builder_init(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                          const float *tri_box, uint32_t triangle_count_hint);
void rt_builder_free(rt_builder *b);

/* Inserts triangle `id` (its box is tri_box[6 * id ..]). */
tt_status rt_builder_insert_triangle(rt_builder *b, uint32_t id);

/* For the dynamic update (rtree/update/): a fresh node at `level` (from the
 * free list first), and the insertion of one entry (box e, child c: a
 * triangle id for level 0, else a node) into a node at `level`, with the
 * strategy, splits and forced reinsert of a top-level insertion. */
tt_status rt_builder_new_node(rt_builder *b, int level, uint32_t *out);
tt_status rt_builder_insert_entry(rt_builder *b, const float e[6], uint32_t c, int level);
/* Entry (e, c) appended to node n, whose room the caller has checked: the
 * child's parent link (or, at level 0, the triangle's leaf) is set and the
 * node touched. The builder's, the update's rebuild's and the compaction's
 * one way to place an entry. */
void rt_builder_put(rt_builder *b, uint32_t n, const float e[6], uint32_t c);

/* The box of everything in node n (the union of its entries). */
void rt_node_bounds(const rt_builder *b, uint32_t n, float out[6]);

/* Verifies the pointer tree: levels, parent links, fill m..M, exact node
 * boxes, every inserted triangle exactly once. TT_ERR_INVARIANT through
 * tt_error naming the node and the broken rule. For white-box tests. */
tt_status rt_builder_check(const rt_builder *b);

/* The RR*-tree's choice of the entry of node n that receives box e
 * (rtree_choose_rrstar.c; strategy TT_RTREE_RRSTAR). */
int rt_choose_rrstar(const rt_builder *b, uint32_t n, const float e[6]);

/* choose_entry's overlap criterion (rtree_choose_overlap.c): min-overlap,
 * and the R* variants in the nodes just above the leaves. */
int rt_choose_overlap(const rt_builder *b, uint32_t n, const float e[6]);

/* Splitting an overflowing node (rtree_split.c): fills group[i] with 0 or
 * 1 for each of the node's count entries, both groups holding >= m. */
void rt_split_rstar(const rt_builder *b, uint32_t n, uint8_t *group);
void rt_split_quadratic(const rt_builder *b, uint32_t n, uint8_t *group);

#endif
