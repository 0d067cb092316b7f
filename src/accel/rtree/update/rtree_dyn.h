/* The R-tree of a changing scene (tt_accel_update): the pointer tree of
 * rtree_build.h kept beside the compact layout, so that triangles can be
 * deleted (Guttman's condense step, orphans reinserted), inserted (the R*
 * choices, splits and forced reinsert of the insertion builder) and refit
 * (moved triangles' boxes up the tree) where they are, and the compact
 * layout follows.
 *
 * The pointer tree is not kept by a one-shot build (it would double the
 * memory of every static scene): the first update rebuilds it from the
 * compact layout, node for node, so the tree keeps the quality of its
 * builder (SAH by default). From then on the structure holds both. */
#ifndef TT_ACCEL_RTREE_DYN_H
#define TT_ACCEL_RTREE_DYN_H

#include "accel/rtree/build/rtree_build.h"
#include "accel/rtree/rtc.h"
#include "io/scene.h"

/* Free groups or region blocks past 1 / RT_DYN_COMPACT_FREE of the
 * records or blocks make the next layout sync a compaction: the slack
 * layout rewritten fresh, depth first, which also restores the
 * traversal's memory locality (`update_compaction_free` in the statistics
 * and `treetrace info`). */
#define RT_DYN_COMPACT_FREE 4

typedef struct rt_dyn {
    rt_builder b;
    tt_rtree_options opt; /* the tree's options (the local rebuilds' loader) */
    float *tri_box;      /* 6 floats an id: the box the tree holds it with  */
    uint32_t *leaf_of;   /* b.leaf_of: the leaf of an id, TT_INVALID_ID: absent */
    size_t id_cap;       /* ids the three per-id arrays hold                 */
    uint32_t *free_node; /* b.free_node's storage                            */
    uint32_t free_cap;
    /* the compact layout's places of the pointer tree's parts: rec_of[node]
     * the record of an interior node (in the slack layout: the first block
     * of a leaf), lane_of[id] the global triangle lane of an id */
    uint32_t *rec_of;
    uint32_t rec_cap;
    uint32_t *lane_of;
    /* The slack layout (rtree_dyn_compact.c), which in-place updates keep:
     * every node above level 1 owns a group of M consecutive records for
     * its children; every level-1 node a region of 2^k blocks (k: grp_hi)
     * in which each of its leaves owns a slot of lanes
     * (rtree_dyn_region.c). An entry added or removed rewrites its node's
     * record and, on level 1, the lanes of the leaves that changed; a
     * region too small (or four times too big) is exchanged for one of the
     * right size. grp_of[node] the group's first record / the region's
     * first block / a leaf's slot's first lane; grp_hi[node] the group's
     * slots written (those past the count are cleared on a shrink) / the
     * region's size class (| RT_DYN_REGION_FRESH: new, no slot in it
     * holds yet) / the slot's lanes. Groups and regions of freed
     * nodes wait in pend_* until the next sync clears them, then in free_*
     * (regions by class) for reuse. */
    uint32_t *grp_of;
    uint8_t *grp_hi;
    uint32_t *free_grp, free_grp_count, free_grp_cap;
#define RT_DYN_REGION_CLASSES 6 /* 1 .. 32 = 2 M blocks */
#define RT_DYN_REGION_FRESH 0x80u
#define RT_DYN_SLOT_LANE_BITS 27 /* TT_RTC_LEAF_BLOCK_BITS + 3: every lane */
#define RT_DYN_SLOT_LANE_MASK ((1u << RT_DYN_SLOT_LANE_BITS) - 1)
    uint32_t *free_reg[RT_DYN_REGION_CLASSES], free_reg_count[RT_DYN_REGION_CLASSES],
        free_reg_cap[RT_DYN_REGION_CLASSES];
    uint64_t free_reg_blocks;
    uint32_t *pend_grp, pend_grp_count, pend_grp_cap;
    uint32_t *pend_reg, pend_reg_count, pend_reg_cap; /* block | class << 26 */
    /* freed leaves' slots: lane | (lanes - 1) << RT_DYN_SLOT_LANE_BITS */
    uint32_t *pend_slot, pend_slot_count, pend_slot_cap;
    uint32_t lay_rec_cap, lay_blk_cap;   /* records / blocks allocated   */
    uint32_t lay_rec_used, lay_blk_used; /* ... in use (c.nodes, c.blocks) */
    uint32_t lay_words;
    uint32_t lay_root, lay_height;     /* the root the layout was synced with */
    int slack;                         /* the layout is the slack one    */
    /* nodes touched since the last layout sync (rt_builder.touch) */
    uint8_t *touched;
    uint32_t touched_cap;
    uint32_t *touch_list, touch_count, touch_list_cap;
    int touch_oom;
    /* per-node dirty marks of one update and the nodes marked */
    uint8_t *dirty;
    uint32_t *dirty_list, dirty_count, dirty_cap;
    /* entries orphaned by deletions: box, child, level */
    float *orphan_box;
    uint32_t *orphan_child;
    uint8_t *orphan_level;
    size_t orphan_count, orphan_cap;
    /* what the last update did, for the statistics and the bench */
    uint64_t last_refit, last_removed, last_inserted, last_moved_far, updates, repacks;
    /* compactions: full rewrites of the slack layout (the first, a change
     * of height, or free groups / regions past RT_DYN_COMPACT_FREE of it);
     * last_records / last_blocks: what the last sync wrote (blocks: a
     * leaf's slot's blocks for every leaf whose lanes it wrote) */
    uint64_t compactions, last_records, last_blocks;
    double last_tree_s, last_layout_s;
    int must_repack; /* the layout's boxes predate the tree's (first update) */
    /* the pointer tree's entry boxes and tri_box predate the last
     * deformation (which wrote the layout, and tri_box only for degenerate
     * triangles): tri_box from the lanes and a refit before use */
    int boxes_stale;
    /* the sync's lanes: a lane that holds id and whose id's stamp is at
     * most lanes_since holds its vertices already (written by an update
     * at or after the id's last change) and is not written again;
     * lanes_trust 0 (the first update, the layout from a build): every
     * lane written */
    uint64_t lanes_since;
    int lanes_trust;
    uint32_t *ids; /* an update's changed ids */
    uint32_t *lev_rec, lev_cap; /* a deformation's records by level */
    double last_cost; /* rt_compact_deform's estimate of the last deformation */
    int last_deform;  /* the last update was a pure deformation */
    size_t ids_cap;
} rt_dyn;

