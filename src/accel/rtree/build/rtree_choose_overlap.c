/* The overlap criterion of choose_entry (rtree_build.c): which entry of node
 * n receives box e when the strategy minimises the overlap enlargement
 * (min-overlap everywhere, the R* variants just above the leaves). Keys,
 * compared lexicographically, the first entry winning ties:
 *   min-overlap, rstar:  d overlap, d volume, volume, d surface, surface
 *   rstar-surface:       d overlap, d surface, surface
 * where d overlap of entry i is the sum over its siblings j of
 * overlap(entry i grown by e, j) minus the sum of overlap(entry i, j).
 *
 * Speed: the O(cnt^2) overlap sums are the cost of the whole insertion
 * build (69% of its instructions at M 16). They run over the node's
 * structure-of-arrays bounds four entries i at a time, the siblings j one
 * after another, so every lane adds its terms in the same order (j
 * ascending) as the scalar definition: the same sums to the bit, the same
 * tree. A term of a lane with itself (j == i) is masked to +0, which adds
 * nothing to sums of non-negative terms. */
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/rtree/build/rtree_choose_overlap.h"
#include "accel/rtree/rtree_box.h"

#define MAX_KEYS 5

static int keys_less(const float *a, const float *b, int n)
{
    for (int i = 0; i < n; i++) {
        if (a[i] < b[i]) return 1;
        if (a[i] > b[i]) return 0;
    }
    return 0;
}

void rt_overlap_keys_sse2(const float *s, int cap, int cnt, const float e[6], rt_overlap_keys *k)
{
    /* per entry: d overlap, d volume, volume, d surface, surface (the
     * surface with the factor 2 of rt_box_area, as the scalar code had) */
#if defined(__SSE2__)
    const float *lx = s, *ly = s + cap, *lz = s + 2 * cap;
    const float *hx = s + 3 * cap, *hy = s + 4 * cap, *hz = s + 5 * cap;
    const __m128 zero = _mm_setzero_ps(), two = _mm_set1_ps(2.0f);
    const __m128 e0 = _mm_set1_ps(e[0]), e1 = _mm_set1_ps(e[1]), e2 = _mm_set1_ps(e[2]);
    const __m128 e3 = _mm_set1_ps(e[3]), e4 = _mm_set1_ps(e[4]), e5 = _mm_set1_ps(e[5]);
    for (int i = 0; i < cnt; i += 4) {
        const __m128 Lx = _mm_loadu_ps(lx + i), Ly = _mm_loadu_ps(ly + i);
        const __m128 Lz = _mm_loadu_ps(lz + i), Hx = _mm_loadu_ps(hx + i);
        const __m128 Hy = _mm_loadu_ps(hy + i), Hz = _mm_loadu_ps(hz + i);
        /* entry i grown by e */
        const __m128 Ux = _mm_min_ps(Lx, e0), Uy = _mm_min_ps(Ly, e1), Uz = _mm_min_ps(Lz, e2);
        const __m128 Vx = _mm_max_ps(Hx, e3), Vy = _mm_max_ps(Hy, e4), Vz = _mm_max_ps(Hz, e5);
        const __m128i lane = _mm_add_epi32(_mm_set1_epi32(i), _mm_set_epi32(3, 2, 1, 0));
        __m128 d = zero, own = zero;
        for (int j = 0; j < cnt; j++) {
            const __m128 jlx = _mm_set1_ps(lx[j]), jly = _mm_set1_ps(ly[j]);
            const __m128 jlz = _mm_set1_ps(lz[j]), jhx = _mm_set1_ps(hx[j]);
            const __m128 jhy = _mm_set1_ps(hy[j]), jhz = _mm_set1_ps(hz[j]);
            const __m128 self =
                _mm_castsi128_ps(_mm_cmpeq_epi32(lane, _mm_set1_epi32(j)));
            /* overlap(grown i, j): rt_box_overlap's (ex * ey) * ez where
             * every extent is positive, else 0 */
            __m128 gx = _mm_sub_ps(_mm_min_ps(Vx, jhx), _mm_max_ps(Ux, jlx));
            __m128 gy = _mm_sub_ps(_mm_min_ps(Vy, jhy), _mm_max_ps(Uy, jly));
            __m128 gz = _mm_sub_ps(_mm_min_ps(Vz, jhz), _mm_max_ps(Uz, jlz));
            __m128 gm = _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(gx, zero), _mm_cmpgt_ps(gy, zero)),
                                   _mm_cmpgt_ps(gz, zero));
            __m128 go = _mm_and_ps(gm, _mm_mul_ps(_mm_mul_ps(gx, gy), gz));
            /* overlap(i, j) */
            __m128 ox = _mm_sub_ps(_mm_min_ps(Hx, jhx), _mm_max_ps(Lx, jlx));
            __m128 oy = _mm_sub_ps(_mm_min_ps(Hy, jhy), _mm_max_ps(Ly, jly));
            __m128 oz = _mm_sub_ps(_mm_min_ps(Hz, jhz), _mm_max_ps(Lz, jlz));
            __m128 om = _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(ox, zero), _mm_cmpgt_ps(oy, zero)),
                                   _mm_cmpgt_ps(oz, zero));
            __m128 oo = _mm_and_ps(om, _mm_mul_ps(_mm_mul_ps(ox, oy), oz));
            d = _mm_add_ps(d, _mm_andnot_ps(self, go));
            own = _mm_add_ps(own, _mm_andnot_ps(self, oo));
        }
        _mm_storeu_ps(k->dov + i, _mm_sub_ps(d, own));
        const __m128 ex = _mm_sub_ps(Hx, Lx), ey = _mm_sub_ps(Hy, Ly), ez = _mm_sub_ps(Hz, Lz);
        const __m128 ux = _mm_sub_ps(Vx, Ux), uy = _mm_sub_ps(Vy, Uy), uz = _mm_sub_ps(Vz, Uz);
        const __m128 a = _mm_mul_ps(two, _mm_add_ps(_mm_add_ps(_mm_mul_ps(ex, ey), _mm_mul_ps(ey, ez)),
                                                    _mm_mul_ps(ez, ex)));
        const __m128 ua = _mm_mul_ps(two, _mm_add_ps(_mm_add_ps(_mm_mul_ps(ux, uy), _mm_mul_ps(uy, uz)),
                                                     _mm_mul_ps(uz, ux)));
        const __m128 v = _mm_mul_ps(_mm_mul_ps(ex, ey), ez);
        const __m128 uv = _mm_mul_ps(_mm_mul_ps(ux, uy), uz);
        _mm_storeu_ps(k->area + i, a);
        _mm_storeu_ps(k->darea + i, _mm_sub_ps(ua, a));
        _mm_storeu_ps(k->vol + i, v);
        _mm_storeu_ps(k->dvol + i, _mm_sub_ps(uv, v));
    }
