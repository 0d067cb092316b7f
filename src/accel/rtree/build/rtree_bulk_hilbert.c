/* Hilbert-sorted packing (Kamel & Faloutsos 1993), in 3D: the triangles'
 * box centres are quantised to a 2^21-cell grid per axis over the box of
 * all centres, sorted by their index along the 3D Hilbert curve (63-bit
 * keys, radix sort), and packed M at a time; every level above packs runs
 * of M consecutive nodes of the level below, which are in curve order
 * already. */
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_bulk.h"

#define HILBERT_BITS 21

/* The low 21 bits of x spread out to every third bit. */
static inline uint64_t spread3(uint32_t x)
{
    uint64_t v = x & 0x1FFFFFu;
    v = (v | v << 32) & 0x001F00000000FFFFull;
    v = (v | v << 16) & 0x001F0000FF0000FFull;
    v = (v | v << 8) & 0x100F00F00F00F00Full;
    v = (v | v << 4) & 0x10C30C30C30C30C3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

/* Skilling's construction ("Programming the Hilbert curve", 2004): the
 * coordinates are transformed in place into the "transposed" Hilbert index
 * (undo the excess rotations and reflections level by level, then Gray-
 * encode), whose bits, interleaved from the top, are the curve index. */
uint64_t rt_hilbert_key(uint32_t x, uint32_t y, uint32_t z, int bits)
{
    uint32_t X[3] = {x, y, z};
    const uint32_t top = 1u << (bits - 1);
    for (uint32_t q = top; q > 1; q >>= 1) {
        const uint32_t p = q - 1;
        for (int i = 0; i < 3; i++) {
            if (X[i] & q) {
                X[0] ^= p; /* reflect the low bits */
            } else {       /* swap the low bits of X[0] and X[i] */
                uint32_t t = (X[0] ^ X[i]) & p;
                X[0] ^= t;
                X[i] ^= t;
            }
        }
    }
    X[1] ^= X[0];
    X[2] ^= X[1];
    uint32_t t = 0;
    for (uint32_t q = top; q > 1; q >>= 1)
        if (X[2] & q) t ^= q - 1;
    for (int i = 0; i < 3; i++) X[i] ^= t;
    /* interleave: bit b of X[0], X[1], X[2] become bits 3b + 2, 3b + 1, 3b */
    return spread3(X[0]) << 2 | spread3(X[1]) << 1 | spread3(X[2]);
}

tt_status rt_bulk_hilbert(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                          const float *tri_box, uint32_t T)
{
    const size_t n = T ? T : 1;
    const int threads = rt_bulk_threads(ctx);
    uint64_t *key = tt_alloc_array(ctx, n, sizeof *key);
    uint64_t *tk = tt_alloc_array(ctx, n, sizeof *tk);
    uint32_t *val = tt_alloc_array(ctx, n, sizeof *val);
    uint32_t *tv = tt_alloc_array(ctx, n, sizeof *tv);
    tt_status st = TT_OK;
    if (!key || !tk || !val || !tv)
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (Hilbert, %u triangles)", T);
    if (st == TT_OK) {
        /* the box of the centres (twice the centres: lo + hi, no rounding
         * of a halving to worry about) */
        float lo[3] = {TT_INF, TT_INF, TT_INF}, hi[3] = {-TT_INF, -TT_INF, -TT_INF};
        for (size_t i = 0; i < T; i++)
            for (int k = 0; k < 3; k++) {
                float c = tri_box[6 * i + k] + tri_box[6 * i + k + 3];
                lo[k] = rt_min(lo[k], c);
                hi[k] = rt_max(hi[k], c);
            }
        const double cells = (double)((1u << HILBERT_BITS) - 1);
        double scale[3];
        for (int k = 0; k < 3; k++) scale[k] = hi[k] > lo[k] ? cells / ((double)hi[k] - lo[k]) : 0.0;
#pragma omp parallel for schedule(static) num_threads(threads) if (T >= RT_BULK_PARALLEL_MIN)
        for (size_t i = 0; i < T; i++) {
            uint32_t q[3];
            for (int k = 0; k < 3; k++) {
                double c = (double)(tri_box[6 * i + k] + tri_box[6 * i + k + 3]);
                double f = (c - lo[k]) * scale[k];
                q[k] = f <= 0.0 ? 0u : f >= cells ? (uint32_t)cells : (uint32_t)f;
            }
            key[i] = rt_hilbert_key(q[0], q[1], q[2], HILBERT_BITS);
            val[i] = (uint32_t)i;
        }
        st = rt_radix_sort(ctx, key, val, tk, tv, T, 3 * HILBERT_BITS, threads);
    }
    tt_free(ctx, key);
    tt_free(ctx, tk);
    tt_free(ctx, tv);
    if (st == TT_OK) st = rt_bulk_bottom_up(b, ctx, opt, tri_box, T, val, NULL, NULL);
    tt_free(ctx, val);
    return st;
}
