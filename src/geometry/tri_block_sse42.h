/* The triangle-block kernels for SSE4.2: a block's 8 lanes as two 128-bit
 * halves. Include only from a *_sse42.c unit (compiled with -msse4.2 and
 * -ffp-contract=off; see core/isa.h). Results are bit for bit those of
 * tt_tri_blocks_intersect_scalar / _occluded_scalar (geometry/tri_block.h);
 * the lane arithmetic is that of tri_block_avx2.h, half a block at a time. */
#ifndef TT_GEOMETRY_TRI_BLOCK_SSE42_H
#define TT_GEOMETRY_TRI_BLOCK_SSE42_H

#include <nmmintrin.h>

#include "geometry/tri_block.h"

/* Per call: the block rows of the permuted coordinates, broadcast origin and
 * shear constants. */
typedef struct tt_tri_ray_sse42 {
    int row[9]; /* a.kx a.ky a.kz b.kx b.ky b.kz c.kx c.ky c.kz */
    __m128 ox, oy, oz, sx, sy, sz, tmin;
} tt_tri_ray_sse42;

static inline void tt_tri_ray_sse42_init(tt_tri_ray_sse42 *q, const tt_wray *r)
{
    for (int k = 0; k < 3; k++) {
        q->row[3 * k] = 3 * k + r->kx;
        q->row[3 * k + 1] = 3 * k + r->ky;
        q->row[3 * k + 2] = 3 * k + r->kz;
    }
    q->ox = _mm_set1_ps(r->org[r->kx]);
    q->oy = _mm_set1_ps(r->org[r->ky]);
    q->oz = _mm_set1_ps(r->org[r->kz]);
    q->sx = _mm_set1_ps(r->sx);
    q->sy = _mm_set1_ps(r->sy);
    q->sz = _mm_set1_ps(r->sz);
    q->tmin = _mm_set1_ps(r->tmin);
}

/* Four lanes' edge functions and the permuted depths t needs. */
typedef struct tt_tri_lanes_sse42 {
    __m128 U, V, W, az, bz, cz;
} tt_tri_lanes_sse42;

/* Lanes h*4 .. h*4+3 of block b. Returns bit i: lane i has a zero edge
 * function; *cand bit i: its edge functions share one sign (see
 * tri_block_avx2.h). */
static inline int tt_tri_edges_sse42(const tt_tri_ray_sse42 *q, const tt_tri_block *b, int h,
                                     tt_tri_lanes_sse42 *L, int *cand)
{
    const float(*v)[TT_TRI_BLOCK_W] = b->v;
    const int o = 4 * h;
    const __m128 ax = _mm_sub_ps(_mm_loadu_ps(v[q->row[0]] + o), q->ox);
    const __m128 ay = _mm_sub_ps(_mm_loadu_ps(v[q->row[1]] + o), q->oy);
    const __m128 az = _mm_sub_ps(_mm_loadu_ps(v[q->row[2]] + o), q->oz);
    const __m128 bx = _mm_sub_ps(_mm_loadu_ps(v[q->row[3]] + o), q->ox);
    const __m128 by = _mm_sub_ps(_mm_loadu_ps(v[q->row[4]] + o), q->oy);
    const __m128 bz = _mm_sub_ps(_mm_loadu_ps(v[q->row[5]] + o), q->oz);
    const __m128 cx = _mm_sub_ps(_mm_loadu_ps(v[q->row[6]] + o), q->ox);
    const __m128 cy = _mm_sub_ps(_mm_loadu_ps(v[q->row[7]] + o), q->oy);
    const __m128 cz = _mm_sub_ps(_mm_loadu_ps(v[q->row[8]] + o), q->oz);
    const __m128 Ax = _mm_sub_ps(ax, _mm_mul_ps(q->sx, az));
    const __m128 Ay = _mm_sub_ps(ay, _mm_mul_ps(q->sy, az));
    const __m128 Bx = _mm_sub_ps(bx, _mm_mul_ps(q->sx, bz));
    const __m128 By = _mm_sub_ps(by, _mm_mul_ps(q->sy, bz));
    const __m128 Cx = _mm_sub_ps(cx, _mm_mul_ps(q->sx, cz));
    const __m128 Cy = _mm_sub_ps(cy, _mm_mul_ps(q->sy, cz));
    L->U = _mm_sub_ps(_mm_mul_ps(Cx, By), _mm_mul_ps(Cy, Bx));
    L->V = _mm_sub_ps(_mm_mul_ps(Ax, Cy), _mm_mul_ps(Ay, Cx));
    L->W = _mm_sub_ps(_mm_mul_ps(Bx, Ay), _mm_mul_ps(By, Ax));
    L->az = az;
    L->bz = bz;
    L->cz = cz;
    const __m128 zero = _mm_setzero_ps();
    const __m128 z = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(L->U, zero), _mm_cmpeq_ps(L->V, zero)),
                               _mm_cmpeq_ps(L->W, zero));
    const __m128 differ = _mm_or_ps(_mm_xor_ps(L->U, L->V), _mm_xor_ps(L->U, L->W));
    *cand = ~_mm_movemask_ps(differ) & 0xf;
    return _mm_movemask_ps(z);
}

