/* The wide BVH's binary tree: top down, each range of triangles split by
 * the surface area heuristic over WBVH_BINS centroid bins per axis (Wald
 * 2007), or made a leaf where that costs less. Costs count triangle blocks
 * (a leaf's test is ceil(n / 8) SIMD block tests, geometry/tri_block.h),
 * so a leaf of 3 triangles costs what one of 8 costs, and the builder has
 * no reason to cut leaves below a block; a split costs WBVH_COST_NODE
 * block tests plus its children's as leaves, weighed by their areas.
 *
 * Determinism: a range is binned and partitioned by one thread, in one
 * order; subranges become OpenMP tasks, which only changes the order in
 * which nodes take indices from the pool, never what a node holds, and the
 * packer walks the tree from the root. So the packed tree does not depend
 * on the number of threads. */
#include "accel/wbvh/wbvh.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#include "accel/rtree/build/rtree_bulk.h" /* rt_bulk_centres, rt_bulk_threads */
#include "accel/rtree/rtree_box.h"

#define WBVH_BINS 32
/* A range below this many triangles is built by the task that split it. */
#define WBVH_TASK_MIN 4096u
/* Past this depth a range is halved as it lies (a bound on the depth for
 * inputs where the SAH peels one triangle at a time). */
#define WBVH_DEPTH_CAP 48u
/* One binary split against one triangle-block test. Measured (1 thread,
 * CPU time, against Embree in the same run): 0.25, 0.5, 1 and 2 traced
 * Sibenik and the bunny within 2-3% of each other; 0.3 made the Cornell
 * box 20% slower. 1 keeps leaves large (about 10 triangles at M = 16) and
 * the tree shallow. */
#define WBVH_COST_NODE 1.0f

typedef struct bin {
    float box[6];
    float cen[6]; /* the centroids' bounds */
    uint32_t n;
} bin;

typedef struct builder {
    const float *tri_box, *cen;
    uint32_t *order;
    wbvh_bin_node *node;
    uint32_t next; /* pool index, taken atomically by tasks */
    uint32_t max_leaf;
    float cost_node;
} builder;

static float blocks_of(uint32_t n) { return (float)((n + TT_TRI_BLOCK_W - 1) / TT_TRI_BLOCK_W); }

static void bin_empty(bin *b)
{
    rt_box_empty(b->box);
    rt_box_empty(b->cen);
    b->n = 0;
}

static void grow_point(float b[6], const float *p)
{
    for (int k = 0; k < 3; k++) {
        b[k] = rt_min(b[k], p[k]);
        b[k + 3] = rt_max(b[k + 3], p[k]);
    }
}

/* The bin of centroid coordinate c on an axis from lo with `scale` bins a
 * unit. */
static inline uint32_t bin_of(float c, float lo, float scale)
{
    const float f = (c - lo) * scale;
    const int i = (int)f;
    return i < 0 ? 0u : i >= WBVH_BINS ? WBVH_BINS - 1u : (uint32_t)i;
}

static uint32_t take_nodes(builder *s)
{
    uint32_t i;
#pragma omp atomic capture
    {
        i = s->next;
        s->next += 2;
    }
    return i;
}

/* Boxes of order[begin, end): triangles' and centroids'. */
static void range_bounds(const builder *s, uint32_t begin, uint32_t end, float box[6],
                         float cen[6])
{
    rt_box_empty(box);
    rt_box_empty(cen);
    for (uint32_t i = begin; i < end; i++) {
        const uint32_t id = s->order[i];
        rt_box_grow(box, s->tri_box + 6 * (size_t)id);
        grow_point(cen, s->cen + 3 * (size_t)id);
    }
}

static void build_node(builder *s, uint32_t n, uint32_t begin, uint32_t end, const float box[6],
                       const float cen[6], uint32_t depth);

static void make_leaf(builder *s, uint32_t n, uint32_t begin, uint32_t end, const float box[6])
{
    wbvh_bin_node *d = &s->node[n];
    memcpy(d->box, box, sizeof d->box);
    d->a = begin;
    d->b = 0;
    d->count = end - begin;
}

/* Splits the range at `mid` (the halves already in place) into two new
 * children of node n, with their bounds. */
static void split_at(builder *s, uint32_t n, uint32_t begin, uint32_t mid, uint32_t end,
                     const float box[6], const float lb[6], const float lc[6], const float rb[6],
                     const float rc[6], uint32_t depth)
{
    wbvh_bin_node *d = &s->node[n];
    memcpy(d->box, box, sizeof d->box);
    d->count = 0;
    const uint32_t c = take_nodes(s);
    d->a = c;
    d->b = c + 1;
#pragma omp task if (mid - begin >= WBVH_TASK_MIN) default(shared) firstprivate(c, begin, mid, depth)
    {
        float b0[6], c0[6];
        memcpy(b0, lb, sizeof b0);
        memcpy(c0, lc, sizeof c0);
        build_node(s, c, begin, mid, b0, c0, depth + 1);
    }
    build_node(s, c + 1, mid, end, rb, rc, depth + 1);
#pragma omp taskwait
}

/* Where SAH cannot split (the depth cap, or every centroid in one bin):
 * one leaf when the range fits in one, else the range halved as it lies. */
static void leaf_or_halves(builder *s, uint32_t n, uint32_t begin, uint32_t end,
                           const float box[6], uint32_t depth)
{
    if (end - begin <= s->max_leaf) {
        make_leaf(s, n, begin, end, box);
        return;
    }
    const uint32_t mid = begin + (end - begin) / 2;
    float lb[6], lc[6], rb[6], rc[6];
    range_bounds(s, begin, mid, lb, lc);
    range_bounds(s, mid, end, rb, rc);
    split_at(s, n, begin, mid, end, box, lb, lc, rb, rc, depth);
}

