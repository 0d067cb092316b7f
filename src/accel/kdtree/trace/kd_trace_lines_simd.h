/* HTR over the node lines (kd_lines.h) with a whole line decided at once,
 * in AVX2: include after kd_trace_lines.h, only from the AVX2 / AVX-512
 * units.
 *
 * kd_trace_lines.h walks a line's three levels one plane test after the
 * other, a branch each. Here the seven planes' crossing distances are one
 * vector computation, and the three levels' decisions are lane arithmetic
 * over the eight exits (lane x = exit x): each exit gets the interval the
 * sequential walk would carry down to it and whether that walk would reach
 * it. The reachable exits are then pushed back to front (a table gives the
 * front-to-back order from the line's near sides, a second one packs the
 * reachable lanes), and the walk pops the next one.
 *
 * Same answers bit for bit: every plane's distance and band are the same
 * float operations as kd_trace_lines.h's; level by level, an exit's
 * interval is narrowed with the same min / max in the same order (maxps
 * and minps are tt_kd_max / tt_kd_min, NaN included), and an exit is
 * reachable exactly when the sequential walk's branches would lead to it.
 * Exits are visited in the sequential order. The one difference: the
 * sequential walk checks a deferred subtree against the closest hit once,
 * where this walk checks each of its exits, whose interval starts no
 * earlier; a cell that starts at or beyond the closest hit holds nothing
 * closer (ties keep the earlier hit), so it only skips work. */
#include <immintrin.h>

#include "accel/kdtree/trace/kd_line_order.h"

/* Pending exits: a line leaves at most 7 besides the one taken, and a
 * child line starts three levels deeper; + 8 for the full-width store. */
#define KD_LINES_SIMD_STACK (7 * (TT_KD_MAX_DEPTH / 3 + 1) + 8)

typedef struct kd_lines_simd_ray {
    __m256 org, inv, e; /* lanes 0..2: per axis; 3: a position without plane */
    __m256i down;       /* lanes 0..2: -1 where the ray moves down the axis   */
} kd_lines_simd_ray;

/* One level: lane x's position at this level is a lane of `pos`, x's side
 * there is `right` (-1: the right child). */
static inline void kd_lines_simd_level(__m256 lo, __m256 hi, __m256i down, __m256i none,
                                       __m256i pos, __m256i right, __m256 *reach, __m256 *ta,
                                       __m256 *tb)
{
    const __m256 plo = _mm256_permutevar8x32_ps(lo, pos);
    const __m256 phi = _mm256_permutevar8x32_ps(hi, pos);
    const __m256 pnone = _mm256_castsi256_ps(_mm256_permutevar8x32_epi32(none, pos));
    const __m256 far =
        _mm256_castsi256_ps(_mm256_xor_si256(_mm256_permutevar8x32_epi32(down, pos), right));
    /* Sequential: hi < ta: far child only; else lo > tb: near only; else
     * both (NaN: both). */
    const __m256 behind = _mm256_cmp_ps(phi, *ta, _CMP_LT_OQ);
    const __m256 ahead = _mm256_cmp_ps(plo, *tb, _CMP_GT_OQ);
    const __m256 near_ok = _mm256_andnot_ps(behind, _mm256_castsi256_ps(_mm256_set1_epi32(-1)));
    const __m256 far_ok = _mm256_or_ps(behind, _mm256_andnot_ps(ahead, near_ok));
    __m256 ok = _mm256_blendv_ps(near_ok, far_ok, far);
    /* No plane: on to the left child, interval unchanged. */
    ok = _mm256_blendv_ps(ok, _mm256_castsi256_ps(_mm256_xor_si256(right, _mm256_set1_epi32(-1))),
                          pnone);
    *reach = _mm256_and_ps(*reach, ok);
    /* Far child: [max(ta, lo), tb]; near child: [ta, min(tb, hi)] (with
     * one child only, these are the unchanged interval, as there). */
    *ta = _mm256_blendv_ps(*ta, _mm256_max_ps(*ta, plo), _mm256_andnot_ps(pnone, far));
    *tb = _mm256_blendv_ps(_mm256_min_ps(*tb, phi), *tb, _mm256_or_ps(pnone, far));
}

/* The next position of the walk: an exit and the ray's interval in it. */
typedef struct kd_lines_simd_next {
    uint32_t x;
    float ta, tb;
} kd_lines_simd_next;

/* Decides line L for the interval [ta0, tb0]: pushes its reachable exits
 * but the first back to front onto the stack at *sp and returns 1 with the
 * first in *next (0: none reachable). The first stays in registers: a
 * scalar load of what a vector store just wrote waits for the store. */
