/* The overlap criterion's keys with AVX2 (rtree_choose_overlap.h): eight
 * entries a vector, the siblings one after another, so each lane adds its
 * terms in the baseline kernel's order. */
#include "accel/rtree/build/rtree_choose_overlap.h"

#if defined(TT_HAVE_X86_KERNELS)
#include <immintrin.h>

void rt_overlap_keys_avx2(const float *s, int cap, int cnt, const float e[6], rt_overlap_keys *k)
{
    const float *lx = s, *ly = s + cap, *lz = s + 2 * cap;
    const float *hx = s + 3 * cap, *hy = s + 4 * cap, *hz = s + 5 * cap;
    const __m256 zero = _mm256_setzero_ps(), two = _mm256_set1_ps(2.0f);
    const __m256 e0 = _mm256_set1_ps(e[0]), e1 = _mm256_set1_ps(e[1]), e2 = _mm256_set1_ps(e[2]);
    const __m256 e3 = _mm256_set1_ps(e[3]), e4 = _mm256_set1_ps(e[4]), e5 = _mm256_set1_ps(e[5]);
    const __m256i step = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (int i = 0; i < cnt; i += 8) {
        const __m256i lane = _mm256_add_epi32(_mm256_set1_epi32(i), step);
        /* lanes of real entries only: the rows end at cap, a multiple of 4 */
        const __m256i live = _mm256_cmpgt_epi32(_mm256_set1_epi32(cnt), lane);
        const __m256 Lx = _mm256_maskload_ps(lx + i, live), Ly = _mm256_maskload_ps(ly + i, live);
        const __m256 Lz = _mm256_maskload_ps(lz + i, live), Hx = _mm256_maskload_ps(hx + i, live);
        const __m256 Hy = _mm256_maskload_ps(hy + i, live), Hz = _mm256_maskload_ps(hz + i, live);
        const __m256 Ux = _mm256_min_ps(Lx, e0), Uy = _mm256_min_ps(Ly, e1), Uz = _mm256_min_ps(Lz, e2);
        const __m256 Vx = _mm256_max_ps(Hx, e3), Vy = _mm256_max_ps(Hy, e4), Vz = _mm256_max_ps(Hz, e5);
        __m256 d = zero, own = zero;
        for (int j = 0; j < cnt; j++) {
            const __m256 jlx = _mm256_broadcast_ss(lx + j), jly = _mm256_broadcast_ss(ly + j);
            const __m256 jlz = _mm256_broadcast_ss(lz + j), jhx = _mm256_broadcast_ss(hx + j);
            const __m256 jhy = _mm256_broadcast_ss(hy + j), jhz = _mm256_broadcast_ss(hz + j);
            const __m256 self = _mm256_castsi256_ps(_mm256_cmpeq_epi32(lane, _mm256_set1_epi32(j)));
            const __m256 gx = _mm256_sub_ps(_mm256_min_ps(Vx, jhx), _mm256_max_ps(Ux, jlx));
            const __m256 gy = _mm256_sub_ps(_mm256_min_ps(Vy, jhy), _mm256_max_ps(Uy, jly));
            const __m256 gz = _mm256_sub_ps(_mm256_min_ps(Vz, jhz), _mm256_max_ps(Uz, jlz));
            const __m256 gm = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(gx, zero, _CMP_GT_OS),
                                                          _mm256_cmp_ps(gy, zero, _CMP_GT_OS)),
                                            _mm256_cmp_ps(gz, zero, _CMP_GT_OS));
            const __m256 go = _mm256_and_ps(gm, _mm256_mul_ps(_mm256_mul_ps(gx, gy), gz));
            const __m256 ox = _mm256_sub_ps(_mm256_min_ps(Hx, jhx), _mm256_max_ps(Lx, jlx));
            const __m256 oy = _mm256_sub_ps(_mm256_min_ps(Hy, jhy), _mm256_max_ps(Ly, jly));
            const __m256 oz = _mm256_sub_ps(_mm256_min_ps(Hz, jhz), _mm256_max_ps(Lz, jlz));
            const __m256 om = _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(ox, zero, _CMP_GT_OS),
                                                          _mm256_cmp_ps(oy, zero, _CMP_GT_OS)),
                                            _mm256_cmp_ps(oz, zero, _CMP_GT_OS));
            const __m256 oo = _mm256_and_ps(om, _mm256_mul_ps(_mm256_mul_ps(ox, oy), oz));
            d = _mm256_add_ps(d, _mm256_andnot_ps(self, go));
            own = _mm256_add_ps(own, _mm256_andnot_ps(self, oo));
        }
        _mm256_storeu_ps(k->dov + i, _mm256_sub_ps(d, own));
        const __m256 ex = _mm256_sub_ps(Hx, Lx), ey = _mm256_sub_ps(Hy, Ly), ez = _mm256_sub_ps(Hz, Lz);
        const __m256 ux = _mm256_sub_ps(Vx, Ux), uy = _mm256_sub_ps(Vy, Uy), uz = _mm256_sub_ps(Vz, Uz);
        const __m256 a = _mm256_mul_ps(
            two, _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ex, ey), _mm256_mul_ps(ey, ez)),
                               _mm256_mul_ps(ez, ex)));
        const __m256 ua = _mm256_mul_ps(
            two, _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ux, uy), _mm256_mul_ps(uy, uz)),
                               _mm256_mul_ps(uz, ux)));
        const __m256 v = _mm256_mul_ps(_mm256_mul_ps(ex, ey), ez);
        const __m256 uv = _mm256_mul_ps(_mm256_mul_ps(ux, uy), uz);
        _mm256_storeu_ps(k->area + i, a);
        _mm256_storeu_ps(k->darea + i, _mm256_sub_ps(ua, a));
        _mm256_storeu_ps(k->vol + i, v);
        _mm256_storeu_ps(k->dvol + i, _mm256_sub_ps(uv, v));
    }
}
#endif
