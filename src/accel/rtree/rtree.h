/* The R-tree structure's private state: the packed tree (rtree_packed.h),
 * the arrays it points into, and what the statistics report. */
#ifndef TT_ACCEL_RTREE_RTREE_H
#define TT_ACCEL_RTREE_RTREE_H

#include "accel/accel.h"
#include "accel/rtree/build/rtree_build.h"
#include "accel/rtree/layout/rtree_packed.h"
#include "accel/rtree/rtc.h"

typedef struct rt_tree {
    /* TT_RTREE_LAYOUT_COMPACT: the tree is `compact` (rtc.h) and nothing
     * below but the options and timings is used */
    tt_rtree_layout layout;
    rtc_tree compact;

    tt_rtree_packed p;
    /* owned arrays behind p */
    float *box;
    uint8_t *count;
    uint32_t *leaf_start;
    float *tri;
    uint32_t *prim;
    size_t box_floats; /* 6 * M * groups */

    float root_box[6]; /* for the auto traversal's inside test */
    int m;             /* the fill minimum the check enforces */
    tt_rtree_traversal traversal;

    uint32_t real_nodes; /* present slots */
    /* the pointer tree of a changing scene, from the first tt_accel_update
     * on (rtree/update/rtree_dyn.h; NULL before) */
    struct rt_dyn *dyn;
    /* deformations before any pointer tree (rtree_vtable.c's update): the
     * records by level; and the motion envelope rebuild: a triangle's box
     * over the last frames (env, 6 floats an id, NULL when not gathering),
     * frames still to gather, the cost estimate after the last (re)build
     * and deformations since */
    uint32_t *lev_rec, lev_cap;
    float *env;
    uint32_t env_left, since_build, env_gap;
    double cost_base;
    double insert_s, pack_s;
} rt_tree;

/* Packs the finished pointer tree into t (allocating t's arrays; on error
 * t holds whatever was allocated, for rt_tree_free). */
tt_status rt_pack(tt_context *ctx, const rt_builder *b, const float *scene_tri, rt_tree *t);
void rt_tree_free(tt_context *ctx, rt_tree *t);
size_t rt_tree_bytes(const rt_tree *t);

/* Verifies the packed tree against the scene (rtree_check.c). */
tt_status rt_check(tt_context *ctx, const rt_tree *t, const tt_scene *scene);
/* Emits the statistics (rtree_stats.c). */
void rt_statistics(const rt_tree *t, tt_stat_fn fn, void *user);

/* The auto traversal's hint: which traversal rays from p use. The encoding
 * is the tt_rtree_traversal value: TT_RTREE_STACKLESS (1) for a point inside
 * the root box (closed), TT_RTREE_ORDERED (2) outside; with a forced
 * traversal option, that traversal's value. */
uint32_t rt_locate(const rt_tree *t, const float *p);

#endif
