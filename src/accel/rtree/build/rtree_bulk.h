/* Bulk loading of the R-tree for a static scene: the same pointer tree as
 * the insertion builder (rtree_build.h: all leaves on level 0, m..M entries
 * a node, the root 2..M or a single leaf, exact node boxes), built from all
 * triangles at once:
 *  - STR, Sort-Tile-Recursive (Leutenegger et al. 1997), bottom-up;
 *  - Hilbert-sorted packing (Kamel & Faloutsos 1993), bottom-up;
 *  - top-down by the surface area heuristic with the tree height fixed
 *    first (OMT-like), every cut chosen by SAH among the cuts whose sides
 *    still fit subtrees of the remaining height.
 * Nodes are numbered level by level from the leaves up (root last), so the
 * tree does not depend on the number of threads. */
#ifndef TT_ACCEL_RTREE_BULK_H
#define TT_ACCEL_RTREE_BULK_H

#include <stdint.h>

#include "accel/rtree/build/rtree_build.h"

/* Builds b (not initialised before; rt_builder_free afterwards, also after
 * an error) from triangles 0 .. T-1 whose boxes are tri_box (6 floats each,
 * kept by b) with the loader opt->build (not TT_RTREE_BUILD_INSERT). */
tt_status rt_bulk_build(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                        const float *tri_box, uint32_t T);

/* ---- shared by the loaders (rtree_bulk_common.c) ---- */

/* OpenMP threads for the build: the context's, or OpenMP's default. */
int rt_bulk_threads(tt_context *ctx);

/* Below this many entries a pass runs on one thread. Measured on the shared
 * 2-core machine: every parallel region costs a wake-up of the other
 * thread, which under load can take a scheduler slice, so on the bunny
 * (69k triangles) two threads were up to 3x slower than one; the regions
 * pay from a few hundred thousand entries on. */
#define RT_BULK_PARALLEL_MIN (1u << 18)

/* Sets b's options and allocates a pool of exactly `nodes` nodes, all in
 * use (headers zeroed; boxes and children uninitialised: the caller writes
 * every node's entries 0 .. count - 1). */
tt_status rt_bulk_pool(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                       const float *tri_box, uint32_t T, uint32_t nodes);

/* Groups of a level of n entries packed M at a time: ceil(n / M), 1 for
 * n = 0 (the empty root leaf). */
uint32_t rt_bulk_groups(uint32_t n, int M);

/* start[0 .. g] (g = rt_bulk_groups(n, M)): groups of M entries, except
 * that the last two are evened out when the last would hold fewer than m
 * (redistributed, never left underfull). */
void rt_bulk_chunk(uint32_t n, int m, int M, uint32_t *start);

/* Makes nodes first .. first + g - 1 on `level`: node first + j holds the
 * entries items[start[j] .. start[j + 1]) (triangle ids on level 0, node
 * ids above; those children get their parent links), boxes exact. */
void rt_bulk_make_level(rt_builder *b, int level, const uint32_t *items, const uint32_t *start,
                        uint32_t g, uint32_t first, int threads);

/* Box centres of the triangles (3 floats each, then one float 0 of padding):
 * the centroid of the box. */
tt_status rt_bulk_centres(tt_context *ctx, const float *tri_box, uint32_t T, float **out);

/* Bottom-up packing: leaves from the triangle ids in `order` (all T, in
 * packing order), then every level from the one below, whose node ids
 * (consecutive) are first put in packing order by `reorder` (NULL: keep
 * their order). The pool is allocated here. */
typedef tt_status (*rt_bulk_reorder_fn)(void *user, rt_builder *b, uint32_t *nodes, uint32_t n);
tt_status rt_bulk_bottom_up(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                            const float *tri_box, uint32_t T, const uint32_t *order,
                            rt_bulk_reorder_fn reorder, void *user);

/* Stable LSD radix sort of n (key, val) pairs by the low key_bits bits of
 * key, in place; tk/tv are scratch of n entries. The result does not depend
 * on `threads`. Errors: out of memory (the per-thread histograms). */
tt_status rt_radix_sort(tt_context *ctx, uint64_t *key, uint32_t *val, uint64_t *tk, uint32_t *tv,
                        size_t n, int key_bits, int threads);

/* A float's order as an unsigned integer (for radix sorting). */
static inline uint32_t rt_float_key(float f)
{
    union {
        float f;
        uint32_t u;
    } x = {f};
    return (x.u & 0x80000000u) ? ~x.u : x.u | 0x80000000u;
}

/* The index of cell (x, y, z) (bits bits each) along the 3D Hilbert curve. */
uint64_t rt_hilbert_key(uint32_t x, uint32_t y, uint32_t z, int bits);

/* The SAH loader's tree in level form, for packing straight into the
 * compact layout (rtc_pack_levels) without the pointer tree, whose node
 * pool (6 x 20 floats of boxes a node, most of them leaves of two or three
 * triangles) was a third of the build's time in page faults and writes.
 * Level 0 holds the leaves, level `height` (>= 1) the root; nodes of a
 * level are numbered left to right, which is also depth-first order. */
typedef struct rt_bulk_levels {
    uint32_t height, M, triangles;
    uint32_t count[TT_RT_BUILD_LEVELS];  /* nodes on each level            */
    /* level-l node j's entries are [first[l][j], first[l][j + 1]): on level
     * 0 positions in `order`, above it nodes of level l - 1 */
    uint32_t *first[TT_RT_BUILD_LEVELS];
    float *box[TT_RT_BUILD_LEVELS];      /* 6 floats a node, exact          */
    const uint32_t *order;               /* triangle ids in leaf order      */
    uint32_t *order_mem, *first_mem;     /* owned                           */
    float *box_mem;
} rt_bulk_levels;

/* The SAH loader (opt->build is not read) into lv, for T >= 1 triangles
 * whose root is above the leaves (T > M; otherwise an invalid-argument
 * error: build the pointer tree). rt_bulk_levels_free afterwards, also
 * after an error. */
tt_status rt_bulk_sah_levels(rt_bulk_levels *lv, tt_context *ctx, const tt_rtree_options *opt,
                             const float *tri_box, uint32_t T);
void rt_bulk_levels_free(tt_context *ctx, rt_bulk_levels *lv);

/* The loaders. */
tt_status rt_bulk_str(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                      const float *tri_box, uint32_t T);
tt_status rt_bulk_hilbert(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                          const float *tri_box, uint32_t T);
tt_status rt_bulk_sah(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                      const float *tri_box, uint32_t T);

#endif
