/* A pure deformation (rtree_dyn.h, rt_dyn_deform): every triangle moved,
 * none added or removed, so the tree keeps its shape and only boxes and
 * lanes change. It works on the compact records themselves, level by
 * level, without the pointer tree: every leaf hangs from a level-1 record
 * (an R-tree), so the level-1 records are independent of each other (each
 * owns its region of blocks in the slack layout) and are refit in
 * parallel straight from their leaves' lanes, which name their triangles;
 * then each level above from the boxes of its children's records. The
 * pointer walk it replaces spent most of its instructions on the walk
 * itself (headers, child arrays, a call per leaf) rather than on the
 * triangles, and shared its work out only by the root's few subtrees. */
#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/update/rtree_dyn.h"

/* The leaf of lanes [g0, g0 + cnt): each lane's triangle (its id in the
 * lane) read from the scene into the lane (NaN when degenerate, as
 * rtc_pack writes it); *out their union. A triangle's own box goes into
 * tri_box only when it is degenerate: the others' are in their lanes and
 * rt_dyn_boxes_from_lanes takes them from there when an update needs them
 * (a run of deformations never does; the stores were a tenth of the
 * walk's instructions and a megabyte and a half of writes a frame on the
 * bunny). */
static inline void deform_leaf(float *tri_box, tt_tri_block *blk, const float *tri, uint64_t g0,
                               uint32_t cnt, float out[6])
{
#if defined(__SSE2__)
    __m128 lo = _mm_set1_ps(TT_INF), hi = _mm_set1_ps(-TT_INF);
#else
    float lo[3] = {TT_INF, TT_INF, TT_INF}, hi[3] = {-TT_INF, -TT_INF, -TT_INF};
#endif
    for (uint64_t g = g0; g < g0 + cnt; g++) {
        tt_tri_block *bk = blk + g / TT_TRI_BLOCK_W;
        const uint32_t l = (uint32_t)(g % TT_TRI_BLOCK_W), id = bk->prim[l];
        const float *v = tri + 9 * (size_t)id;
#if defined(__SSE2__)
        /* a corner a vector load (the third one ending at the triangle's
         * last float, shifted down): the same min / max per coordinate;
         * lane 3 is unused. Loaded straight from the scene: a copy into a
         * padded buffer first cost a store-to-load forwarding stall a
         * triangle */
        const __m128 p0 = _mm_loadu_ps(v), p1 = _mm_loadu_ps(v + 3), p2r = _mm_loadu_ps(v + 5);
        const __m128 p2 = _mm_shuffle_ps(p2r, p2r, _MM_SHUFFLE(3, 3, 2, 1));
        const __m128 mn = _mm_min_ps(_mm_min_ps(p0, p1), p2);
        const __m128 mx = _mm_max_ps(_mm_max_ps(p0, p1), p2);
        lo = _mm_min_ps(lo, mn);
        hi = _mm_max_ps(hi, mx);
        /* tt_tri_is_degenerate's three products, a lane each (the same
         * float operations in the same order, so the same answer): the
         * scalar test was a third of the walk's instructions */
        const __m128 e1 = _mm_sub_ps(p1, p0), e2 = _mm_sub_ps(p2, p0);
        const __m128 e1a = _mm_shuffle_ps(e1, e1, _MM_SHUFFLE(3, 0, 2, 1)); /* y z x */
        const __m128 e2b = _mm_shuffle_ps(e2, e2, _MM_SHUFFLE(3, 1, 0, 2)); /* z x y */
        const __m128 e1c = _mm_shuffle_ps(e1, e1, _MM_SHUFFLE(3, 1, 0, 2)); /* z x y */
        const __m128 e2d = _mm_shuffle_ps(e2, e2, _MM_SHUFFLE(3, 0, 2, 1)); /* y z x */
        const __m128 n = _mm_sub_ps(_mm_mul_ps(e1a, e2b), _mm_mul_ps(e1c, e2d));
        const int dead = (_mm_movemask_ps(_mm_cmpeq_ps(n, _mm_setzero_ps())) & 7) == 7;
#else
        for (int k = 0; k < 3; k++) {
            lo[k] = rt_min(lo[k], rt_min(rt_min(v[k], v[3 + k]), v[6 + k]));
            hi[k] = rt_max(hi[k], rt_max(rt_max(v[k], v[3 + k]), v[6 + k]));
        }
#endif
#if !defined(__SSE2__)
        const int dead = tt_tri_is_degenerate(v, v + 3, v + 6);
#endif
        if (dead) { /* rare: its box again, scalar (no tri_box: none kept) */
            float *bx = tri_box ? tri_box + 6 * (size_t)id : NULL;
            for (int k = 0; k < 3 && bx; k++) {
                bx[k] = rt_min(rt_min(v[k], v[3 + k]), v[6 + k]);
                bx[k + 3] = rt_max(rt_max(v[k], v[3 + k]), v[6 + k]);
            }
            for (int q = 0; q < 9; q++) bk->v[q][l] = NAN;
        } else {
            for (int q = 0; q < 9; q++) bk->v[q][l] = v[q];
        }
    }
#if defined(__SSE2__)
    float o[8];
    _mm_storeu_ps(o, lo);
    _mm_storeu_ps(o + 4, hi);
    memcpy(out, o, 3 * sizeof(float));
    memcpy(out + 3, o + 4, 3 * sizeof(float));
#else
    memcpy(out, lo, sizeof lo);
    memcpy(out + 3, hi, sizeof hi);
#endif
}

