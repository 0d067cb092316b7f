/* The triangle-block kernels for AVX-512 (F, VL, DQ, BW): two blocks per
 * 512-bit vector while at least two remain, a last odd block with 256-bit
 * operations and mask registers. Include only from a *_avx512.c unit
 * (compiled with the AVX-512 flags and -ffp-contract=off; see core/isa.h).
 * Results are bit for bit those of tt_tri_blocks_intersect_scalar /
 * _occluded_scalar (geometry/tri_block.h); the lane arithmetic is that of
 * tri_block_avx2.h. */
#ifndef TT_GEOMETRY_TRI_BLOCK_AVX512_H
#define TT_GEOMETRY_TRI_BLOCK_AVX512_H

#include <immintrin.h>

#include "geometry/tri_block.h"

/* Per call: the block rows of the permuted coordinates, broadcast origin and
 * shear constants (512-bit; the 256-bit path uses their low halves). */
typedef struct tt_tri_ray_avx512 {
    int row[9]; /* a.kx a.ky a.kz b.kx b.ky b.kz c.kx c.ky c.kz */
    __m512 ox, oy, oz, sx, sy, sz, tmin;
} tt_tri_ray_avx512;

static inline void tt_tri_ray_avx512_init(tt_tri_ray_avx512 *q, const tt_wray *r)
{
    for (int k = 0; k < 3; k++) {
        q->row[3 * k] = 3 * k + r->kx;
        q->row[3 * k + 1] = 3 * k + r->ky;
        q->row[3 * k + 2] = 3 * k + r->kz;
    }
    q->ox = _mm512_set1_ps(r->org[r->kx]);
    q->oy = _mm512_set1_ps(r->org[r->ky]);
    q->oz = _mm512_set1_ps(r->org[r->kz]);
    q->sx = _mm512_set1_ps(r->sx);
    q->sy = _mm512_set1_ps(r->sy);
    q->sz = _mm512_set1_ps(r->sz);
    q->tmin = _mm512_set1_ps(r->tmin);
}

/* Sixteen lanes (blocks b[0] and b[1]) at once. */
typedef struct tt_tri_lanes_avx512 {
    __m512 U, V, W, az, bz, cz;
} tt_tri_lanes_avx512;

/* Row `row` of blocks b[0] (low half) and b[1] (high half). */
static inline __m512 tt_tri_load2_avx512(const tt_tri_block *b, int row)
{
    return _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_loadu_ps(b[0].v[row])),
                              _mm256_loadu_ps(b[1].v[row]), 1);
}

/* Bit i (0..15): lane i%8 of block b[i/8] has a zero edge function;
 * *cand: the lanes whose edge functions share one sign (see tri_block_avx2.h). */
