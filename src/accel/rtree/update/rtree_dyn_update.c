/* One tt_accel_update of the R-tree (rtree_dyn.h): the ids the scene
 * stamped after `since`, classified against what the tree holds:
 *  - live and in the tree (moved): refit where it is, unless, in an update
 *    that moves few triangles, it jumped (its box's centre moved more than
 *    twice the sizes of its old and new boxes) or would grow its leaf's
 *    surface by more than a quarter, or its id was reused by an addition (a
 *    new triangle): then it is deleted and inserted again. When a quarter
 *    or more of the live triangles moved
 *    (a deformation) all are refit: neighbours move together there, and
 *    the refit keeps the tree's shape;
 *  - removed and in the tree: deleted (Guttman's condense step);
 *  - live and not in the tree (added, or a removed id reused): inserted
 *    (R* choices, splits, forced reinsert).
 * Order: refits first and the boxes brought up (so every box is exact),
 * then deletions, then insertions. The compact layout: when nothing was
 * deleted or inserted, the moved lanes and the boxes that changed are
 * written in place; otherwise the records and blocks of the nodes the
 * update touched are rewritten in the slack layout (rt_dyn_sync). */
#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/update/rtree_dyn.h"

static float diag2(const float b[6])
{
    float s = 0.0f;
    for (int k = 0; k < 3; k++) s += (b[k + 3] - b[k]) * (b[k + 3] - b[k]);
    return s;
}

/* The centre moved by more than twice the two boxes' diagonals. */
static int jumped(const float old[6], const float now[6])
{
    float m = 0.0f;
    for (int k = 0; k < 3; k++) {
        const float o = (now[k] + now[k + 3]) - (old[k] + old[k + 3]);
        m += o * o;
    }
    const float reach = 2.0f * (sqrtf(diag2(old)) + sqrtf(diag2(now)));
    return 0.25f * m > reach * reach;
}

/* Threads only for big frames: on the shared 2-core box a 69k-triangle
 * refit ran 2-3x slower in wall time on 2 threads than on 1 (fork/join
 * under load); 2^17 changed triangles keep the threads busy enough. */
int rt_dyn_threads(tt_context *ctx, size_t changed)
{
    if (changed < ((size_t)1 << 17)) return 1;
    return tt_context_team(ctx);
}

size_t rt_dyn_pure_deformation(const tt_scene *scene, uint64_t since, size_t triangles)
{
    const size_t T = scene->triangle_count, live = tt_scene_live_triangle_count(scene);
    if (!scene->flags || !scene->stamp || scene->structural > since || triangles != live) return 0;
    size_t moved = 0;
    for (size_t id = 0; id < T; id++) moved += scene->stamp[id] > since;
    return moved > 0 && moved * 4 >= live ? moved : 0;
}

/* Whether any of the 16 stamps at s is above since: since - stamp has
 * its top bit set there (versions count edit calls, far below 2^63). */
static int stamps_above(const uint64_t *s, uint64_t since)
{
#if defined(__SSE2__)
    const __m128i v = _mm_set1_epi64x((long long)since);
    __m128i acc = _mm_setzero_si128();
    for (int j = 0; j < 16; j += 2)
        acc = _mm_or_si128(acc, _mm_sub_epi64(v, _mm_loadu_si128((const __m128i *)(s + j))));
    return _mm_movemask_pd(_mm_castsi128_pd(acc)) != 0;
#else
    uint64_t any = 0;
    for (int j = 0; j < 16; j++) any |= since - s[j];
    return (int)(any >> 63);
#endif
}

/* The record of an update answered by rt_dyn_deform alone (moves only). */
static void deformed(rt_dyn *d, size_t moved, double t0)
{
    d->last_refit = moved;
    d->last_removed = d->last_inserted = d->last_moved_far = 0;
    d->last_tree_s = tt_now() - t0;
    d->last_layout_s = 0.0;
    d->last_deform = 1;
    d->updates++;
}