static inline int kd_lines_simd_line(const tt_kd_line *L, const kd_lines_simd_ray *w, float ta0,
                                     float tb0, uint32_t *sx, float *sa, float *sb, int *sp,
                                     kd_lines_simd_next *next)
{
    const __m256i three = _mm256_set1_epi32(3);
    const __m256i ax = _mm256_and_si256(
        _mm256_srlv_epi32(_mm256_set1_epi32((int)L->axes),
                          _mm256_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14)),
        three);
    /* Lane 7 loads the axes: cleared, as their bits are a denormal float,
     * which float arithmetic may take a slow path for. */
    const __m256 split = _mm256_and_ps(
        _mm256_load_ps(L->split),
        _mm256_castsi256_ps(_mm256_setr_epi32(-1, -1, -1, -1, -1, -1, -1, 0)));
    const __m256 ts = _mm256_mul_ps(_mm256_sub_ps(split, _mm256_permutevar8x32_ps(w->org, ax)),
                                    _mm256_permutevar8x32_ps(w->inv, ax));
    const __m256 e = _mm256_permutevar8x32_ps(w->e, ax);
    const __m256 lo = _mm256_sub_ps(ts, e), hi = _mm256_add_ps(ts, e);
    const __m256i none = _mm256_cmpeq_epi32(ax, three);
    const __m256i down = _mm256_permutevar8x32_epi32(w->down, ax); /* none: 0 */
    __m256 reach = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    __m256 ta = _mm256_set1_ps(ta0), tb = _mm256_set1_ps(tb0);
    kd_lines_simd_level(lo, hi, down, none, _mm256_setzero_si256(),
                        _mm256_setr_epi32(0, 0, 0, 0, -1, -1, -1, -1), &reach, &ta, &tb);
    kd_lines_simd_level(lo, hi, down, none, _mm256_setr_epi32(1, 1, 1, 1, 2, 2, 2, 2),
                        _mm256_setr_epi32(0, 0, -1, -1, 0, 0, -1, -1), &reach, &ta, &tb);
    kd_lines_simd_level(lo, hi, down, none, _mm256_setr_epi32(3, 3, 4, 4, 5, 5, 6, 6),
                        _mm256_setr_epi32(0, -1, 0, -1, 0, -1, 0, -1), &reach, &ta, &tb);
    const __m256i exits = _mm256_load_si256((const __m256i *)(const void *)L->exit);
    reach = _mm256_andnot_ps(
        _mm256_castsi256_ps(_mm256_cmpeq_epi32(exits, _mm256_set1_epi32((int)TT_KD_LINE_EMPTY))),
        reach);
    const unsigned near_right = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(down)) & 0x7Fu;
    const __m256i order = _mm256_cvtepu8_epi32(
        _mm_loadl_epi64((const __m128i *)(const void *)&kd_line_back_to_front[near_right]));
    const unsigned m = (unsigned)_mm256_movemask_ps(_mm256_permutevar8x32_ps(reach, order));
    if (!m) return 0;
    const __m256i pick = _mm256_permutevar8x32_epi32(
        order,
        _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)(const void *)&kd_line_left_pack[m])));
    const __m256i px = _mm256_permutevar8x32_epi32(exits, pick);
    const __m256 pa = _mm256_permutevar8x32_ps(ta, pick), pb = _mm256_permutevar8x32_ps(tb, pick);
    const int n = __builtin_popcount(m) - 1;
    _mm256_storeu_si256((__m256i *)(void *)(sx + *sp), px);
    _mm256_storeu_ps(sa + *sp, pa);
    _mm256_storeu_ps(sb + *sp, pb);
    *sp += n;
    /* The front exit is the last packed lane. */
    const __m256i last = _mm256_set1_epi32(n);
    next->x = (uint32_t)_mm256_cvtsi256_si32(_mm256_permutevar8x32_epi32(px, last));
    next->ta = _mm256_cvtss_f32(_mm256_permutevar8x32_ps(pa, last));
    next->tb = _mm256_cvtss_f32(_mm256_permutevar8x32_ps(pb, last));
    return 1;
}

static inline int kd_lines_simd_htr(const tt_kd_view *T, const tt_wray *r, int any,
                                    tt_kd_best *best)
{
    float ta, tb;
    tt_kd_band band;
    tt_kd_band_init(&band, r);
    if (!tt_kd_root_interval(T, r, &band, &ta, &tb)) return 0;
    tb = tt_kd_min(tb, r->tmax);
    float e[3];
    for (int k = 0; k < 3; k++) {
        const float m = tt_kd_max(fabsf(T->aug[0].lo[k]), fabsf(T->aug[0].hi[k]));
        e[k] = m * band.bi[k] + band.bo[k];
    }
    kd_lines_simd_ray w;
    w.org = _mm256_setr_ps(r->org[0], r->org[1], r->org[2], 0, 0, 0, 0, 0);
    w.inv = _mm256_setr_ps(r->inv[0], r->inv[1], r->inv[2], 0, 0, 0, 0, 0);
    w.e = _mm256_setr_ps(e[0], e[1], e[2], 0, 0, 0, 0, 0);
    w.down = _mm256_setr_epi32(-(r->dir[0] < 0.0f), -(r->dir[1] < 0.0f), -(r->dir[2] < 0.0f), 0,
                               0, 0, 0, 0);
    uint32_t sx[KD_LINES_SIMD_STACK];
    float sa[KD_LINES_SIMD_STACK], sb[KD_LINES_SIMD_STACK];
    int sp = 0;
    kd_lines_simd_next at = {0, ta, tb};
    for (;;) {
        if (!(at.x & TT_KD_LINE_LEAF)) {
            if (kd_lines_simd_line(T->lines + at.x, &w, at.ta, at.tb, sx, sa, sb, &sp, &at))
                continue;
        } else if (kd_lines_leaf(T, at.x, r, any, best)) {
            return 1;
        }
        do {
            if (sp == 0) return 0;
            sp--;
        } while (sa[sp] >= best->t);
        at.x = sx[sp];
        at.ta = sa[sp];
        at.tb = sb[sp];
    }
}
