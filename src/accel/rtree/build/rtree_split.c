/* Splitting an overflowing R-tree node of M + 1 entries into two groups of
 * at least m: the R*-tree's topological split (Beckmann et al. 1990) and
 * Guttman's quadratic split (1984), in 3D (area -> volume, margin ->
 * surface area).
 *
 * As in choose_entry, every volume-based comparison falls back to surface
 * area on ties, because flat boxes have zero volume and would otherwise
 * tie everywhere. */
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_build.h"

/* ------------------------------------------------------------ R* split */

/* Sorts entry indices by (primary bound, other bound) on an axis, ties in
 * index order: the order of a stable insertion sort, computed as ranks
 * (entry j goes before entry i when its key is less, or equal with j < i),
 * so without the insertion sort's data-dependent branches. The bounds are
 * rows a and o of the node's SoA boxes s; four entries i at a time where
 * SSE2 is available. The keys are never NaN, so the order is total and the
 * ranks are a permutation. */
static void sort_entries(const float *s, int cap, int cnt, int axis, int by_hi, int *order)
{
    const float *A = s + (by_hi ? axis + 3 : axis) * cap, *O = s + (by_hi ? axis : axis + 3) * cap;
    int rank[TT_RT_CAP + 3];
#if defined(__SSE2__)
    for (int i = 0; i < cnt; i += 4) {
        /* rows hold cap (a multiple of 4) floats: whole vectors stay in the row */
        const __m128 Ai = _mm_loadu_ps(A + i), Oi = _mm_loadu_ps(O + i);
        const __m128i idx = _mm_add_epi32(_mm_set1_epi32(i), _mm_set_epi32(3, 2, 1, 0));
        __m128i r = _mm_setzero_si128();
        for (int j = 0; j < cnt; j++) {
            const __m128 Aj = _mm_set1_ps(A[j]), Oj = _mm_set1_ps(O[j]);
            const __m128 jlt = _mm_castsi128_ps(_mm_cmpgt_epi32(idx, _mm_set1_epi32(j)));
            const __m128 tie = _mm_or_ps(_mm_cmplt_ps(Oj, Oi), _mm_and_ps(_mm_cmpeq_ps(Oj, Oi), jlt));
            const __m128 before =
                _mm_or_ps(_mm_cmplt_ps(Aj, Ai), _mm_and_ps(_mm_cmpeq_ps(Aj, Ai), tie));
            r = _mm_sub_epi32(r, _mm_castps_si128(before)); /* a true lane is -1 */
        }
        _mm_storeu_si128((__m128i *)(rank + i), r);
    }
#else
    for (int i = 0; i < cnt; i++) {
        int r = 0;
        for (int j = 0; j < cnt; j++)
            r += A[j] < A[i] || (A[j] == A[i] && (O[j] < O[i] || (O[j] == O[i] && j < i)));
        rank[i] = r;
    }
#endif
    for (int i = 0; i < cnt; i++) order[rank[i]] = i;
}

/* Prefix and suffix boxes of the entries in `order`: prefix[k] bounds the
 * first k, suffix[k] the rest (k = m .. cnt - m are used). */
static void prefix_suffix(float (*ent)[6], const int *order, int cnt, int m,
                          float (*prefix)[6], float (*suffix)[6])
{
    memcpy(prefix[1], ent[order[0]], sizeof prefix[1]);
    for (int k = 1; k < cnt - m; k++) {
        const float *e = ent[order[k]];
        for (int c = 0; c < 3; c++) {
            prefix[k + 1][c] = rt_min(prefix[k][c], e[c]);
            prefix[k + 1][c + 3] = rt_max(prefix[k][c + 3], e[c + 3]);
        }
    }
    memcpy(suffix[cnt - 1], ent[order[cnt - 1]], sizeof suffix[0]);
    for (int k = cnt - 2; k >= m; k--) {
        const float *e = ent[order[k]];
        for (int c = 0; c < 3; c++) {
            suffix[k][c] = rt_min(suffix[k + 1][c], e[c]);
            suffix[k][c + 3] = rt_max(suffix[k + 1][c + 3], e[c + 3]);
        }
    }
}