/* The pointer tree and the maps from the compact layout t (built on the
 * scene's geometry as of its last build or update). */
tt_status rt_dyn_from_compact(rt_dyn *d, tt_context *ctx, const tt_rtree_options *o,
                              const rtc_tree *t, const tt_scene *scene);
void rt_dyn_free(tt_context *ctx, rt_dyn *d);
size_t rt_dyn_bytes(const rt_dyn *d);

/* Pointer-tree operations (rtree_dyn_tree.c). */
tt_status rt_dyn_reserve_ids(rt_dyn *d, size_t ids);
/* The per-node arrays sized to the node pool. */
tt_status rt_dyn_node_arrays(rt_dyn *d);
/* Removes triangle id (present in the tree): condense, orphans reinserted. */
tt_status rt_dyn_delete(rt_dyn *d, uint32_t id);
/* Node n (out of the tree, no entries left in use) back on the free list;
 * its places in the layout wait for the next sync. */
void rt_dyn_free_node(rt_dyn *d, uint32_t n);
/* An edit's local rebuild (rtree_dyn_rebuild.c): the level-2 subtree
 * whose level-1 boxes spread most over its own box rebuilt below its
 * level-2 node by the SAH loader. */
tt_status rt_dyn_rebuild_worst(rt_dyn *d);
/* Inserts triangle id with box tri_box[id]. */
tt_status rt_dyn_insert(rt_dyn *d, uint32_t id);
/* Sets id's entry box in its leaf to tri_box[id], marking the leaf dirty. */
tt_status rt_dyn_set_box(rt_dyn *d, uint32_t id);
/* Recomputes the boxes of the dirty nodes and their ancestors, bottom up;
 * clears the marks. `changed` (may be NULL) collects the nodes whose box in
 * their parent was rewritten, for the compact layout. */
tt_status rt_dyn_refit(rt_dyn *d);
/* Every box recomputed from the ids' boxes (tri_box) up: the refit of a
 * deformation, one sequential pass instead of a climb per triangle. */
void rt_dyn_refit_all(rt_dyn *d);
/* The same, the root's subtrees on `threads` threads. */
void rt_dyn_refit_all_par(rt_dyn *d, int threads);

/* The compact layout from the pointer tree (rtree_dyn_compact.c): a full
 * repack with the maps, or, when the tree's shape did not change, the
 * moved triangles' lanes and the dirty nodes' boxes written in place. */
