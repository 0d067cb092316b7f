/* Rows to prepared single rays: a group of up to TT_WRAY_ROWS rows of a
 * tt_packet_rays as tt_wray's, each bit for bit what tt_wray_init makes of
 * its row. For the kernels' rows entries (the vtable's intersect_rows /
 * occluded_rows): the batch used to build each ray's tt_wray one by one
 * (nine divisions, the shear's selects) before two indirect calls.
 *
 * Included by each ISA unit: where the unit's flags have AVX2 (the AVX2
 * and AVX-512 units) eight rows at once, with tt_wray_init's IEEE
 * operations lane by lane (1 / d, tt_safe_inv's select, the dominant
 * axis's compares, d[kx] / d[kz]; no multiply, so nothing to contract),
 * the lanes then turned into structures by transposes; elsewhere
 * tt_wray_init row by row. The packet units (rtc_packet.h, kd_packet.h)
 * compute the same reciprocals and shear into their own rows. */
#ifndef TT_ACCEL_WRAY_ROWS_H
#define TT_ACCEL_WRAY_ROWS_H

#include <stddef.h>
#include <stdint.h>

#include "accel/accel.h"
#include "geometry/ray.h"

#define TT_WRAY_ROWS 8u

#if defined(__AVX2__)
#include <immintrin.h>

/* the transposes below write a tt_wray as 8 + 8 + 4 consecutive words */
_Static_assert(sizeof(tt_wray) == 20 * sizeof(float), "tt_wray is 20 words");
_Static_assert(offsetof(tt_wray, inv) == 6 * sizeof(float) &&
                   offsetof(tt_wray, tmin) == 12 * sizeof(float) &&
                   offsetof(tt_wray, kx) == 14 * sizeof(float) &&
                   offsetof(tt_wray, kz) == 16 * sizeof(float) &&
                   offsetof(tt_wray, sz) == 19 * sizeof(float),
               "tt_wray's field order");

/* r[k] lane l -> o[l] lane k */
static inline void tt_wray_rows_t8(const __m256 r[8], __m256 o[8])
{
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
    const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
    const __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xee);
    const __m256 s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xee);
    const __m256 s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xee);
    const __m256 s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xee);
    o[0] = _mm256_permute2f128_ps(s0, s4, 0x20);
    o[1] = _mm256_permute2f128_ps(s1, s5, 0x20);
    o[2] = _mm256_permute2f128_ps(s2, s6, 0x20);
    o[3] = _mm256_permute2f128_ps(s3, s7, 0x20);
    o[4] = _mm256_permute2f128_ps(s0, s4, 0x31);
    o[5] = _mm256_permute2f128_ps(s1, s5, 0x31);
    o[6] = _mm256_permute2f128_ps(s2, s6, 0x31);
    o[7] = _mm256_permute2f128_ps(s3, s7, 0x31);
}

/* Rows first .. first + 7 (first a multiple of 8, so whole aligned vectors
 * inside the rows, which a kernel may read past n) into w[0..8); returns
 * how many of them are rays (rows below R->n). Lanes past n compute
 * whatever the rows hold there; their structures are never traced. */
