/* The kd-tree's packet traversal (kd_packet.h) with 8 rays per AVX2
 * register; compare results stay vectors (movemask gives a vector's lane
 * bits). Compiled with the AVX2 flags and -ffp-contract=off (no FMA: every
 * lane rounds as the single-ray kernels do). */
#include "accel/kdtree/trace/kd_packet_cpu.h"

#if defined(TT_HAVE_X86_KERNELS)
#include <immintrin.h>
#include <math.h>

#include "accel/kdtree/trace/kd_trace_cpu.h"

#define KD_FN(name) name##_avx2
#define PK_L 8
typedef __m256 pk_v;
typedef __m256 pk_m;
typedef __m256i pk_vi;
/* lanes a[idx] (idx < 8) or b[idx - 8]: bit 3 of idx, shifted into the
 * sign bit, picks b */
#define PK_PERM2(idx, a, b)                                                                      \
    _mm256_blendv_ps(_mm256_permutevar8x32_ps(a, idx), _mm256_permutevar8x32_ps(b, idx),         \
                     _mm256_castsi256_ps(_mm256_slli_epi32(idx, 28)))
#define PK_LOAD(p) _mm256_load_ps(p)
#define PK_LOADU(p) _mm256_loadu_ps(p)
#define PK_STORE(p, x) _mm256_store_ps(p, x)
#define PK_LOADI(p) _mm256_load_si256((const __m256i *)(const void *)(p))
#define PK_STOREI(p, x) _mm256_store_si256((__m256i *)(void *)(p), x)
#define PK_SET1(x) _mm256_set1_ps(x)
#define PK_ADD _mm256_add_ps
#define PK_SUB _mm256_sub_ps
#define PK_MUL _mm256_mul_ps
#define PK_DIV _mm256_div_ps
/* min(a, b) = a < b ? a : b and max(a, b) = a > b ? a : b, NaN included:
 * tt_kd_min / tt_kd_max exactly */
#define PK_MIN _mm256_min_ps
#define PK_MAX _mm256_max_ps
#define PK_CMP_LT(a, b) _mm256_cmp_ps(a, b, _CMP_LT_OQ)
#define PK_CMP_GT(a, b) _mm256_cmp_ps(a, b, _CMP_GT_OQ)
#define PK_CMP_GE(a, b) _mm256_cmp_ps(a, b, _CMP_GE_OQ)
#define PK_CMP_EQ(a, b) _mm256_cmp_ps(a, b, _CMP_EQ_OQ)
#define PK_CMP_LE(a, b) _mm256_cmp_ps(a, b, _CMP_LE_OQ)
#define PK_ANDNOT(a, b) _mm256_andnot_ps(a, b) /* not a, and b (bits) */
#define PK_SETI(x) _mm256_set1_epi32((int)(x))
/* (a ^ b) | (a ^ c), bitwise; the lanes whose sign bit is set */
#define PK_XOR_OR(a, b, c) _mm256_or_ps(_mm256_xor_ps(a, b), _mm256_xor_ps(a, c))
#define PK_SIGNS(x) ((uint32_t)_mm256_movemask_ps(x))
#define PK_CMP_NEQ(a, b) _mm256_cmp_ps(a, b, _CMP_NEQ_UQ)
#define PK_MAND _mm256_and_ps
#define PK_MOR _mm256_or_ps
#define PK_MANDNOT _mm256_andnot_ps /* not a, and b */
#define PK_BITS(m) ((uint32_t)_mm256_movemask_ps(m))
static inline __m256 kp_mask_avx2(uint32_t bits)
{
    const __m256i lane = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(
        _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32((int)bits), lane), lane));
}
#define PK_MASK(bits) kp_mask_avx2(bits)
#define PK_BLEND(m, a, b) _mm256_blendv_ps(a, b, m) /* m ? b : a */
#define PK_BLENDI(m, a, x)                                                                       \
    _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(a),                                \
                                         _mm256_castsi256_ps(_mm256_set1_epi32((int)(x))), m))

/* kp_multi: a block's row of eight triangles' coordinates, lanes picked
 * from a vector, 32-bit integers added */
#define PK_ROW(p) _mm256_load_ps(p)
#define PK_PERMX(idx, a) _mm256_permutevar8x32_ps(a, idx)
#define PK_PERMXI(idx, a) _mm256_permutevar8x32_epi32(a, idx)
#define PK_ADDI _mm256_add_epi32
#define KD_SINGLE_INTERSECT tt_kd_avx2_intersect
#define KD_SINGLE_OCCLUDED tt_kd_avx2_occluded

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_packet.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_packet.h"
#endif
