/* The compact R-tree's packet traversal (rtc_packet.h) with 8 rays per AVX2
 * register; compare results stay vectors (movemask gives a group's lane
 * bits). Compiled with the AVX2 flags and -ffp-contract=off (no FMA: every
 * lane rounds as the single-ray kernels do). */
#include <immintrin.h>
#include <math.h>

#include "accel/accel.h"
#include "accel/rtree/rtc.h"
#include "geometry/tri_block_avx2.h"

#define RTC_ISA _avx2
#define PK_L 8
typedef __m256 pk_v;
typedef __m256 pk_m;
#define PK_LOAD(p) _mm256_load_ps(p)
#define PK_LOADU(p) _mm256_loadu_ps(p)
#define PK_STOREU(p, x) _mm256_storeu_ps(p, x)
#define PK_STORE(p, x) _mm256_store_ps(p, x)
#define PK_LOADI(p) _mm256_load_si256((const __m256i *)(const void *)(p))
#define PK_STOREI(p, x) _mm256_store_si256((__m256i *)(void *)(p), x)
#define PK_SET1(x) _mm256_set1_ps(x)
#define PK_ADD _mm256_add_ps
#define PK_SUB _mm256_sub_ps
#define PK_MUL _mm256_mul_ps
#define PK_DIV _mm256_div_ps
/* max/min(candidate, accumulator) return the accumulator on NaN, as
 * tt_slab_near / tt_slab_far and the single-ray kernels */
#define PK_MIN _mm256_min_ps
#define PK_MAX _mm256_max_ps
#define PK_ABS(x) _mm256_and_ps(x, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)))
#define PK_CMP_LT(a, b) _mm256_cmp_ps(a, b, _CMP_LT_OQ)
#define PK_CMP_LE(a, b) _mm256_cmp_ps(a, b, _CMP_LE_OQ)
#define PK_CMP_GT(a, b) _mm256_cmp_ps(a, b, _CMP_GT_OQ)
#define PK_CMP_GE(a, b) _mm256_cmp_ps(a, b, _CMP_GE_OQ)
#define PK_CMP_EQ(a, b) _mm256_cmp_ps(a, b, _CMP_EQ_OQ)
#define PK_CMP_NEQ(a, b) _mm256_cmp_ps(a, b, _CMP_NEQ_UQ)
#define PK_MAND _mm256_and_ps
#define PK_MOR _mm256_or_ps
#define PK_MANDNOT _mm256_andnot_ps /* not a, and b */
#define PK_BITS(m) ((uint32_t)_mm256_movemask_ps(m))
static inline __m256 pk_mask_avx2(uint32_t bits)
{
    const __m256i lane = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(
        _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32((int)bits), lane), lane));
}
#define PK_MASK(bits) pk_mask_avx2(bits)
#define PK_BLEND(m, a, b) _mm256_blendv_ps(a, b, m) /* m ? b : a */
#define PK_BLENDI(m, a, x)                                                                       \
    _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(a),                                \
                                         _mm256_castsi256_ps(_mm256_set1_epi32((int)(x))), m))
static inline float pk_hmin_avx2(__m256 x)
{
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(x), _mm256_extractf128_ps(x, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    m = _mm_min_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}
static inline float pk_hmax_avx2(__m256 x)
{
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(x), _mm256_extractf128_ps(x, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}
#define PK_IDGT(v, id) _mm256_castsi256_ps(_mm256_cmpgt_epi32(v, _mm256_set1_epi32((int)(id))))
#define PK_HMIN(x) pk_hmin_avx2(x)
#define PK_HMAX(x) pk_hmax_avx2(x)

#define RTC_BLOCKS_INTERSECT tt_tri_blocks_intersect_avx2
#define RTC_BLOCKS_OCCLUDED tt_tri_blocks_occluded_avx2
#define RTC_SINGLE tt_rtc_stack_avx2
#define RTC_SINGLE_STATS tt_rtc_stack_avx2_stats

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_packet.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_packet.h"