static inline __mmask16 tt_tri_edges2_avx512(const tt_tri_ray_avx512 *q, const tt_tri_block *b,
                                             tt_tri_lanes_avx512 *L, __mmask16 *cand)
{
    const __m512 ax = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[0]), q->ox);
    const __m512 ay = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[1]), q->oy);
    const __m512 az = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[2]), q->oz);
    const __m512 bx = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[3]), q->ox);
    const __m512 by = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[4]), q->oy);
    const __m512 bz = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[5]), q->oz);
    const __m512 cx = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[6]), q->ox);
    const __m512 cy = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[7]), q->oy);
    const __m512 cz = _mm512_sub_ps(tt_tri_load2_avx512(b, q->row[8]), q->oz);
    const __m512 Ax = _mm512_sub_ps(ax, _mm512_mul_ps(q->sx, az));
    const __m512 Ay = _mm512_sub_ps(ay, _mm512_mul_ps(q->sy, az));
    const __m512 Bx = _mm512_sub_ps(bx, _mm512_mul_ps(q->sx, bz));
    const __m512 By = _mm512_sub_ps(by, _mm512_mul_ps(q->sy, bz));
    const __m512 Cx = _mm512_sub_ps(cx, _mm512_mul_ps(q->sx, cz));
    const __m512 Cy = _mm512_sub_ps(cy, _mm512_mul_ps(q->sy, cz));
    L->U = _mm512_sub_ps(_mm512_mul_ps(Cx, By), _mm512_mul_ps(Cy, Bx));
    L->V = _mm512_sub_ps(_mm512_mul_ps(Ax, Cy), _mm512_mul_ps(Ay, Cx));
    L->W = _mm512_sub_ps(_mm512_mul_ps(Bx, Ay), _mm512_mul_ps(By, Ax));
    L->az = az;
    L->bz = bz;
    L->cz = cz;
    const __m512 zero = _mm512_setzero_ps();
    const __mmask16 z = _mm512_cmp_ps_mask(L->U, zero, _CMP_EQ_OQ) |
                        _mm512_cmp_ps_mask(L->V, zero, _CMP_EQ_OQ) |
                        _mm512_cmp_ps_mask(L->W, zero, _CMP_EQ_OQ);
    const __m512i differ = _mm512_or_si512(
        _mm512_xor_si512(_mm512_castps_si512(L->U), _mm512_castps_si512(L->V)),
        _mm512_xor_si512(_mm512_castps_si512(L->U), _mm512_castps_si512(L->W)));
    *cand = (__mmask16)~_mm512_movepi32_mask(differ);
    return z;
}

/* In-range lanes among cand, t and 1/det of all sixteen lanes in
 * tt_intersect_triangle's order. */
static inline __mmask16 tt_tri_hits2_avx512(const tt_tri_ray_avx512 *q,
                                            const tt_tri_lanes_avx512 *L, __mmask16 cand,
                                            float tmax, __m512 *t, __m512 *inv_det)
{
    const __m512 det = _mm512_add_ps(_mm512_add_ps(L->U, L->V), L->W);
    const __m512 T = _mm512_add_ps(
        _mm512_add_ps(_mm512_mul_ps(L->U, _mm512_mul_ps(q->sz, L->az)),
                      _mm512_mul_ps(L->V, _mm512_mul_ps(q->sz, L->bz))),
        _mm512_mul_ps(L->W, _mm512_mul_ps(q->sz, L->cz)));
    *inv_det = _mm512_div_ps(_mm512_set1_ps(1.0f), det);
    *t = _mm512_mul_ps(T, *inv_det);
    const __mmask16 ge = _mm512_mask_cmp_ps_mask(cand, *t, q->tmin, _CMP_GE_OQ);
    return _mm512_mask_cmp_ps_mask(ge, *t, _mm512_set1_ps(tmax), _CMP_LT_OQ);
}

/* The 256-bit forms for one block (the last of an odd count, or a pair that
 * holds a zero edge function). */
typedef struct tt_tri_lanes_avx512h {
    __m256 U, V, W, az, bz, cz;
} tt_tri_lanes_avx512h;

