/* STR, Sort-Tile-Recursive (Leutenegger, Lopez & Edgington 1997), in 3D: the
 * P = ceil(n / M) nodes of a level are laid out as an S x S x S grid of
 * tiles, S = ceil(P^(1/3)): the entries are sorted by x and cut into slabs
 * of S^2 M entries, each slab sorted by y and cut into runs of S M, each
 * run sorted by z and packed M at a time. Slabs and runs hold whole nodes,
 * so only the level's last node can come out short; rt_bulk_chunk evens it
 * with the one before. The level above is tiled the same way from the
 * centres of the nodes' boxes. */
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_bulk.h"

typedef struct str_scratch {
    uint64_t *key, *tk;
    uint32_t *val, *tv;
    float *cen; /* level > 0: centres of the level's nodes */
    int M, threads;
} str_scratch;

/* Sorts val[lo .. hi) by centre coordinate `axis` (cen is indexed by the
 * values, 3 floats each). Single-threaded: segments run in parallel. */
static void sort_segment(str_scratch *s, const float *cen, size_t lo, size_t hi, int axis)
{
    for (size_t i = lo; i < hi; i++) s->key[i] = rt_float_key(cen[3 * (size_t)s->val[i] + axis]);
    /* one thread allocates nothing: cannot fail */
    (void)rt_radix_sort(NULL, s->key + lo, s->val + lo, s->tk + lo, s->tv + lo, hi - lo, 32, 1);
}

/* Puts val[0 .. n) (indices into cen) in STR order. */
static tt_status str_order(tt_context *ctx, str_scratch *s, const float *cen, uint32_t n)
{
    const uint64_t M = (uint64_t)s->M, P = (n + M - 1) / M;
    uint64_t S = 1;
    while (S * S * S < P) S++;
    const uint64_t slab = S * S * M, run = S * M;
    for (uint32_t i = 0; i < n; i++) {
        s->val[i] = i;
        s->key[i] = rt_float_key(cen[3 * (size_t)i]);
    }
    tt_status st = rt_radix_sort(ctx, s->key, s->val, s->tk, s->tv, n, 32, s->threads);
    if (st != TT_OK) return st;
    const long slabs = (long)((n + slab - 1) / slab);
#pragma omp parallel for schedule(dynamic, 1) num_threads(s->threads) if (slabs > 1 && n >= RT_BULK_PARALLEL_MIN)
    for (long k = 0; k < slabs; k++) {
        const size_t lo = (size_t)k * slab, hi = lo + slab < n ? lo + slab : n;
        sort_segment(s, cen, lo, hi, 1);
        for (size_t r = lo; r < hi; r += run) sort_segment(s, cen, r, r + run < hi ? r + run : hi, 2);
    }
    return TT_OK;
}

/* The level above the leaves and up: tile the nodes by their boxes' centres. */
static tt_status reorder_nodes(void *user, rt_builder *b, uint32_t *nodes, uint32_t n)
{
    str_scratch *s = user;
    for (uint32_t i = 0; i < n; i++) {
        float bx[6];
        rt_node_bounds(b, nodes[i], bx);
        for (int k = 0; k < 3; k++) s->cen[3 * (size_t)i + k] = 0.5f * (bx[k] + bx[k + 3]);
    }
    tt_status st = str_order(b->ctx, s, s->cen, n);
    if (st != TT_OK) return st;
    /* nodes[] are consecutive ids: rewrite them in the order found */
    const uint32_t first = nodes[0];
    for (uint32_t i = 0; i < n; i++) nodes[i] = first + s->val[i];
    return TT_OK;
}

tt_status rt_bulk_str(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                      const float *tri_box, uint32_t T)
{
    str_scratch s;
    memset(&s, 0, sizeof s);
    s.M = opt->M;
    s.threads = rt_bulk_threads(ctx);
    const size_t n = T ? T : 1;
    float *tri_cen = NULL;
    tt_status st = rt_bulk_centres(ctx, tri_box, T, &tri_cen);
    s.key = tt_alloc_array(ctx, n, sizeof *s.key);
    s.tk = tt_alloc_array(ctx, n, sizeof *s.tk);
    s.val = tt_alloc_array(ctx, n, sizeof *s.val);
    s.tv = tt_alloc_array(ctx, n, sizeof *s.tv);
    s.cen = tt_alloc_array(ctx, (size_t)rt_bulk_groups(T, opt->M), 3 * sizeof *s.cen);
    uint32_t *order = tt_alloc_array(ctx, n, sizeof *order);
    if (st == TT_OK && (!s.key || !s.tk || !s.val || !s.tv || !s.cen || !order))
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (STR, %u triangles)", T);
    if (st == TT_OK) st = str_order(ctx, &s, tri_cen, T);
    if (st == TT_OK) {
        memcpy(order, s.val, (size_t)T * sizeof *order);
        st = rt_bulk_bottom_up(b, ctx, opt, tri_box, T, order, reorder_nodes, &s);
    }
    tt_free(ctx, tri_cen);
    tt_free(ctx, s.key);
    tt_free(ctx, s.tk);
    tt_free(ctx, s.val);
    tt_free(ctx, s.tv);
    tt_free(ctx, s.cen);
    tt_free(ctx, order);
    return st;
}