#else
    float ent[TT_RT_CAP][6], uni[TT_RT_CAP][6];
    for (int i = 0; i < cnt; i++) {
        rt_soa_get(s, cap, i, ent[i]);
        for (int k = 0; k < 3; k++) {
            uni[i][k] = rt_min(ent[i][k], e[k]);
            uni[i][k + 3] = rt_max(ent[i][k + 3], e[k + 3]);
        }
    }
    for (int i = 0; i < cnt; i++) {
        float d = 0.0f, own = 0.0f;
        for (int j = 0; j < cnt; j++)
            if (j != i) {
                d += rt_box_overlap(uni[i], ent[j]);
                own += rt_box_overlap(ent[i], ent[j]);
            }
        k->dov[i] = d - own;
        k->area[i] = rt_box_area(ent[i]);
        k->darea[i] = rt_box_area(uni[i]) - k->area[i];
        k->vol[i] = rt_box_volume(ent[i]);
        k->dvol[i] = rt_box_volume(uni[i]) - k->vol[i];
    }
#endif
}

rt_overlap_keys_fn rt_overlap_keys_best(void)
{
#if defined(TT_HAVE_X86_KERNELS)
    if (tt_isa_supported(TT_ISA_AVX512)) return rt_overlap_keys_avx512;
    if (tt_isa_supported(TT_ISA_AVX2)) return rt_overlap_keys_avx2;
#endif
    return rt_overlap_keys_sse2;
}

int rt_choose_overlap(const rt_builder *b, uint32_t n, const float e[6])
{
    const float *s = rt_node_box(b, n);
    const int cap = b->cap, cnt = b->hdr[n].count;
    const tt_rtree_strategy st = b->strategy;
    const float *lx = s, *ly = s + cap, *lz = s + 2 * cap;
    const float *hx = s + 3 * cap, *hy = s + 4 * cap, *hz = s + 5 * cap;

    /* An entry that already contains e has every enlargement 0, the least
     * possible value of all the leading keys: the smallest such entry wins
     * without the quadratic overlap sums. */
    int inside = -1;
    for (int i = 0; i < cnt; i++) {
        if (lx[i] <= e[0] && ly[i] <= e[1] && lz[i] <= e[2] && hx[i] >= e[3] && hy[i] >= e[4] &&
            hz[i] >= e[5]) {
            const float ex = hx[i] - lx[i], ey = hy[i] - ly[i], ez = hz[i] - lz[i];
            const float ix = hx[inside < 0 ? i : inside] - lx[inside < 0 ? i : inside];
            const float iy = hy[inside < 0 ? i : inside] - ly[inside < 0 ? i : inside];
            const float iz = hz[inside < 0 ? i : inside] - lz[inside < 0 ? i : inside];
            float key[2] = {ex * ey * ez, ex * ey + ey * ez + ez * ex};
            float best[2] = {ix * iy * iz, ix * iy + iy * iz + iz * ix};
            if (st == TT_RTREE_RSTAR_SURFACE) key[0] = best[0] = 0.0f;
            if (inside < 0 || keys_less(key, best, 2)) inside = i;
        }
    }
    if (inside >= 0) return inside;

    /* per entry: d overlap, d volume, volume, d surface, surface */
    rt_overlap_keys k;
    (b->overlap_keys ? b->overlap_keys : rt_overlap_keys_sse2)(s, cap, cnt, e, &k);
    float best[MAX_KEYS], key[MAX_KEYS];
    int best_i = 0;
    for (int i = 0; i < cnt; i++) {
        int nk = 0;
        key[nk++] = k.dov[i];
        if (st != TT_RTREE_RSTAR_SURFACE) {
            key[nk++] = k.dvol[i];
            key[nk++] = k.vol[i];
        }
        key[nk++] = k.darea[i];
        key[nk++] = k.area[i];
        if (i == 0 || keys_less(key, best, nk)) {
            memcpy(best, key, sizeof best);
            best_i = i;
        }
    }
    return best_i;
}
