/* The triangle-block kernels for AVX2: one 256-bit vector is one block's 8
 * lanes. Include only from a *_avx2.c unit (compiled with -mavx2 and
 * -ffp-contract=off; see core/isa.h). Results are bit for bit those of
 * tt_tri_blocks_intersect_scalar / _occluded_scalar (geometry/tri_block.h):
 * each lane runs tt_intersect_triangle's float operations in its order, with
 * a true division for 1/det and no fused multiply-add, and a block in which
 * any lane has a zero edge function is handed whole to the scalar code
 * (its double-precision recomputation). */
#ifndef TT_GEOMETRY_TRI_BLOCK_AVX2_H
#define TT_GEOMETRY_TRI_BLOCK_AVX2_H

#include <immintrin.h>

#include "geometry/tri_block.h"

/* What the test needs of the ray, set up once per call: the rows of the
 * block that hold the permuted coordinates (kx, ky, kz of each vertex) and
 * the broadcast origin and shear constants. */
typedef struct tt_tri_ray_avx2 {
    int row[9]; /* a.kx a.ky a.kz b.kx b.ky b.kz c.kx c.ky c.kz */
    __m256 ox, oy, oz, sx, sy, sz, tmin;
} tt_tri_ray_avx2;

static inline void tt_tri_ray_avx2_init(tt_tri_ray_avx2 *q, const tt_wray *r)
{
    for (int k = 0; k < 3; k++) {
        q->row[3 * k] = 3 * k + r->kx;
        q->row[3 * k + 1] = 3 * k + r->ky;
        q->row[3 * k + 2] = 3 * k + r->kz;
    }
    q->ox = _mm256_set1_ps(r->org[r->kx]);
    q->oy = _mm256_set1_ps(r->org[r->ky]);
    q->oz = _mm256_set1_ps(r->org[r->kz]);
    q->sx = _mm256_set1_ps(r->sx);
    q->sy = _mm256_set1_ps(r->sy);
    q->sz = _mm256_set1_ps(r->sz);
    q->tmin = _mm256_set1_ps(r->tmin);
}

/* One block's edge functions, determinant-to-be and scaled depth. */
typedef struct tt_tri_lanes_avx2 {
    __m256 U, V, W, az, bz, cz;
} tt_tri_lanes_avx2;

/* Bit i: lane i has a zero edge function (the block goes to the scalar code).
 * Otherwise writes *cand, bit i: lane i's edge functions share one sign, the
 * lanes tt_intersect_triangle's sign test lets through. (With no zero, "not
 * both a negative and a positive one" is "all signs equal"; NaN lanes may
 * pass here, their t is NaN and fails the range test.) */
static inline int tt_tri_edges_avx2(const tt_tri_ray_avx2 *q, const tt_tri_block *b,
                                    tt_tri_lanes_avx2 *L, int *cand)
{
    const float(*v)[TT_TRI_BLOCK_W] = b->v;
    const __m256 ax = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[0]]), q->ox);
    const __m256 ay = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[1]]), q->oy);
    const __m256 az = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[2]]), q->oz);
    const __m256 bx = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[3]]), q->ox);
    const __m256 by = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[4]]), q->oy);
    const __m256 bz = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[5]]), q->oz);
    const __m256 cx = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[6]]), q->ox);
    const __m256 cy = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[7]]), q->oy);
    const __m256 cz = _mm256_sub_ps(_mm256_loadu_ps(v[q->row[8]]), q->oz);
    const __m256 Ax = _mm256_sub_ps(ax, _mm256_mul_ps(q->sx, az));
    const __m256 Ay = _mm256_sub_ps(ay, _mm256_mul_ps(q->sy, az));
    const __m256 Bx = _mm256_sub_ps(bx, _mm256_mul_ps(q->sx, bz));
    const __m256 By = _mm256_sub_ps(by, _mm256_mul_ps(q->sy, bz));
    const __m256 Cx = _mm256_sub_ps(cx, _mm256_mul_ps(q->sx, cz));
    const __m256 Cy = _mm256_sub_ps(cy, _mm256_mul_ps(q->sy, cz));
    L->U = _mm256_sub_ps(_mm256_mul_ps(Cx, By), _mm256_mul_ps(Cy, Bx));
    L->V = _mm256_sub_ps(_mm256_mul_ps(Ax, Cy), _mm256_mul_ps(Ay, Cx));
    L->W = _mm256_sub_ps(_mm256_mul_ps(Bx, Ay), _mm256_mul_ps(By, Ax));
    L->az = az;
    L->bz = bz;
    L->cz = cz;
    const __m256 zero = _mm256_setzero_ps();
    const __m256 z = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(L->U, zero, _CMP_EQ_OQ),
                                               _mm256_cmp_ps(L->V, zero, _CMP_EQ_OQ)),
                                  _mm256_cmp_ps(L->W, zero, _CMP_EQ_OQ));
    /* Sign bit of (U^V)|(U^W): set where the signs differ. */
    const __m256 differ = _mm256_or_ps(_mm256_xor_ps(L->U, L->V), _mm256_xor_ps(L->U, L->W));
    *cand = ~_mm256_movemask_ps(differ) & 0xff;
    return _mm256_movemask_ps(z);
}

