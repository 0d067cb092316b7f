/* The motion envelope rebuild of a deforming R-tree (rtree_dyn.h,
 * rt_env_after_deform), called by the vtable's update after each pure
 * deformation, whether refit on the compact records alone or through the
 * pointer tree. */
#include <string.h>

#include "accel/rtree/rtree.h"
#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_bulk.h"
#include "accel/rtree/update/rtree_dyn.h"

/* The motion envelope rebuild. A deformation refits the tree it has, so
 * its grouping stays the one of the frame it was built for; a motion that
 * grows (bench D's wave: amplitude up with the frame, a phase that moves
 * 0.7 rad a frame) leaves it ever worse (bunny: SAH 1.19x a fresh
 * build's after 100 frames). A tree built from any one frame is no cure:
 * the wave's phase moves on and two frames later it is as bad (built at
 * frame 98: 1.18x at frame 100; at 95: 1.31x). Built from each
 * triangle's box over the last ENV_FRAMES frames (their union), the
 * grouping fits the motion rather than one pose: built at frame 70, 80,
 * 90 or 95 it stays at 1.03-1.11x through frame 100. So: when the
 * refit's cost estimate has grown ENV_TRIGGER over the estimate after the
 * last build, the boxes of the next ENV_FRAMES deformations are gathered,
 * and the tree is then built again from them by the SAH loader and refit
 * to the frame, and kept if its whole cost (tree_cost, leaves included)
 * is ENV_KEEP of the old tree's or less; at most once in ENV_GAP
 * deformations (doubled by each rebuild not kept). */
#define ENV_FRAMES 8u
#define ENV_TRIGGER 1.15
#define ENV_GAP 24u
#define ENV_KEEP 0.97 /* a rebuilt tree kept only with its cost 3% under the old's */

static void env_gather(float *env, const float *tri, size_t T, int first)
{
    for (size_t i = 0; i < T; i++) {
        float b[6];
        rt_box_of_triangle(tri + 9 * i, b);
        if (first) memcpy(env + 6 * i, b, sizeof b);
        else rt_box_grow(env + 6 * i, b);
    }
}

/* A SAH-like cost of compact tree c (as it stands): every used record's
 * entries' box areas, a leaf's times (its count + 1). */
static double tree_cost(const tt_rtc *c)
{
    double sum = 0.0;
    for (uint32_t r = 0; r < c->nodes; r++) {
        const float *rec = tt_rtc_node(c, r);
        const uint32_t lv = tt_rtc_level(c, rec);
        if (!lv) continue; /* free */
        const uint32_t *ref = tt_rtc_child(c, rec);
        for (uint32_t i = 0; i < tt_rtc_count(c, rec); i++) {
            float b[6];
            for (uint32_t k = 0; k < 6; k++) b[k] = rec[k * c->S + i];
            const double w = lv == 1 ? (double)tt_rtc_leaf_count(ref[i]) + 1.0 : 1.0;
            sum += w * (double)rt_box_area(b);
        }
    }
    return sum;
}

/* The tree built again from the boxes env (the SAH loader into the
 * compact layout), refit to the scene's triangles; the pointer tree is
 * dropped (the next edit makes it again from the records). On failure
 * the old tree stays. */
static tt_status env_rebuild(tt_accel *a, const float *env, int threads)
{
    rt_tree *t = a->impl;
    const tt_rtree_options *o = &a->options.rtree;
    const tt_scene *scene = a->scene;
    const uint32_t T = (uint32_t)scene->triangle_count;
    rt_bulk_levels lv;
    memset(&lv, 0, sizeof lv);
    rtc_tree nc;
    memset(&nc, 0, sizeof nc);
    tt_status st = rt_bulk_sah_levels(&lv, a->ctx, o, env, T);
    if (st == TT_OK) st = rtc_pack_levels(a->ctx, &lv, scene->tri, &nc);
    rt_bulk_levels_free(a->ctx, &lv);
    double cost = 0.0;
    if (st == TT_OK && !rt_compact_deform(a->ctx, &nc.c, scene->tri, NULL, &t->lev_rec,
                                          &t->lev_cap, threads, &cost))
        st = TT_ERR_OUT_OF_MEMORY;
    /* no better than the refit tree on this frame (the conference under
     * bench D's wave: its triangles' own growth is the refit's; rebuilt
     * every 31 frames for SAH 1.02x instead of 1.00x): kept out, and the
     * next try waits twice as long */
    if (st == TT_OK && tree_cost(&nc.c) > ENV_KEEP * tree_cost(&t->compact.c)) {
        t->env_gap = t->env_gap < 4096u ? 2u * t->env_gap : t->env_gap;
        st = TT_ERR_UNSUPPORTED;
    }
    if (st != TT_OK) {
        rtc_free(a->ctx, &nc);
        return st;
    }
    nc.m = t->compact.m;
    rtc_free(a->ctx, &t->compact);
    t->compact = nc;
    rtc_select(&t->compact, (int)o->traversal, a->isa);
    if (t->dyn) {
        rt_dyn_free(a->ctx, t->dyn);
        tt_free(a->ctx, t->dyn);
        t->dyn = NULL;
    }
    t->cost_base = cost;
    return TT_OK;
}

/* After a pure deformation whose cost estimate is `cost`: the envelope
 * rebuild's bookkeeping (above). */
void rt_env_after_deform(tt_accel *a, double cost, int threads)
{
    rt_tree *t = a->impl;
    const tt_rtree_options *o = &a->options.rtree;
    const size_t T = a->scene->triangle_count;
    t->since_build++;
    if (o->build != TT_RTREE_BUILD_SAH || T <= (size_t)o->M) return;
    if (t->cost_base <= 0.0) {
        t->cost_base = cost;
        return;
    }
    if (!t->env) {
        if (!t->env_gap) t->env_gap = ENV_GAP;
        if (t->since_build < t->env_gap || cost <= ENV_TRIGGER * t->cost_base) return;
        t->env = tt_alloc_array(a->ctx, T, 6 * sizeof(float));
        if (!t->env) return; /* only quality is lost */
        env_gather(t->env, a->scene->tri, T, 1);
        t->env_left = ENV_FRAMES - 1;
        return;
    }
    env_gather(t->env, a->scene->tri, T, 0);
    if (--t->env_left > 0) return;
    t->since_build = 0; /* rebuilt, or the refit kept and the gap doubled */
    (void)env_rebuild(a, t->env, threads);
    tt_free(a->ctx, t->env);
    t->env = NULL;
}
