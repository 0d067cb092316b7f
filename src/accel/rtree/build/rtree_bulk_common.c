/* What the bulk loaders share: the exact node pool, packing a level of
 * nodes from groups of entries, the bottom-up driver of STR and Hilbert
 * packing, and the dispatch. */
#include "accel/rtree/build/rtree_bulk.h"

#include <string.h>

#include "accel/rtree/rtree_box.h"

int rt_bulk_threads(tt_context *ctx)
{
    return tt_context_team(ctx);
}

tt_status rt_bulk_build(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                        const float *tri_box, uint32_t T)
{
    memset(b, 0, sizeof *b);
    b->ctx = ctx;
    switch (opt->build) {
    case TT_RTREE_BUILD_STR: return rt_bulk_str(b, ctx, opt, tri_box, T);
    case TT_RTREE_BUILD_HILBERT: return rt_bulk_hilbert(b, ctx, opt, tri_box, T);
    case TT_RTREE_BUILD_SAH: return rt_bulk_sah(b, ctx, opt, tri_box, T);
    default:
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "rtree: build %d is not a bulk loader",
                        (int)opt->build);
    }
}

tt_status rt_bulk_pool(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                       const float *tri_box, uint32_t T, uint32_t nodes)
{
    memset(b, 0, sizeof *b);
    b->ctx = ctx;
    b->m = opt->m;
    b->M = opt->M;
    b->cap = (opt->M + 1 + 3) & ~3; /* as the insertion builder's pool */
    b->strategy = opt->strategy;
    b->split = opt->split;
    b->tri_box = tri_box;
    b->triangles = T;
    b->hdr = tt_calloc(ctx, nodes, sizeof *b->hdr);
    /* boxes and children uninitialised: the loaders write every node's
     * entries 0 .. count - 1, and nothing reads past count (zeroing was 7%
     * of the SAH build's instructions on Sibenik: 18 MB of leaf rows) */
    b->box = tt_alloc_array(ctx, (size_t)nodes * 6, (size_t)b->cap * sizeof *b->box);
    b->child = tt_alloc_array(ctx, nodes, (size_t)b->cap * sizeof *b->child);
    if (!b->hdr || !b->box || !b->child)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (bulk node pool of %u)",
                        nodes);
    b->node_count = b->node_cap = nodes;
    b->root = nodes - 1;
    b->hdr[b->root].parent = TT_INVALID_ID;
    return TT_OK;
}

uint32_t rt_bulk_groups(uint32_t n, int M)
{
    return n == 0 ? 1 : (uint32_t)((n + (uint32_t)M - 1) / (uint32_t)M);
}

void rt_bulk_chunk(uint32_t n, int m, int M, uint32_t *start)
{
    const uint32_t g = rt_bulk_groups(n, M);
    for (uint32_t j = 0; j < g; j++) start[j] = j * (uint32_t)M;
    start[g] = n;
    if (g >= 2 && n - start[g - 1] < (uint32_t)m) {
        /* the last group would be underfull: it takes from the one before,
         * which keeps M - (m - r) >= m since M >= 2m */
        start[g - 1] = n - (uint32_t)m;
    }
}

void rt_bulk_make_level(rt_builder *b, int level, const uint32_t *items, const uint32_t *start,
                        uint32_t g, uint32_t first, int threads)
{
    const int cap = b->cap;
#pragma omp parallel for schedule(static) num_threads(threads) if (g >= RT_BULK_PARALLEL_MIN / 4)
    for (uint32_t j = 0; j < g; j++) {
        const uint32_t n = first + j;
        rt_node_hdr *h = &b->hdr[n];
        h->count = (uint8_t)(start[j + 1] - start[j]);
        h->level = (uint8_t)level;
        float *soa = rt_node_box(b, n);
        uint32_t *ch = rt_node_child(b, n);
        for (uint32_t i = start[j]; i < start[j + 1]; i++) {
            const int e = (int)(i - start[j]);
            const uint32_t c = items[i];
            float bx[6];
            if (level == 0) {
                memcpy(bx, b->tri_box + 6 * (size_t)c, sizeof bx);
            } else {
                rt_node_bounds(b, c, bx);
                b->hdr[c].parent = n;
                b->hdr[c].slot = (uint8_t)e;
            }
            rt_soa_put(soa, cap, e, bx);
            ch[e] = c;
        }
    }
}

tt_status rt_bulk_centres(tt_context *ctx, const float *tri_box, uint32_t T, float **out)
{
    /* one float of padding: the SAH loader reads a centre as 4 floats */
    float *c = tt_alloc_array(ctx, (size_t)3 * T + 1, sizeof(float));
    *out = c;
    if (!c) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (centres)");
    c[3 * (size_t)T] = 0.0f;
    for (size_t i = 0; i < T; i++)
        for (int k = 0; k < 3; k++)
            c[3 * i + k] = 0.5f * (tri_box[6 * i + k] + tri_box[6 * i + k + 3]);
    return TT_OK;
}

tt_status rt_bulk_bottom_up(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                            const float *tri_box, uint32_t T, const uint32_t *order,
                            rt_bulk_reorder_fn reorder, void *user)
{
    const int M = opt->M, m = opt->m, threads = rt_bulk_threads(ctx);
    /* nodes per level, to allocate the pool exactly */
    uint32_t g[TT_RT_BUILD_LEVELS];
    int levels = 0;
    uint64_t nodes = 0;
    for (uint32_t n = T;; levels++) {
        g[levels] = rt_bulk_groups(n, M);
        nodes += g[levels];
        if (g[levels] == 1) break;
        n = g[levels];
    }
    levels++;
    tt_status st = rt_bulk_pool(b, ctx, opt, tri_box, T, (uint32_t)nodes);
    if (st != TT_OK) return st;
    uint32_t *start = tt_alloc_array(ctx, (size_t)g[0] + 1, sizeof *start);
    uint32_t *items = tt_alloc_array(ctx, g[0], sizeof *items);
    if (!start || !items) {
        tt_free(ctx, start);
        tt_free(ctx, items);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (bulk levels)");
    }
    rt_bulk_chunk(T, m, M, start);
    rt_bulk_make_level(b, 0, order, start, g[0], 0, threads);
    uint32_t first = 0;
    for (int l = 1; l < levels && st == TT_OK; l++) {
        const uint32_t below = g[l - 1];
        for (uint32_t j = 0; j < below; j++) items[j] = first + j;
        if (reorder) st = reorder(user, b, items, below);
        if (st != TT_OK) break;
        first += below;
        rt_bulk_chunk(below, m, M, start);
        rt_bulk_make_level(b, l, items, start, g[l], first, threads);
    }
    tt_free(ctx, start);
    tt_free(ctx, items);
    return st;
}