void rt_split_rstar(const rt_builder *b, uint32_t n, uint8_t *group)
{
    const int cnt = b->hdr[n].count, m = b->m, cap = b->cap;
    const float *s = rt_node_box(b, n);
    float ent[TT_RT_CAP][6];
    for (int i = 0; i < cnt; i++) rt_soa_get(s, cap, i, ent[i]);
    /* the distributions' boxes of every sort, kept for ChooseSplitIndex */
    float prefix[3][2][TT_RT_CAP + 1][6], suffix[3][2][TT_RT_CAP + 1][6];

    /* ChooseSplitAxis: the least sum of surface areas (margins) over all
     * distributions of both sorts. */
    int order[3][2][TT_RT_CAP];
    float best_margin = TT_INF;
    int axis = 0;
    for (int a = 0; a < 3; a++) {
        float margin = 0.0f;
        for (int by_hi = 0; by_hi < 2; by_hi++) {
            float(*pre)[6] = prefix[a][by_hi], (*suf)[6] = suffix[a][by_hi];
            sort_entries(s, cap, cnt, a, by_hi, order[a][by_hi]);
            prefix_suffix(ent, order[a][by_hi], cnt, m, pre, suf);
            for (int k = m; k <= cnt - m; k++) margin += rt_box_area(pre[k]) + rt_box_area(suf[k]);
        }
        if (margin < best_margin) {
            best_margin = margin;
            axis = a;
        }
    }
    /* ChooseSplitIndex on that axis: least overlap, then least volume, then
     * least surface area (the fallback for flat boxes). */
    float k0 = TT_INF, k1 = TT_INF, k2 = TT_INF;
    int best_sort = 0, best_k = m;
    for (int by_hi = 0; by_hi < 2; by_hi++) {
        float(*pre)[6] = prefix[axis][by_hi], (*suf)[6] = suffix[axis][by_hi];
        for (int k = m; k <= cnt - m; k++) {
            const float ov = rt_box_overlap(pre[k], suf[k]);
            if (ov > k0) continue;
            const float vol = rt_box_volume(pre[k]) + rt_box_volume(suf[k]);
            const float area = rt_box_area(pre[k]) + rt_box_area(suf[k]);
            if (ov < k0 || vol < k1 || (vol == k1 && area < k2)) {
                k0 = ov;
                k1 = vol;
                k2 = area;
                best_sort = by_hi;
                best_k = k;
            }
        }
    }
    const int *best = order[axis][best_sort];
    for (int k = 0; k < cnt; k++) group[best[k]] = k >= best_k;
}

/* ----------------------------------------------------- quadratic split */

/* A measure pair: volume first, surface area on ties. */
typedef struct measure {
    float vol, area;
} measure;

static measure measure_of(const float b[6])
{
    measure r = {rt_box_volume(b), rt_box_area(b)};
    return r;
}

static measure measure_sub(measure a, measure b)
{
    measure r = {a.vol - b.vol, a.area - b.area};
    return r;
}

static int measure_less(measure a, measure b)
{
    return a.vol < b.vol || (a.vol == b.vol && a.area < b.area);
}

static measure enlargement(const float box[6], const float e[6])
{
    float u[6];
    memcpy(u, box, sizeof u);
    rt_box_grow(u, e);
    return measure_sub(measure_of(u), measure_of(box));
}

void rt_split_quadratic(const rt_builder *b, uint32_t n, uint8_t *group)
{
    const int cnt = b->hdr[n].count, m = b->m, cap = b->cap;
    const float *s = rt_node_box(b, n);
    float ent[TT_RT_CAP][6];
    for (int i = 0; i < cnt; i++) rt_soa_get(s, cap, i, ent[i]);

    /* PickSeeds: the pair that would waste the most if grouped together. */
    int s1 = 0, s2 = 1;
    measure worst = {-TT_INF, -TT_INF};
    for (int i = 0; i < cnt; i++) {
        for (int j = i + 1; j < cnt; j++) {
            float u[6];
            memcpy(u, ent[i], sizeof u);
            rt_box_grow(u, ent[j]);
            measure d = measure_sub(measure_sub(measure_of(u), measure_of(ent[i])),
                                    measure_of(ent[j]));
            if (measure_less(worst, d)) {
                worst = d;
                s1 = i;
                s2 = j;
            }
        }
    }
    uint8_t assigned[TT_RT_CAP] = {0};
    float gbox[2][6];
    int gcount[2] = {1, 1};
    memcpy(gbox[0], ent[s1], sizeof gbox[0]);
    memcpy(gbox[1], ent[s2], sizeof gbox[1]);
    group[s1] = 0;
    group[s2] = 1;
    assigned[s1] = assigned[s2] = 1;
    int left = cnt - 2;
    while (left > 0) {
        /* a group that needs all the rest to reach m gets them */
        for (int g = 0; g < 2; g++) {
            if (gcount[g] + left == m) {
                for (int i = 0; i < cnt; i++)
                    if (!assigned[i]) {
                        group[i] = (uint8_t)g;
                        assigned[i] = 1;
                        gcount[g]++;
                    }
                left = 0;
            }
        }
        if (left == 0) break;
        /* PickNext: the entry with the strongest preference */
        int next = -1;
        measure pref = {-TT_INF, -TT_INF};
        measure d0n = {0, 0}, d1n = {0, 0};
        for (int i = 0; i < cnt; i++) {
            if (assigned[i]) continue;
            measure d0 = enlargement(gbox[0], ent[i]), d1 = enlargement(gbox[1], ent[i]);
            measure diff = {fabsf(d0.vol - d1.vol), fabsf(d0.area - d1.area)};
            if (next < 0 || measure_less(pref, diff)) {
                pref = diff;
                next = i;
                d0n = d0;
                d1n = d1;
            }
        }
        /* least enlargement, then smaller group box, then fewer entries */
        int g;
        if (measure_less(d0n, d1n)) g = 0;
        else if (measure_less(d1n, d0n)) g = 1;
        else {
            measure m0 = measure_of(gbox[0]), m1 = measure_of(gbox[1]);
            if (measure_less(m0, m1)) g = 0;
            else if (measure_less(m1, m0)) g = 1;
            else g = gcount[1] < gcount[0];
        }
        group[next] = (uint8_t)g;
        assigned[next] = 1;
        gcount[g]++;
        rt_box_grow(gbox[g], ent[next]);
        left--;
    }
}