/* Level-1 record r: its leaves refit, their boxes into its rows. */
static void deform_record(float *tri_box, const tt_rtc *c, const float *tri, uint32_t r)
{
    float *rec = (float *)tt_rtc_node(c, r);
    const uint32_t *ref = tt_rtc_child(c, rec);
    const uint32_t cnt = tt_rtc_count(c, rec), S = c->S;
    tt_tri_block *blk = (tt_tri_block *)c->block;
    for (uint32_t i = 0; i < cnt; i++) {
        float cb[6];
        const uint64_t g0 =
            (uint64_t)tt_rtc_leaf_block(ref[i]) * TT_TRI_BLOCK_W + tt_rtc_leaf_lane(ref[i]);
        deform_leaf(tri_box, blk, tri, g0, tt_rtc_leaf_count(ref[i]), cb);
        for (uint32_t k = 0; k < 6; k++) rec[k * S + i] = cb[k];
    }
}

/* Record r above level 1: entry i's box the union of child record i's
 * entries (a record's slots past its count already hold the free mark,
 * and the count does not change here); returns the entries' areas (the
 * cost estimate's part: a leaves' term cost ~0.5 M instructions a bunny
 * frame, a tenth of the walk, and the upper levels drift with them). */
static double refit_record(const tt_rtc *c, uint32_t r)
{
    float *rec = (float *)tt_rtc_node(c, r);
    const uint32_t *ref = tt_rtc_child(c, rec);
    const uint32_t cnt = tt_rtc_count(c, rec), S = c->S;
    double cost = 0.0;
    for (uint32_t i = 0; i < cnt; i++) {
        const float *cr = tt_rtc_node(c, ref[i]);
        const uint32_t cc = tt_rtc_count(c, cr);
        float eb[6];
        for (uint32_t k = 0; k < 3; k++) {
            const float *rl = cr + k * S, *rh = cr + (k + 3) * S;
            float lo = TT_INF, hi = -TT_INF;
            for (uint32_t j = 0; j < cc; j++) {
                lo = rt_min(lo, rl[j]);
                hi = rt_max(hi, rh[j]);
            }
            rec[k * S + i] = lo;
            rec[(k + 3) * S + i] = hi;
            eb[k] = lo;
            eb[k + 3] = hi;
        }
        cost += (double)rt_box_area(eb);
    }
    return cost;
}