static void build_node(builder *s, uint32_t n, uint32_t begin, uint32_t end, const float box[6],
                       const float cen[6], uint32_t depth)
{
    const uint32_t count = end - begin;
    if (count <= 2) {
        make_leaf(s, n, begin, end, box);
        return;
    }
    if (depth >= WBVH_DEPTH_CAP) {
        leaf_or_halves(s, n, begin, end, box, depth);
        return;
    }
    /* bin along every axis with extent */
    bin bins[3][WBVH_BINS];
    float scale[3];
    for (int k = 0; k < 3; k++) {
        const float ext = cen[k + 3] - cen[k];
        scale[k] = ext > 0.0f ? (float)WBVH_BINS / ext : 0.0f;
        for (int i = 0; i < WBVH_BINS; i++) bin_empty(&bins[k][i]);
    }
    for (uint32_t i = begin; i < end; i++) {
        const uint32_t id = s->order[i];
        const float *c = s->cen + 3 * (size_t)id, *tb = s->tri_box + 6 * (size_t)id;
        for (int k = 0; k < 3; k++) {
            if (scale[k] == 0.0f) continue;
            bin *b = &bins[k][bin_of(c[k], cen[k], scale[k])];
            rt_box_grow(b->box, tb);
            grow_point(b->cen, c);
            b->n++;
        }
    }
    /* the sweep: split j puts bins [0, j) left */
    const float area = rt_box_area(box);
    const float inv = area > 0.0f ? 1.0f / area : 0.0f;
    float best = count <= s->max_leaf ? blocks_of(count) : INFINITY;
    int best_axis = -1, best_j = 0;
    for (int k = 0; k < 3; k++) {
        if (scale[k] == 0.0f) continue;
        float right_cost[WBVH_BINS];
        float acc[6];
        rt_box_empty(acc);
        uint32_t nr = 0;
        for (int j = WBVH_BINS - 1; j > 0; j--) {
            rt_box_grow(acc, bins[k][j].box);
            nr += bins[k][j].n;
            right_cost[j] = nr ? rt_box_area(acc) * blocks_of(nr) : 0.0f;
        }
        rt_box_empty(acc);
        uint32_t nl = 0;
        for (int j = 1; j < WBVH_BINS; j++) {
            rt_box_grow(acc, bins[k][j - 1].box);
            nl += bins[k][j - 1].n;
            if (nl == 0 || nl == count) continue;
            const float cost =
                s->cost_node + (rt_box_area(acc) * blocks_of(nl) + right_cost[j]) * inv;
            if (cost < best) {
                best = cost;
                best_axis = k;
                best_j = j;
            }
        }
    }
    if (best_axis < 0) {
        /* no binned split (every centroid in one bin on every axis) */
        leaf_or_halves(s, n, begin, end, box, depth);
        return;
    }
    /* partition in place: bins [0, best_j) of best_axis first */
    const int k = best_axis;
    uint32_t i = begin, j = end;
    while (i < j) {
        const uint32_t id = s->order[i];
        if (bin_of(s->cen[3 * (size_t)id + k], cen[k], scale[k]) < (uint32_t)best_j) {
            i++;
        } else {
            s->order[i] = s->order[--j];
            s->order[j] = id;
        }
    }
    float lb[6], lc[6], rb[6], rc[6];
    rt_box_empty(lb);
    rt_box_empty(lc);
    rt_box_empty(rb);
    rt_box_empty(rc);
    for (int q = 0; q < WBVH_BINS; q++) {
        const bin *b = &bins[k][q];
        if (!b->n) continue;
        rt_box_grow(q < best_j ? lb : rb, b->box);
        rt_box_grow(q < best_j ? lc : rc, b->cen);
    }
    split_at(s, n, begin, i, end, box, lb, lc, rb, rc, depth);
}

void wbvh_bin_free(tt_context *ctx, wbvh_bin_tree *b)
{
    tt_free(ctx, b->node);
    tt_free(ctx, b->order);
    memset(b, 0, sizeof *b);
}

tt_status wbvh_build_binary(tt_context *ctx, const float *tri_box, uint32_t T, uint32_t max_leaf,
                            int threads, wbvh_bin_tree *out)
{
    memset(out, 0, sizeof *out);
    const size_t cap = T ? 2 * (size_t)T - 1 : 1;
    out->node = tt_alloc_array(ctx, cap, sizeof *out->node);
    out->order = tt_alloc_array(ctx, T ? T : 1, sizeof *out->order);
    float *cen = NULL;
    tt_status st = rt_bulk_centres(ctx, tri_box, T, &cen);
    if (st != TT_OK || !out->node || !out->order) {
        tt_free(ctx, cen);
        wbvh_bin_free(ctx, out);
        return st != TT_OK ? st : tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "wbvh: out of memory");
    }
    for (uint32_t i = 0; i < T; i++) out->order[i] = i;
    builder s = {tri_box, cen, out->order, out->node, 1, max_leaf, WBVH_COST_NODE};
    float box[6], cb[6];
    range_bounds(&s, 0, T, box, cb);
    if (T == 0) {
        make_leaf(&s, 0, 0, 0, box);
    } else if (T < RT_BULK_PARALLEL_MIN || threads <= 1) {
        build_node(&s, 0, 0, T, box, cb, 0);
    } else {
#pragma omp parallel num_threads(threads)
#pragma omp single
        build_node(&s, 0, 0, T, box, cb, 0);
    }
    out->nodes = s.next;
    tt_free(ctx, cen);
    return TT_OK;
}
