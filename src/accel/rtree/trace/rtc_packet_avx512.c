/* The compact R-tree's packet traversal (rtc_packet.h) with 16 rays per
 * AVX-512 register; mask registers hold a group's lanes. Compiled with the
 * AVX-512 flags and -ffp-contract=off (no FMA: every lane rounds as the
 * single-ray kernels do). */
#include <immintrin.h>
#include <math.h>

#include "accel/accel.h"
#include "accel/rtree/rtc.h"
#include "geometry/tri_block_avx512.h"

#define RTC_ISA _avx512
#define PK_L 16
typedef __m512 pk_v;
typedef __mmask16 pk_m;
#define PK_LOAD(p) _mm512_load_ps(p)
#define PK_LOADU(p) _mm512_loadu_ps(p)
#define PK_STOREU(p, x) _mm512_storeu_ps(p, x)
#define PK_STORE(p, x) _mm512_store_ps(p, x)
#define PK_LOADI(p) _mm512_load_si512((const void *)(p))
#define PK_STOREI(p, x) _mm512_store_si512((void *)(p), x)
#define PK_SET1(x) _mm512_set1_ps(x)
#define PK_ADD _mm512_add_ps
#define PK_SUB _mm512_sub_ps
#define PK_MUL _mm512_mul_ps
#define PK_DIV _mm512_div_ps
/* max/min(candidate, accumulator) return the accumulator on NaN, as
 * tt_slab_near / tt_slab_far and the single-ray kernels */
#define PK_MIN _mm512_min_ps
#define PK_MAX _mm512_max_ps
#define PK_ABS _mm512_abs_ps
#define PK_CMP_LT(a, b) _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ)
#define PK_CMP_LE(a, b) _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ)
#define PK_CMP_GT(a, b) _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ)
#define PK_CMP_GE(a, b) _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ)
#define PK_CMP_EQ(a, b) _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ)
#define PK_CMP_NEQ(a, b) _mm512_cmp_ps_mask(a, b, _CMP_NEQ_UQ)
#define PK_MAND(a, b) ((pk_m)((a) & (b)))
#define PK_MOR(a, b) ((pk_m)((a) | (b)))
#define PK_MANDNOT(a, b) ((pk_m)(~(a) & (b))) /* not a, and b */
#define PK_BITS(m) ((uint32_t)(m))
#define PK_MASK(bits) ((pk_m)(bits))
#define PK_BLEND(m, a, b) _mm512_mask_blend_ps(m, a, b) /* m ? b : a */
#define PK_BLENDI(m, a, x) _mm512_mask_blend_epi32(m, a, _mm512_set1_epi32((int)(x)))
#define PK_IDGT(v, id) _mm512_cmpgt_epi32_mask(v, _mm512_set1_epi32((int)(id)))
#define PK_HMIN(x) _mm512_reduce_min_ps(x)
#define PK_HMAX(x) _mm512_reduce_max_ps(x)

#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_avx512
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_avx512
#define RTC_SINGLE tt_rtc_stack_avx512
#define RTC_SINGLE_STATS tt_rtc_stack_avx512_stats

/* Two rays against one block of 8 triangles, a ray a 256-bit half of a
 * 512-bit vector: the few-lane groups' leaf test (rtc_pk_block) for
 * occlusion, two lanes a call where the single-ray block kernel took one.
 * Each half runs tt_tri_blocks_occluded_avx2's operations on its ray
 * (rows by the ray's own kx, ky, kz; no FMA in this unit), and a half with
 * a zero edge function goes to the scalar block test as there, so each
 * ray's answer is the single-ray kernel's. Bit h: ray h occluded. */
static inline __m512 rtc_pair_set(float a, float b)
{
    return _mm512_mask_blend_ps(0xff00, _mm512_set1_ps(a), _mm512_set1_ps(b));
}