static inline uint32_t tt_wray_rows(const tt_packet_rays *R, uint32_t first,
                                    tt_wray w[TT_WRAY_ROWS])
{
    const __m256 x = _mm256_load_ps(R->dir[0] + first), y = _mm256_load_ps(R->dir[1] + first),
                 z = _mm256_load_ps(R->dir[2] + first);
    const __m256 one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
    const __m256 sign = _mm256_set1_ps(-0.0f), tiny = _mm256_set1_ps(1e-30f),
                 big = _mm256_set1_ps(1e30f);
    const __m256 ax = _mm256_andnot_ps(sign, x), ay = _mm256_andnot_ps(sign, y),
                 az = _mm256_andnot_ps(sign, z);
    /* tt_safe_inv: copysignf(1e30f, d) where |d| < 1e-30, else 1 / d */
    const __m256 rx = _mm256_div_ps(one, x), ry = _mm256_div_ps(one, y),
                 rz = _mm256_div_ps(one, z);
#define TT_WRAY_SAFE(d, a, r)                                                                    \
    _mm256_blendv_ps(r, _mm256_or_ps(_mm256_and_ps(d, sign), big),                               \
                     _mm256_cmp_ps(a, tiny, _CMP_LT_OQ))
    const __m256 ix = TT_WRAY_SAFE(x, ax, rx), iy = TT_WRAY_SAFE(y, ay, ry),
                 iz = TT_WRAY_SAFE(z, az, rz);
#undef TT_WRAY_SAFE
    /* the shear: kz the dominant axis (x wins ties, then y), kx, ky the
     * next ones cyclically, swapped where d[kz] < 0 */
    const __m256 m0 = _mm256_and_ps(_mm256_cmp_ps(ax, ay, _CMP_GE_OQ),
                                    _mm256_cmp_ps(ax, az, _CMP_GE_OQ));
    const __m256 m1 = _mm256_andnot_ps(m0, _mm256_cmp_ps(ay, az, _CMP_GE_OQ));
    const __m256 dkz = _mm256_blendv_ps(_mm256_blendv_ps(z, y, m1), x, m0);
    const __m256 dkx = _mm256_blendv_ps(_mm256_blendv_ps(x, z, m1), y, m0);
    const __m256 dky = _mm256_blendv_ps(_mm256_blendv_ps(y, x, m1), z, m0);
    const __m256 neg = _mm256_cmp_ps(dkz, zero, _CMP_LT_OQ);
    const __m256 sx = _mm256_div_ps(_mm256_blendv_ps(dkx, dky, neg), dkz);
    const __m256 sy = _mm256_div_ps(_mm256_blendv_ps(dky, dkx, neg), dkz);
    const __m256 sz = _mm256_div_ps(one, dkz);
#define TT_WRAY_I(v) _mm256_castsi256_ps(_mm256_set1_epi32(v))
    const __m256 kz = _mm256_blendv_ps(_mm256_blendv_ps(TT_WRAY_I(2), TT_WRAY_I(1), m1),
                                       TT_WRAY_I(0), m0);
    const __m256 kx0 = _mm256_blendv_ps(_mm256_blendv_ps(TT_WRAY_I(0), TT_WRAY_I(2), m1),
                                        TT_WRAY_I(1), m0);
    const __m256 ky0 = _mm256_blendv_ps(_mm256_blendv_ps(TT_WRAY_I(1), TT_WRAY_I(0), m1),
                                        TT_WRAY_I(2), m0);
#undef TT_WRAY_I
    const __m256 kx = _mm256_blendv_ps(kx0, ky0, neg), ky = _mm256_blendv_ps(ky0, kx0, neg);
    const __m256 a[8] = {_mm256_load_ps(R->org[0] + first), _mm256_load_ps(R->org[1] + first),
                         _mm256_load_ps(R->org[2] + first), x, y, z, ix, iy};
    const __m256 b[8] = {iz, rx, ry, rz, _mm256_load_ps(R->tmin + first),
                         _mm256_load_ps(R->tmax + first), kx, ky};
    __m256 ta[8], tb[8];
    tt_wray_rows_t8(a, ta);
    tt_wray_rows_t8(b, tb);
    /* kz sx sy sz: four words a ray */
    const __m256 u0 = _mm256_unpacklo_ps(kz, sx), u1 = _mm256_unpackhi_ps(kz, sx);
    const __m256 u2 = _mm256_unpacklo_ps(sy, sz), u3 = _mm256_unpackhi_ps(sy, sz);
    const __m256 c[4] = {_mm256_shuffle_ps(u0, u2, 0x44), _mm256_shuffle_ps(u0, u2, 0xee),
                         _mm256_shuffle_ps(u1, u3, 0x44), _mm256_shuffle_ps(u1, u3, 0xee)};
    for (uint32_t l = 0; l < 8; l++) {
        float *const p = (float *)(void *)&w[l];
        _mm256_storeu_ps(p, ta[l]);
        _mm256_storeu_ps(p + 8, tb[l]);
        _mm_storeu_ps(p + 16, l < 4 ? _mm256_castps256_ps128(c[l])
                                    : _mm256_extractf128_ps(c[l - 4], 1));
    }
    const uint32_t left = R->n - first;
    return left < TT_WRAY_ROWS ? left : TT_WRAY_ROWS;
}

#else

static inline uint32_t tt_wray_rows(const tt_packet_rays *R, uint32_t first,
                                    tt_wray w[TT_WRAY_ROWS])
{
    const uint32_t left = R->n - first, c = left < TT_WRAY_ROWS ? left : TT_WRAY_ROWS;
    for (uint32_t l = 0; l < c; l++) tt_packet_ray_wray(R, first + l, &w[l]);
    return c;
}

#endif

#endif