static inline __mmask8 tt_tri_edges1_avx512(const tt_tri_ray_avx512 *q, const tt_tri_block *b,
                                            tt_tri_lanes_avx512h *L, __mmask8 *cand)
{
    const __m256 ox = _mm512_castps512_ps256(q->ox), oy = _mm512_castps512_ps256(q->oy);
    const __m256 oz = _mm512_castps512_ps256(q->oz);
    const __m256 sx = _mm512_castps512_ps256(q->sx), sy = _mm512_castps512_ps256(q->sy);
    const float(*v)[TT_TRI_BLOCK_W] = b->v;
    const __m256 ax = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[0]]), ox);
    const __m256 ay = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[1]]), oy);
    const __m256 az = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[2]]), oz);
    const __m256 bx = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[3]]), ox);
    const __m256 by = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[4]]), oy);
    const __m256 bz = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[5]]), oz);
    const __m256 cx = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[6]]), ox);
    const __m256 cy = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[7]]), oy);
    const __m256 cz = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[8]]), oz);
    const __m256 Ax = _mm256_sub_ps(ax, _mm256_mul_ps(sx, az));
    const __m256 Ay = _mm256_sub_ps(ay, _mm256_mul_ps(sy, az));
    const __m256 Bx = _mm256_sub_ps(bx, _mm256_mul_ps(sx, bz));
    const __m256 By = _mm256_sub_ps(by, _mm256_mul_ps(sy, bz));
    const __m256 Cx = _mm256_sub_ps(cx, _mm256_mul_ps(sx, cz));
    const __m256 Cy = _mm256_sub_ps(cy, _mm256_mul_ps(sy, cz));
    L->U = _mm256_sub_ps(_mm256_mul_ps(Cx, By), _mm256_mul_ps(Cy, Bx));
    L->V = _mm256_sub_ps(_mm256_mul_ps(Ax, Cy), _mm256_mul_ps(Ay, Cx));
    L->W = _mm256_sub_ps(_mm256_mul_ps(Bx, Ay), _mm256_mul_ps(By, Ax));
    L->az = az;
    L->bz = bz;
    L->cz = cz;
    const __m256 zero = _mm256_setzero_ps();
    const __mmask8 z = _mm256_cmp_ps_mask(L->U, zero, _CMP_EQ_OQ) |
                       _mm256_cmp_ps_mask(L->V, zero, _CMP_EQ_OQ) |
                       _mm256_cmp_ps_mask(L->W, zero, _CMP_EQ_OQ);
    const __m256i differ = _mm256_or_si256(
        _mm256_xor_si256(_mm256_castps_si256(L->U), _mm256_castps_si256(L->V)),
        _mm256_xor_si256(_mm256_castps_si256(L->U), _mm256_castps_si256(L->W)));
    *cand = (__mmask8)~_mm256_movepi32_mask(differ);
    return z;
}

static inline __mmask8 tt_tri_hits1_avx512(const tt_tri_ray_avx512 *q,
                                           const tt_tri_lanes_avx512h *L, __mmask8 cand,
                                           float tmax, __m256 *t, __m256 *inv_det)
{
    const __m256 sz = _mm512_castps512_ps256(q->sz);
    const __m256 det = _mm256_add_ps(_mm256_add_ps(L->U, L->V), L->W);
    const __m256 T = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(L->U, _mm256_mul_ps(sz, L->az)),
                                                 _mm256_mul_ps(L->V, _mm256_mul_ps(sz, L->bz))),
                                   _mm256_mul_ps(L->W, _mm256_mul_ps(sz, L->cz)));
    *inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
    *t = _mm256_mul_ps(T, *inv_det);
    const __mmask8 ge = _mm256_mask_cmp_ps_mask(cand, *t, _mm512_castps512_ps256(q->tmin),
                                                _CMP_GE_OQ);
    return _mm256_mask_cmp_ps_mask(ge, *t, _mm256_set1_ps(tmax), _CMP_LT_OQ);
}

/* Among the lanes of m (lane order = scalar loop order), the nearest, the
 * first among equals; writes it into *hit. ts, vs, ws, is: t, V, W, 1/det. */
static inline void tt_tri_take_avx512(unsigned m, const float *ts, const float *vs,
                                      const float *ws, const float *is, const tt_tri_block *b,
                                      tt_hit *hit)
{
    int best = __builtin_ctz(m);
    for (m &= m - 1; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        if (ts[i] < ts[best]) best = i;
    }
    hit->t = ts[best];
    hit->u = vs[best] * is[best];
    hit->v = ws[best] * is[best];
    hit->prim = b[best / TT_TRI_BLOCK_W].prim[best % TT_TRI_BLOCK_W];
}

