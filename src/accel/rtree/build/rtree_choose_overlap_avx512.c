/* The overlap criterion's keys with AVX-512 (rtree_choose_overlap.h): all
 * entries of a node (M <= 16) in one 16-lane vector, the siblings one after
 * another, so each lane adds its terms in the baseline kernel's order. */
#include "accel/rtree/build/rtree_choose_overlap.h"

#if defined(TT_HAVE_X86_KERNELS)
#include <immintrin.h>

void rt_overlap_keys_avx512(const float *s, int cap, int cnt, const float e[6], rt_overlap_keys *k)
{
    const float *lx = s, *ly = s + cap, *lz = s + 2 * cap;
    const float *hx = s + 3 * cap, *hy = s + 4 * cap, *hz = s + 5 * cap;
    const __m512 zero = _mm512_setzero_ps(), two = _mm512_set1_ps(2.0f);
    const __m512 e0 = _mm512_set1_ps(e[0]), e1 = _mm512_set1_ps(e[1]), e2 = _mm512_set1_ps(e[2]);
    const __m512 e3 = _mm512_set1_ps(e[3]), e4 = _mm512_set1_ps(e[4]), e5 = _mm512_set1_ps(e[5]);
    for (int i = 0; i < cnt; i += 16) {
        const int left = cnt - i;
        const __mmask16 live = left >= 16 ? (__mmask16)0xffff : (__mmask16)((1u << left) - 1u);
        const __m512 Lx = _mm512_maskz_loadu_ps(live, lx + i), Ly = _mm512_maskz_loadu_ps(live, ly + i);
        const __m512 Lz = _mm512_maskz_loadu_ps(live, lz + i), Hx = _mm512_maskz_loadu_ps(live, hx + i);
        const __m512 Hy = _mm512_maskz_loadu_ps(live, hy + i), Hz = _mm512_maskz_loadu_ps(live, hz + i);
        const __m512 Ux = _mm512_min_ps(Lx, e0), Uy = _mm512_min_ps(Ly, e1), Uz = _mm512_min_ps(Lz, e2);
        const __m512 Vx = _mm512_max_ps(Hx, e3), Vy = _mm512_max_ps(Hy, e4), Vz = _mm512_max_ps(Hz, e5);
        __m512 d = zero, own = zero;
        for (int j = 0; j < cnt; j++) {
            const __m512 jlx = _mm512_set1_ps(lx[j]), jly = _mm512_set1_ps(ly[j]);
            const __m512 jlz = _mm512_set1_ps(lz[j]), jhx = _mm512_set1_ps(hx[j]);
            const __m512 jhy = _mm512_set1_ps(hy[j]), jhz = _mm512_set1_ps(hz[j]);
            /* every lane but entry j itself */
            const __mmask16 other = (j - i >= 0 && j - i < 16) ? (__mmask16)~(1u << (j - i))
                                                               : (__mmask16)0xffff;
            const __m512 gx = _mm512_sub_ps(_mm512_min_ps(Vx, jhx), _mm512_max_ps(Ux, jlx));
            const __m512 gy = _mm512_sub_ps(_mm512_min_ps(Vy, jhy), _mm512_max_ps(Uy, jly));
            const __m512 gz = _mm512_sub_ps(_mm512_min_ps(Vz, jhz), _mm512_max_ps(Uz, jlz));
            __mmask16 gm = _mm512_mask_cmp_ps_mask(other, gx, zero, _CMP_GT_OS);
            gm = _mm512_mask_cmp_ps_mask(gm, gy, zero, _CMP_GT_OS);
            gm = _mm512_mask_cmp_ps_mask(gm, gz, zero, _CMP_GT_OS);
            /* a masked-off lane adds nothing, as the +0 of the other kernels */
            d = _mm512_mask_add_ps(d, gm, d, _mm512_mul_ps(_mm512_mul_ps(gx, gy), gz));
            const __m512 ox = _mm512_sub_ps(_mm512_min_ps(Hx, jhx), _mm512_max_ps(Lx, jlx));
            const __m512 oy = _mm512_sub_ps(_mm512_min_ps(Hy, jhy), _mm512_max_ps(Ly, jly));
            const __m512 oz = _mm512_sub_ps(_mm512_min_ps(Hz, jhz), _mm512_max_ps(Lz, jlz));
            __mmask16 om = _mm512_mask_cmp_ps_mask(other, ox, zero, _CMP_GT_OS);
            om = _mm512_mask_cmp_ps_mask(om, oy, zero, _CMP_GT_OS);
            om = _mm512_mask_cmp_ps_mask(om, oz, zero, _CMP_GT_OS);
            own = _mm512_mask_add_ps(own, om, own, _mm512_mul_ps(_mm512_mul_ps(ox, oy), oz));
        }
        _mm512_storeu_ps(k->dov + i, _mm512_sub_ps(d, own));
        const __m512 ex = _mm512_sub_ps(Hx, Lx), ey = _mm512_sub_ps(Hy, Ly), ez = _mm512_sub_ps(Hz, Lz);
        const __m512 ux = _mm512_sub_ps(Vx, Ux), uy = _mm512_sub_ps(Vy, Uy), uz = _mm512_sub_ps(Vz, Uz);
        const __m512 a = _mm512_mul_ps(
            two, _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(ex, ey), _mm512_mul_ps(ey, ez)),
                               _mm512_mul_ps(ez, ex)));
        const __m512 ua = _mm512_mul_ps(
            two, _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(ux, uy), _mm512_mul_ps(uy, uz)),
                               _mm512_mul_ps(uz, ux)));
        const __m512 v = _mm512_mul_ps(_mm512_mul_ps(ex, ey), ez);
        const __m512 uv = _mm512_mul_ps(_mm512_mul_ps(ux, uy), uz);
        _mm512_storeu_ps(k->area + i, a);
        _mm512_storeu_ps(k->darea + i, _mm512_sub_ps(ua, a));
        _mm512_storeu_ps(k->vol + i, v);
        _mm512_storeu_ps(k->dvol + i, _mm512_sub_ps(uv, v));
    }
}
#endif