tt_status rt_dyn_update(rt_dyn *d, tt_context *ctx, rtc_tree *t, const tt_scene *scene,
                        uint64_t since)
{
    const size_t T = scene->triangle_count;
    /* deletions leave leaves of one triangle (rt_dyn_delete): the check's
     * fill minimum follows */
    t->m = 1;
    d->last_deform = 0;
    double t0 = tt_now();
    tt_status st = rt_dyn_reserve_ids(d, T ? T : 1);
    if (st != TT_OK) return st;
    /* the changed ids, in one pass (into d's buffer, kept between updates:
     * a deformation lists every id) */
    size_t changed = 0, moved = 0;
    /* a tree packed after removals holds the removed slots (as points):
     * the first update takes them out as if just removed */
    const int sweep = d->must_repack;
    if (T > d->ids_cap) {
        uint32_t *buf = tt_realloc_array(ctx, d->ids, T, sizeof *buf);
        if (!buf) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
        d->ids = buf;
        d->ids_cap = T;
    }
    uint32_t *ids = d->ids;
    const uint64_t *stamp = scene->stamp;
    const uint8_t *flags = scene->flags;
    const uint32_t *leaf_of = d->leaf_of;
    /* no triangle added or removed since the last update: every changed id
     * is live and in the tree, and a deformation (a quarter or more of
     * them moved) needs only their count, not the list (the list was a
     * sixth of a conference deformation's instructions) */
    const size_t live = tt_scene_live_triangle_count(scene);
    const size_t pure = sweep ? 0 : rt_dyn_pure_deformation(scene, since, d->b.triangles);
    if (pure && rt_dyn_deform(d, t, scene, rt_dyn_threads(ctx, pure))) {
        deformed(d, pure, t0);
        return TT_OK;
    }
    if (!sweep && flags) { /* every frame after the first: the tight loop */
        /* sixteen stamps at a time first (stamps_above): the branch per
         * id cost ~10 instructions an id (5% of a bunny edits frame) */
        size_t id = 0;
        for (; id < T; id += 16) {
            const size_t e = T - id < 16 ? T - id : 16;
            if (e == 16 && !stamps_above(stamp + id, since)) continue;
            for (size_t j = id; j < id + e; j++) {
                if (stamp[j] <= since) continue;
                ids[changed++] = (uint32_t)j;
                moved += ((flags[j] & TT_TRI_DEAD) == 0) & (leaf_of[j] != TT_INVALID_ID);
            }
        }
    }
    for (size_t id = 0; id < T && (sweep || !flags); id++) {
        if (scene->stamp[id] <= since &&
            !(sweep && d->leaf_of[id] != TT_INVALID_ID && tt_scene_is_dead(scene, id)))
            continue;
        ids[changed++] = (uint32_t)id;
        moved += !tt_scene_is_dead(scene, id) && d->leaf_of[id] != TT_INVALID_ID;
    }
    const int deform = moved * 4 >= live && moved > 0;
    size_t removed = 0, inserted = 0, far = 0, refit = 0;
    /* a pure deformation (only moves): one walk refits and writes it all */
    if (deform && moved == changed && rt_dyn_deform(d, t, scene, rt_dyn_threads(ctx, changed))) {
        deformed(d, moved, t0);
        return TT_OK;
    }

    /* the pointer tree's boxes after deformations: tri_box from the lanes
     * and the boxes from tri_box (as of the last update), before anything
     * reads or grows them */
    if (d->boxes_stale) {
        rt_dyn_boxes_from_lanes(d, t);
        rt_dyn_refit_all(d);
        d->boxes_stale = 0;
    }
    /* 1. refits: new boxes into the leaves, marked for the climb */
    uint8_t *again = tt_calloc(ctx, changed ? changed : 1, 1); /* delete + insert */
    if (!again) st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree update: out of memory");
    const int threads = rt_dyn_threads(ctx, changed);
    if (deform) { /* every moved id refits: its new box, on the threads */
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : refit)
        for (size_t i = 0; i < changed; i++) {
            const uint32_t id = ids[i];
            if (tt_scene_is_dead(scene, id) || d->leaf_of[id] == TT_INVALID_ID) continue;
            rt_box_of_triangle(scene->tri + 9 * (size_t)id, d->tri_box + 6 * (size_t)id);
            refit++;
        }
    }
    for (size_t i = 0; i < changed && st == TT_OK && !deform; i++) {
        const uint32_t id = ids[i];
        if (tt_scene_is_dead(scene, id) || d->leaf_of[id] == TT_INVALID_ID) continue;
        /* an id reused by an addition is a new triangle (an edits frame's
         * additions reuse its removals' ids: decided before any box is
         * computed); a moved one that would grow its leaf's surface by
         * more than a quarter (or jumped away) is better placed again than
         * refit where it was */
        const int reborn = scene->born[id] > since;
        float nb[6], lb[6], grown[6];
        if (!reborn) {
            rt_box_of_triangle(scene->tri + 9 * (size_t)id, nb);
            rt_node_bounds(&d->b, d->leaf_of[id], lb);
            memcpy(grown, lb, sizeof grown);
            rt_box_grow(grown, nb);
        }
        if (reborn || rt_box_area(grown) > 1.25f * rt_box_area(lb) ||
            jumped(d->tri_box + 6 * (size_t)id, nb)) {
            again[i] = 1;
            far++;
            continue;
        }
        memcpy(d->tri_box + 6 * (size_t)id, nb, sizeof nb);
        st = rt_dyn_set_box(d, id);
        refit++;
    }
    /* a deformation refits the whole tree in one pass; a few moves climb
     * from their leaves */
    if (st == TT_OK && deform) rt_dyn_refit_all_par(d, threads);
    else if (st == TT_OK) st = rt_dyn_refit(d);
    /* 2. deletions: removed ids and jumped ones */
    for (size_t i = 0; i < changed && st == TT_OK; i++) {
        const uint32_t id = ids[i];
        if (d->leaf_of[id] == TT_INVALID_ID) continue;
        if (!tt_scene_is_dead(scene, id) && !again[i]) continue;
        st = rt_dyn_delete(d, id);
        removed++;
    }
    /* 3. insertions: new ids, reused ids, jumped ones. By the SAH
     * (rt_builder.sah_leaves) in an edit (some removed, few changed
     * against the tree); a tree grown from nothing by whole objects (the
     * bench's growth, additions only) took its new leaves and split charge
     * badly (bunny SAH 3.5x -> 39x a fresh build's; with only the "few"
     * test 12.9x), so it keeps the least-surface choice */
    d->b.sah_leaves = removed > 0 && (changed - moved) * 8 <= live;
    for (size_t i = 0; i < changed && st == TT_OK; i++) {
        const uint32_t id = ids[i];
        if (tt_scene_is_dead(scene, id) || d->leaf_of[id] != TT_INVALID_ID) continue;
        rt_box_of_triangle(scene->tri + 9 * (size_t)id, d->tri_box + 6 * (size_t)id);
        st = rt_dyn_insert(d, id);
        inserted++;
    }
    /* 4. every second edit, the most spread level-2 subtree rebuilt by the
     * SAH loader (rtree_dyn_rebuild.c). Bunny, 100 frames of 1% edits, two
     * trees in one process, thread CPU: shadow rays 0.86-0.88x, primary
     * 0.92-0.96x of the tree without it, update 1.04-1.05x; every edit:
     * the same trace for 1.10x; four a frame or the levels above rebuilt
     * too: no better trace for more */
    if (st == TT_OK && d->b.sah_leaves && (d->updates & 1u) == 0) st = rt_dyn_rebuild_worst(d);
    double t1 = tt_now();
    /* 5. the compact layout */
    if (st == TT_OK && removed == 0 && inserted == 0 && !d->must_repack) {
#pragma omp parallel for schedule(static) num_threads(threads)
        for (size_t i = 0; i < changed; i++)
            if (d->leaf_of[ids[i]] != TT_INVALID_ID) rt_dyn_write_lane(d, t, scene, ids[i]);
        if (deform) rt_dyn_write_all_boxes(d, t, threads);
        else
            for (uint32_t j = 0; j < d->dirty_count; j++) rt_dyn_write_box(d, t, d->dirty_list[j]);
    } else if (st == TT_OK) {
        /* the touched nodes' records and blocks rewritten in the slack
         * layout (a compaction now and then: rt_dyn_sync) */
        d->lanes_since = since;
        d->lanes_trust = !d->must_repack && scene->stamp != NULL;
        st = rt_dyn_sync(d, ctx, t, scene);
        if (st == TT_OK) d->must_repack = 0;
    }
    for (uint32_t j = 0; j < d->dirty_count; j++) d->dirty[d->dirty_list[j]] = 0;
    d->dirty_count = 0;
    tt_free(ctx, again);
    d->last_refit = refit;
    d->last_removed = removed;
    d->last_inserted = inserted;
    d->last_moved_far = far;
    d->last_tree_s = t1 - t0;
    d->last_layout_s = tt_now() - t1;
    d->updates++;
    return st;
}