int rt_compact_deform(tt_context *ctx, const tt_rtc *c, const float *tri, float *tri_box,
                      uint32_t **lev_rec, uint32_t *lev_cap, int threads, double *cost)
{
    const uint32_t nodes = c->nodes, height = c->height;
    if (height == 0 || height > 255) return 0;
    /* the used records by level (free ones have level 0): counting sort */
    if (nodes > *lev_cap) {
        uint32_t *l = tt_realloc_array(ctx, *lev_rec, nodes, sizeof *l);
        if (!l) return 0; /* the general path needs no buffer */
        *lev_rec = l;
        *lev_cap = nodes;
    }
    uint32_t start[257] = {0};
    for (uint32_t r = 0; r < nodes; r++) start[tt_rtc_level(c, tt_rtc_node(c, r)) + 1]++;
    for (uint32_t k = 1; k <= 256; k++) start[k] += start[k - 1];
    uint32_t fill[256];
    memcpy(fill, start, sizeof fill);
    for (uint32_t r = 0; r < nodes; r++) {
        const uint32_t lv = tt_rtc_level(c, tt_rtc_node(c, r));
        if (lv) (*lev_rec)[fill[lv]++] = r;
    }
    const uint32_t *lev = *lev_rec;
    const long n1 = (long)(start[2] - start[1]);
    double sum = 0.0;
    /* level 1: the leaves, on the threads (regions are disjoint; in the
     * packer's layout two records may share a block, but never a lane) */
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (long k = 0; k < n1; k++) deform_record(tri_box, c, tri, lev[start[1] + (uint32_t)k]);
    /* above: few records (a sixteenth per level), one thread */
    for (uint32_t lv = 2; lv <= height; lv++)
        for (uint32_t k = start[lv]; k < start[lv + 1]; k++) sum += refit_record(c, lev[k]);
    /* the estimate relative to the root record's box (its entries' union) */
    const float *root = tt_rtc_node(c, lev[start[height]]);
    float rb[6] = {TT_INF, TT_INF, TT_INF, -TT_INF, -TT_INF, -TT_INF};
    for (uint32_t i = 0; i < tt_rtc_count(c, root); i++)
        for (uint32_t k = 0; k < 3; k++) {
            rb[k] = rt_min(rb[k], root[k * c->S + i]);
            rb[k + 3] = rt_max(rb[k + 3], root[(k + 3) * c->S + i]);
        }
    const double ra = (double)rt_box_area(rb);
    *cost = ra > 0.0 ? sum / ra : 0.0;
    return 1;
}

int rt_dyn_deform(rt_dyn *d, rtc_tree *t, const tt_scene *scene, int threads)
{
    rt_builder *b = &d->b;
    /* the general path: a lone leaf as root, a layout still to be written,
     * or the packer's layout (whose level-1 nodes may share blocks) */
    if (b->hdr[b->root].level == 0 || d->must_repack || !d->slack) return 0;
    if (!rt_compact_deform(b->ctx, &t->c, scene->tri, d->tri_box, &d->lev_rec, &d->lev_cap,
                           threads, &d->last_cost))
        return 0;
    d->boxes_stale = 1;
    return 1;
}

void rt_dyn_boxes_from_lanes(rt_dyn *d, const rtc_tree *t)
{
    const tt_rtc *c = &t->c;
    for (uint32_t j = 0; j < c->blocks; j++) {
        const tt_tri_block *bk = &c->block[j];
        for (uint32_t l = 0; l < TT_TRI_BLOCK_W; l++) {
            const uint32_t id = bk->prim[l];
            /* no triangle, or a degenerate one (its box is in tri_box) */
            if (id == TT_INVALID_ID || id >= d->id_cap || isnan(bk->v[0][l])) continue;
            float *bx = d->tri_box + 6 * (size_t)id;
            for (int k = 0; k < 3; k++) {
                bx[k] = rt_min(rt_min(bk->v[k][l], bk->v[3 + k][l]), bk->v[6 + k][l]);
                bx[k + 3] = rt_max(rt_max(bk->v[k][l], bk->v[3 + k][l]), bk->v[6 + k][l]);
            }
        }
    }
}