tt_status rt_dyn_repack(rt_dyn *d, tt_context *ctx, rtc_tree *t, const tt_scene *scene);
void rt_dyn_write_lane(rt_dyn *d, rtc_tree *t, const tt_scene *scene, uint32_t id);
void rt_dyn_write_box(rt_dyn *d, rtc_tree *t, uint32_t node);
/* Every node's box written into the layout (after rt_dyn_refit_all). */
void rt_dyn_write_all_boxes(rt_dyn *d, rtc_tree *t, int threads);

/* The slack layout brought up to date with the pointer tree: only the
 * touched nodes' records and their leaves' blocks are written, unless a
 * compaction is due (then all of it, fresh, depth first). */
tt_status rt_dyn_sync(rt_dyn *d, tt_context *ctx, rtc_tree *t, const tt_scene *scene);
/* The blocks level-1 node n's leaves need in its region
 * (rtree_dyn_region.c); with c, the leaves that came from another region
 * since the last sync lose their slots there (lanes cleared). Then, after
 * every touched node's need: their lanes and references written there,
 * only the leaves that changed or have no slot in it yet. A freed leaf's
 * slot (pend_slot) cleared by rt_dyn_slot_clear. */
uint32_t rt_dyn_region_need(rt_dyn *d, const tt_rtc *c, uint32_t n);
tt_status rt_dyn_region_write(rt_dyn *d, const tt_rtc *c, const tt_scene *scene, uint32_t n,
                              uint32_t *ref);
void rt_dyn_slot_clear(const tt_rtc *c, uint32_t packed);
/* Node n left the pointer tree: its group or region waits for the sync. */
void rt_dyn_release(rt_dyn *d, uint32_t n);
/* rt_builder.touch for the pointer tree of d. */
void rt_dyn_touch(void *d, uint32_t n);

/* A pure deformation (every live triangle in the tree, none added or
 * removed): boxes refit from the vertices, lanes and records written
 * straight on the compact records, level by level (rtree_dyn_deform.c);
 * the pointer tree's entry boxes are left stale (boxes_stale). Returns 0
 * (nothing done) where the general path must run: a lone leaf as root, a
 * layout still to be rewritten, or one not the slack layout. */
int rt_dyn_deform(rt_dyn *d, rtc_tree *t, const tt_scene *scene, int threads);
/* After deformations (boxes_stale): tri_box of every id in a lane that is
 * not degenerate from the lane's vertices (the deformation wrote only the
 * degenerate ones' boxes), as of the last update. */
/* A pure deformation refit straight on compact records (rt_dyn_deform's
 * walk; also a packed tree that has no pointer tree yet): every record's
 * boxes and every leaf's lanes from the scene's triangles tri; tri_box
 * (or NULL) gets the boxes of degenerate triangles; *lev_rec / *lev_cap a
 * buffer kept between calls; *cost a SAH-like estimate of the levels
 * above the leaves (the areas of level-1 and higher nodes, over the
 * root's), for the envelope rebuild's trigger. 0: not done (height 0
 * or out of memory), nothing written. */
int rt_compact_deform(tt_context *ctx, const tt_rtc *c, const float *tri, float *tri_box,
                      uint32_t **lev_rec, uint32_t *lev_cap, int threads, double *cost);

/* After a pure deformation of accel a (an R-tree in the compact layout)
 * whose rt_compact_deform estimate is `cost`: the motion envelope
 * rebuild's bookkeeping (rtree_dyn_envelope.c); when the estimate has
 * grown, the boxes of the next frames are gathered and the tree is built
 * again from their union (kept only where it is cheaper). */
void rt_env_after_deform(tt_accel *a, double cost, int threads);
void rt_dyn_boxes_from_lanes(rt_dyn *d, const rtc_tree *t);

/* Threads for an update that changes `changed` triangles: the context's
 * team from 2^17 on, else one (rtree_dyn_update.c says why). */
int rt_dyn_threads(tt_context *ctx, size_t changed);

/* A pure deformation of a tree holding `triangles` triangles since
 * `since`: no triangle added or removed (the tree holds every live one) and
 * a quarter or more of them moved. The moved count, else 0. */
size_t rt_dyn_pure_deformation(const tt_scene *scene, uint64_t since, size_t triangles);

/* The whole update: the ids stamped after `since` (tt_accel_update). */
tt_status rt_dyn_update(rt_dyn *d, tt_context *ctx, rtc_tree *t, const tt_scene *scene,
                        uint64_t since);

#endif