/* t of every lane and 1/det, in tt_intersect_triangle's order:
 * det = (U + V) + W, T = (U*(sz*az) + V*(sz*bz)) + W*(sz*cz), t = T * (1/det). */
static inline __m256 tt_tri_t_avx2(const tt_tri_ray_avx2 *q, const tt_tri_lanes_avx2 *L,
                                   __m256 *inv_det)
{
    const __m256 det = _mm256_add_ps(_mm256_add_ps(L->U, L->V), L->W);
    const __m256 T = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(L->U, _mm256_mul_ps(q->sz, L->az)),
                      _mm256_mul_ps(L->V, _mm256_mul_ps(q->sz, L->bz))),
        _mm256_mul_ps(L->W, _mm256_mul_ps(q->sz, L->cz)));
    *inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
    return _mm256_mul_ps(T, *inv_det);
}

/* Bit i: lane i's t lies in [tmin, tmax). */
static inline int tt_tri_in_range_avx2(const tt_tri_ray_avx2 *q, __m256 t, float tmax)
{
    const __m256 in = _mm256_and_ps(_mm256_cmp_ps(t, q->tmin, _CMP_GE_OQ),
                                    _mm256_cmp_ps(t, _mm256_set1_ps(tmax), _CMP_LT_OQ));
    return _mm256_movemask_ps(in);
}

TT_TRI_KERNEL int tt_tri_blocks_intersect_avx2(const tt_wray *r, const tt_tri_block *b,
                                               uint32_t count, tt_hit *hit)
{
    tt_tri_ray_avx2 q;
    tt_tri_ray_avx2_init(&q, r);
    int found = 0;
    for (uint32_t j = 0; j < count; j++) {
        tt_tri_lanes_avx2 L;
        int cand;
        if (tt_tri_edges_avx2(&q, &b[j], &L, &cand)) {
            found |= tt_tri_blocks_intersect_scalar(r, &b[j], 1, hit);
            continue;
        }
        if (!cand) continue;
        const float limit = tt_tri_tie_limit(hit);
        __m256 inv_det;
        const __m256 t = tt_tri_t_avx2(&q, &L, &inv_det);
        int m = cand & tt_tri_in_range_avx2(&q, t, limit);
        if (!m) continue;
        /* The nearest lane, the smallest id among equals (tt_tri_better),
         * as the scalar loop. Usually one lane. */
        float ts[TT_TRI_BLOCK_W], vs[TT_TRI_BLOCK_W], ws[TT_TRI_BLOCK_W], is[TT_TRI_BLOCK_W];
        _mm256_storeu_ps(ts, t);
        int best = __builtin_ctz((unsigned)m);
        for (m &= m - 1; m; m &= m - 1) {
            const int i = __builtin_ctz((unsigned)m);
            if (ts[i] < ts[best] || (ts[i] == ts[best] && b[j].prim[i] < b[j].prim[best]))
                best = i;
        }
        if (!tt_tri_better(ts[best], b[j].prim[best], hit)) continue;
        _mm256_storeu_ps(vs, L.V);
        _mm256_storeu_ps(ws, L.W);
        _mm256_storeu_ps(is, inv_det);
        hit->t = ts[best];
        hit->u = vs[best] * is[best];
        hit->v = ws[best] * is[best];
        hit->prim = b[j].prim[best];
        found = 1;
    }
    return found;
}

TT_TRI_KERNEL int tt_tri_blocks_occluded_avx2(const tt_wray *r, const tt_tri_block *b,
                                              uint32_t count, float tmax)
{
    tt_tri_ray_avx2 q;
    tt_tri_ray_avx2_init(&q, r);
    for (uint32_t j = 0; j < count; j++) {
        tt_tri_lanes_avx2 L;
        int cand;
        if (tt_tri_edges_avx2(&q, &b[j], &L, &cand)) {
            if (tt_tri_blocks_occluded_scalar(r, &b[j], 1, tmax)) return 1;
            continue;
        }
        if (!cand) continue;
        __m256 inv_det;
        const __m256 t = tt_tri_t_avx2(&q, &L, &inv_det);
        if (cand & tt_tri_in_range_avx2(&q, t, tmax)) return 1;
    }
    return 0;
}

#endif