/* One block with 256-bit operations. */
static inline int tt_tri_block1_intersect_avx512(const tt_tri_ray_avx512 *q, const tt_wray *r,
                                                 const tt_tri_block *b, tt_hit *hit)
{
    tt_tri_lanes_avx512h L;
    __mmask8 cand;
    if (tt_tri_edges1_avx512(q, b, &L, &cand)) return tt_tri_blocks_intersect_scalar(r, b, 1, hit);
    if (!cand) return 0;
    __m256 t, inv;
    const __mmask8 m = tt_tri_hits1_avx512(q, &L, cand, hit->t, &t, &inv);
    if (!m) return 0;
    float ts[8], vs[8], ws[8], is[8];
    _mm256_storeu_ps(ts, t);
    _mm256_storeu_ps(vs, L.V);
    _mm256_storeu_ps(ws, L.W);
    _mm256_storeu_ps(is, inv);
    tt_tri_take_avx512(m, ts, vs, ws, is, b, hit);
    return 1;
}

static inline int tt_tri_block1_occluded_avx512(const tt_tri_ray_avx512 *q, const tt_wray *r,
                                                const tt_tri_block *b, float tmax)
{
    tt_tri_lanes_avx512h L;
    __mmask8 cand;
    if (tt_tri_edges1_avx512(q, b, &L, &cand)) return tt_tri_blocks_occluded_scalar(r, b, 1, tmax);
    if (!cand) return 0;
    __m256 t, inv;
    return tt_tri_hits1_avx512(q, &L, cand, tmax, &t, &inv) != 0;
}

static inline int tt_tri_blocks_intersect_avx512(const tt_wray *r, const tt_tri_block *b,
                                                 uint32_t count, tt_hit *hit)
{
    tt_tri_ray_avx512 q;
    tt_tri_ray_avx512_init(&q, r);
    int found = 0;
    uint32_t j = 0;
    for (; j + 1 < count; j += 2) {
        tt_tri_lanes_avx512 L;
        __mmask16 cand;
        if (tt_tri_edges2_avx512(&q, &b[j], &L, &cand)) {
            /* Rare: each block alone, the one with the zero through the
             * scalar code, in order. */
            found |= tt_tri_block1_intersect_avx512(&q, r, &b[j], hit);
            found |= tt_tri_block1_intersect_avx512(&q, r, &b[j + 1], hit);
            continue;
        }
        if (!cand) continue;
        __m512 t, inv;
        /* Both blocks against the nearest hit before them; the lane loop
         * keeps the scalar order (block j's lanes come first). */
        const __mmask16 m = tt_tri_hits2_avx512(&q, &L, cand, hit->t, &t, &inv);
        if (!m) continue;
        float ts[16], vs[16], ws[16], is[16];
        _mm512_storeu_ps(ts, t);
        _mm512_storeu_ps(vs, L.V);
        _mm512_storeu_ps(ws, L.W);
        _mm512_storeu_ps(is, inv);
        tt_tri_take_avx512(m, ts, vs, ws, is, &b[j], hit);
        found = 1;
    }
    if (j < count) found |= tt_tri_block1_intersect_avx512(&q, r, &b[j], hit);
    return found;
}

static inline int tt_tri_blocks_occluded_avx512(const tt_wray *r, const tt_tri_block *b,
                                                uint32_t count, float tmax)
{
    tt_tri_ray_avx512 q;
    tt_tri_ray_avx512_init(&q, r);
    uint32_t j = 0;
    for (; j + 1 < count; j += 2) {
        tt_tri_lanes_avx512 L;
        __mmask16 cand;
        if (tt_tri_edges2_avx512(&q, &b[j], &L, &cand)) {
            if (tt_tri_block1_occluded_avx512(&q, r, &b[j], tmax) ||
                tt_tri_block1_occluded_avx512(&q, r, &b[j + 1], tmax))
                return 1;
            continue;
        }
        if (!cand) continue;
        __m512 t, inv;
        if (tt_tri_hits2_avx512(&q, &L, cand, tmax, &t, &inv)) return 1;
    }
    return j < count && tt_tri_block1_occluded_avx512(&q, r, &b[j], tmax);
}

#endif
