/* The "wbvh" structure: a wide bounding volume hierarchy. Unlike the
 * R-tree (rtree/), whose leaves all sit on one level, its leaves sit
 * wherever the surface area heuristic puts them: a binary tree built top
 * down by binned SAH (wbvh_build.c), collapsed into M-wide nodes by
 * opening the child of largest surface area until a node is full
 * (wbvh_pack.c), stored in the R-tree's compact records (rtc_layout.h) as
 * mixed nodes: a record's entries may be leaves and nodes at once (level
 * field 0, see below), and traced by its own near-to-far kernel per ISA
 * (wbvh_trace.h). The check, statistics and memory of the compact layout
 * are shared (rtc_check.c knows mixed records).
 *
 * Mixed records (rtc_layout.h with these differences): the level field is
 * 0 in every record; a record's leaf entries come first, in the order of
 * their blocks, then its node entries, consecutive nodes after it; the
 * header's `height` is the depth of the deepest record (root: 1). The
 * leaves of one record are placed together (first fit, as rtc_pack.c
 * places them), so they lie within 2 M blocks from the first one's, which
 * the kernel's set of tested blocks needs. A leaf holds 1..M triangles. */
#ifndef TT_ACCEL_WBVH_WBVH_H
#define TT_ACCEL_WBVH_WBVH_H

#include "accel/accel.h"
#include "accel/rtree/rtc.h"

/* The kernel's stack: M - 1 waiting nodes per record on the path, and the
 * packer refuses a tree deeper than this allows. */
#define TT_WBVH_STACK_SIZE 1280

/* The structure's state (accel->impl): the records in the compact
 * layout's owner, with its trace functions (wbvh_select). */
typedef struct wbvh_tree {
    rtc_tree t;
    double build_s, pack_s;
} wbvh_tree;

/* The binary builder's tree (wbvh_build.c): node 0 the root. */
typedef struct wbvh_bin_node {
    float box[6];   /* lo xyz, hi xyz: exact union of the content */
    uint32_t a, b;  /* interior: children; leaf: a = first index in `order` */
    uint32_t count; /* 0: interior; else the leaf's triangles             */
} wbvh_bin_node;

typedef struct wbvh_bin_tree {
    wbvh_bin_node *node;
    uint32_t nodes;
    uint32_t *order; /* triangle ids, each leaf's a range              */
} wbvh_bin_tree;

/* The binned SAH build over triangles 0 .. T-1 (tri_box: 6 floats each):
 * leaves of at most max_leaf triangles; OpenMP tasks on `threads` threads
 * for large inputs; the tree does not depend on the thread count. */
tt_status wbvh_build_binary(tt_context *ctx, const float *tri_box, uint32_t T, uint32_t max_leaf,
                            int threads, wbvh_bin_tree *out);
void wbvh_bin_free(tt_context *ctx, wbvh_bin_tree *b);

/* Collapses b into M-wide mixed records and writes them with the leaves'
 * triangle blocks into t (t->c, node_mem, block_mem; rtc_free frees). */
tt_status wbvh_pack(tt_context *ctx, const wbvh_bin_tree *b, const float *scene_tri, uint32_t T,
                    uint32_t M, rtc_tree *t);

/* The traversal units (wbvh_trace_<isa>.c) and the choice among them. */
#define TT_WBVH_DECLARE(isa)                                                                      \
    int tt_wbvh_trace_##isa(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,              \
                            tt_ray_stats *stats);                                                 \
    int tt_wbvh_trace_##isa##_stats(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,      \
                                    tt_ray_stats *stats);                                         \
    void tt_wbvh_trace_##isa##_rows(const tt_rtc *t, const tt_packet_rays *rays, int any,         \
                                    tt_hit *hits, uint8_t *occ);
TT_WBVH_DECLARE(scalar)
#ifdef TT_HAVE_X86_KERNELS
TT_WBVH_DECLARE(sse42)
TT_WBVH_DECLARE(avx2)
TT_WBVH_DECLARE(avx512)
#endif
void wbvh_select(rtc_tree *t, tt_isa isa);

#endif
