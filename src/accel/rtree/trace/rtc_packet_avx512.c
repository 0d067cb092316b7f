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

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_packet.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/rtree/trace/rtc_packet.h"