/* t and 1/det of four lanes, in tt_intersect_triangle's order. */
static inline __m128 tt_tri_t_sse42(const tt_tri_ray_sse42 *q, const tt_tri_lanes_sse42 *L,
                                    __m128 *inv_det)
{
    const __m128 det = _mm_add_ps(_mm_add_ps(L->U, L->V), L->W);
    const __m128 T = _mm_add_ps(_mm_add_ps(_mm_mul_ps(L->U, _mm_mul_ps(q->sz, L->az)),
                                           _mm_mul_ps(L->V, _mm_mul_ps(q->sz, L->bz))),
                                _mm_mul_ps(L->W, _mm_mul_ps(q->sz, L->cz)));
    *inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
    return _mm_mul_ps(T, *inv_det);
}

/* Bit i: lane i's t lies in [tmin, tmax). */
static inline int tt_tri_in_range_sse42(const tt_tri_ray_sse42 *q, __m128 t, float tmax)
{
    return _mm_movemask_ps(
        _mm_and_ps(_mm_cmpge_ps(t, q->tmin), _mm_cmplt_ps(t, _mm_set1_ps(tmax))));
}

TT_TRI_KERNEL int tt_tri_blocks_intersect_sse42(const tt_wray *r, const tt_tri_block *b,
                                                uint32_t count, tt_hit *hit)
{
    tt_tri_ray_sse42 q;
    tt_tri_ray_sse42_init(&q, r);
    int found = 0;
    for (uint32_t j = 0; j < count; j++) {
        tt_tri_lanes_sse42 lo, hi;
        int cand_lo, cand_hi;
        const int zeros = tt_tri_edges_sse42(&q, &b[j], 0, &lo, &cand_lo) |
                          tt_tri_edges_sse42(&q, &b[j], 1, &hi, &cand_hi);
        if (zeros) {
            found |= tt_tri_blocks_intersect_scalar(r, &b[j], 1, hit);
            continue;
        }
        if (!(cand_lo | cand_hi)) continue;
        const float limit = tt_tri_tie_limit(hit);
        /* Both halves against the nearest hit before this block; the lane
         * loop below then keeps scalar order (strict <, lowest lane first). */
        float ts[TT_TRI_BLOCK_W], vs[TT_TRI_BLOCK_W], ws[TT_TRI_BLOCK_W], is[TT_TRI_BLOCK_W];
        int m = 0;
        if (cand_lo) {
            __m128 inv;
            const __m128 t = tt_tri_t_sse42(&q, &lo, &inv);
            m |= cand_lo & tt_tri_in_range_sse42(&q, t, limit);
            _mm_storeu_ps(ts, t);
            _mm_storeu_ps(is, inv);
        }
        if (cand_hi) {
            __m128 inv;
            const __m128 t = tt_tri_t_sse42(&q, &hi, &inv);
            m |= (cand_hi & tt_tri_in_range_sse42(&q, t, limit)) << 4;
            _mm_storeu_ps(ts + 4, t);
            _mm_storeu_ps(is + 4, inv);
        }
        if (!m) continue;
        int best = __builtin_ctz((unsigned)m);
        for (m &= m - 1; m; m &= m - 1) {
            const int i = __builtin_ctz((unsigned)m);
            if (ts[i] < ts[best] || (ts[i] == ts[best] && b[j].prim[i] < b[j].prim[best]))
                best = i;
        }
        if (!tt_tri_better(ts[best], b[j].prim[best], hit)) continue;
        _mm_storeu_ps(vs, lo.V);
        _mm_storeu_ps(vs + 4, hi.V);
        _mm_storeu_ps(ws, lo.W);
        _mm_storeu_ps(ws + 4, hi.W);
        hit->t = ts[best];
        hit->u = vs[best] * is[best];
        hit->v = ws[best] * is[best];
        hit->prim = b[j].prim[best];
        found = 1;
    }
    return found;
}

TT_TRI_KERNEL int tt_tri_blocks_occluded_sse42(const tt_wray *r, const tt_tri_block *b,
                                               uint32_t count, float tmax)
{
    tt_tri_ray_sse42 q;
    tt_tri_ray_sse42_init(&q, r);
    for (uint32_t j = 0; j < count; j++) {
        tt_tri_lanes_sse42 lo, hi;
        int cand_lo, cand_hi;
        const int zeros = tt_tri_edges_sse42(&q, &b[j], 0, &lo, &cand_lo) |
                          tt_tri_edges_sse42(&q, &b[j], 1, &hi, &cand_hi);
        if (zeros) {
            if (tt_tri_blocks_occluded_scalar(r, &b[j], 1, tmax)) return 1;
            continue;
        }
        __m128 inv;
        if (cand_lo && (cand_lo & tt_tri_in_range_sse42(&q, tt_tri_t_sse42(&q, &lo, &inv), tmax)))
            return 1;
        if (cand_hi && (cand_hi & tt_tri_in_range_sse42(&q, tt_tri_t_sse42(&q, &hi, &inv), tmax)))
            return 1;
    }
    return 0;
}

#endif