static inline uint32_t rtc_pair_occluded(const tt_wray *r0, const tt_wray *r1,
                                         const tt_tri_block *b, float t0, float t1)
{
    const float(*v)[TT_TRI_BLOCK_W] = b->v;
    const int k0[3] = {r0->kx, r0->ky, r0->kz}, k1[3] = {r1->kx, r1->ky, r1->kz};
    __m512 row[9];
    for (int i = 0; i < 9; i++)
        row[i] = _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_loadu_ps(v[i / 3 * 3 + k0[i % 3]])),
                                    _mm256_loadu_ps(v[i / 3 * 3 + k1[i % 3]]), 1);
    const __m512 ox = rtc_pair_set(r0->org[k0[0]], r1->org[k1[0]]);
    const __m512 oy = rtc_pair_set(r0->org[k0[1]], r1->org[k1[1]]);
    const __m512 oz = rtc_pair_set(r0->org[k0[2]], r1->org[k1[2]]);
    const __m512 sx = rtc_pair_set(r0->sx, r1->sx), sy = rtc_pair_set(r0->sy, r1->sy);
    const __m512 ax = _mm512_sub_ps(row[0], ox), ay = _mm512_sub_ps(row[1], oy),
                 az = _mm512_sub_ps(row[2], oz);
    const __m512 bx = _mm512_sub_ps(row[3], ox), by = _mm512_sub_ps(row[4], oy),
                 bz = _mm512_sub_ps(row[5], oz);
    const __m512 cx = _mm512_sub_ps(row[6], ox), cy = _mm512_sub_ps(row[7], oy),
                 cz = _mm512_sub_ps(row[8], oz);
    const __m512 Ax = _mm512_sub_ps(ax, _mm512_mul_ps(sx, az));
    const __m512 Ay = _mm512_sub_ps(ay, _mm512_mul_ps(sy, az));
    const __m512 Bx = _mm512_sub_ps(bx, _mm512_mul_ps(sx, bz));
    const __m512 By = _mm512_sub_ps(by, _mm512_mul_ps(sy, bz));
    const __m512 Cx = _mm512_sub_ps(cx, _mm512_mul_ps(sx, cz));
    const __m512 Cy = _mm512_sub_ps(cy, _mm512_mul_ps(sy, cz));
    const __m512 U = _mm512_sub_ps(_mm512_mul_ps(Cx, By), _mm512_mul_ps(Cy, Bx));
    const __m512 V = _mm512_sub_ps(_mm512_mul_ps(Ax, Cy), _mm512_mul_ps(Ay, Cx));
    const __m512 W = _mm512_sub_ps(_mm512_mul_ps(Bx, Ay), _mm512_mul_ps(By, Ax));
    const __m512 zero = _mm512_setzero_ps();
    const uint32_t z = (uint32_t)(_mm512_cmp_ps_mask(U, zero, _CMP_EQ_OQ) |
                                  _mm512_cmp_ps_mask(V, zero, _CMP_EQ_OQ) |
                                  _mm512_cmp_ps_mask(W, zero, _CMP_EQ_OQ));
    /* the sign bits of (U^V)|(U^W): set where the signs differ */
    const __m512 differ = _mm512_or_ps(_mm512_xor_ps(U, V), _mm512_xor_ps(U, W));
    uint32_t cand = ~(uint32_t)_mm512_movepi32_mask(_mm512_castps_si512(differ)) & 0xffffu;
    /* a half with a zero edge function: the scalar block test (as the
     * single-ray kernel hands such a block over) */
    uint32_t out = 0;
    if (z & 0x00ffu) {
        out |= (uint32_t)(tt_tri_blocks_occluded_scalar(r0, b, 1, t0) != 0);
        cand &= 0xff00u;
    }
    if (z & 0xff00u) {
        out |= (uint32_t)(tt_tri_blocks_occluded_scalar(r1, b, 1, t1) != 0) << 1;
        cand &= 0x00ffu;
    }
    if (!cand) return out;
    const __m512 sz = rtc_pair_set(r0->sz, r1->sz);
    const __m512 det = _mm512_add_ps(_mm512_add_ps(U, V), W);
    const __m512 T = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(U, _mm512_mul_ps(sz, az)),
                                                 _mm512_mul_ps(V, _mm512_mul_ps(sz, bz))),
                                   _mm512_mul_ps(W, _mm512_mul_ps(sz, cz)));
    const __m512 t = _mm512_mul_ps(T, _mm512_div_ps(_mm512_set1_ps(1.0f), det));
    const uint32_t in = (uint32_t)(_mm512_cmp_ps_mask(t, rtc_pair_set(r0->tmin, r1->tmin), _CMP_GE_OQ) &
                                   _mm512_cmp_ps_mask(t, rtc_pair_set(t0, t1), _CMP_LT_OQ));
    const uint32_t hit = cand & in;
    return out | (uint32_t)((hit & 0x00ffu) != 0) | (uint32_t)((hit & 0xff00u) != 0) << 1;
}
#define RTC_OCC_PAIR rtc_pair_occluded

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_packet.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_packet.h"
