/* The kd-tree's packet traversal (kd_packet.h) with 16 rays per AVX-512
 * register; mask registers hold a vector's lanes. Compiled with the
 * AVX-512 flags and -ffp-contract=off (no FMA: every lane rounds as the
 * single-ray kernels do). */
#include "accel/kdtree/trace/kd_packet_cpu.h"

#if defined(TT_HAVE_X86_KERNELS)
#include <immintrin.h>
#include <math.h>

#include "accel/kdtree/trace/kd_trace_cpu.h"

#define KD_FN(name) name##_avx512
#define PK_L 16
typedef __m512 pk_v;
typedef __mmask16 pk_m;
typedef __m512i pk_vi;
/* lanes a[idx] (idx < 16) or b[idx - 16] */
#define PK_PERM2(idx, a, b) _mm512_permutex2var_ps(a, idx, b)
#define PK_LOAD(p) _mm512_load_ps(p)
#define PK_LOADU(p) _mm512_loadu_ps(p)
#define PK_STORE(p, x) _mm512_store_ps(p, x)
#define PK_LOADI(p) _mm512_load_si512((const void *)(p))
#define PK_STOREI(p, x) _mm512_store_si512((void *)(p), x)
#define PK_SET1(x) _mm512_set1_ps(x)
#define PK_ADD _mm512_add_ps
#define PK_SUB _mm512_sub_ps
#define PK_MUL _mm512_mul_ps
#define PK_DIV _mm512_div_ps
/* min(a, b) = a < b ? a : b and max(a, b) = a > b ? a : b, NaN included:
 * tt_kd_min / tt_kd_max exactly */
#define PK_MIN _mm512_min_ps
#define PK_MAX _mm512_max_ps
#define PK_CMP_LT(a, b) _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ)
#define PK_CMP_GT(a, b) _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ)
#define PK_CMP_GE(a, b) _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ)
#define PK_CMP_EQ(a, b) _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ)
#define PK_CMP_LE(a, b) _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ)
#define PK_ANDNOT(a, b) _mm512_andnot_ps(a, b) /* not a, and b (bits) */
#define PK_SETI(x) _mm512_set1_epi32((int)(x))
/* (a ^ b) | (a ^ c), bitwise; the lanes whose sign bit is set */
#define PK_XOR_OR(a, b, c) _mm512_or_ps(_mm512_xor_ps(a, b), _mm512_xor_ps(a, c))
#define PK_SIGNS(x) ((uint32_t)_mm512_movepi32_mask(_mm512_castps_si512(x)))
#define PK_CMP_NEQ(a, b) _mm512_cmp_ps_mask(a, b, _CMP_NEQ_UQ)
#define PK_MAND(a, b) ((pk_m)((a) & (b)))
#define PK_MOR(a, b) ((pk_m)((a) | (b)))
#define PK_MANDNOT(a, b) ((pk_m)(~(a) & (b))) /* not a, and b */
#define PK_BITS(m) ((uint32_t)(m))
#define PK_MASK(bits) ((pk_m)(bits))
#define PK_BLEND(m, a, b) _mm512_mask_blend_ps(m, a, b) /* m ? b : a */
#define PK_BLENDI(m, a, x) _mm512_mask_blend_epi32(m, a, _mm512_set1_epi32((int)(x)))
/* kp_multi: a block's row of eight triangles' coordinates in the lower
 * half (the upper is never picked), two blocks' rows side by side, lanes
 * picked from a vector, 32-bit integers added */
#define PK_ROW(p) _mm512_castps256_ps512(_mm256_load_ps(p))
#define PK_ROW2(p, q) _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_load_ps(p)), _mm256_load_ps(q), 1)
#define PK_PERMX(idx, a) _mm512_permutexvar_ps(idx, a)
#define PK_PERMXI(idx, a) _mm512_permutexvar_epi32(idx, a)
#define PK_ADDI _mm512_add_epi32

#define KD_SINGLE_INTERSECT tt_kd_avx512_intersect
#define KD_SINGLE_OCCLUDED tt_kd_avx512_occluded

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_packet.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "accel/kdtree/trace/kd_packet.h"
#endif
