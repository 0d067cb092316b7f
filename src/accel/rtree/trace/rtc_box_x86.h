/* The slab test of a compact node's child boxes (rtc_layout.h) on x86 SIMD
 * registers, 4, 8 or 16 children per instruction: for inclusion in the
 * per-ISA units rtc_trace_sse42.c / _avx2.c / _avx512.c only, which are
 * compiled with that ISA's flags (the wider kernels exist where __AVX2__ /
 * __AVX512F__ says the unit may use them).
 *
 * Units with FMA (AVX2, AVX-512) compute a slab distance in one fused
 * operation, bound * r' + c', with the widenings folded into the ray's
 * constants so that nothing but the fused operation and the min/max
 * accumulation stands between a node's load and its hit mask (a ray's
 * walk is a chain of dependent node tests: each multiply on it is paid at
 * every node). Near planes use r' = rcp (1 - 2^-16) and c' = -x (1 -
 * 2^-16) - pad, far planes r' = rcp (1 + 2^-21) and c' = -x (1 + 2^-21) +
 * pad, with x = org * rcp and pad = 2^-21 |x| (both rounded). The fused
 * result's errors are the roundings of r' (2^-24 |bound r|, at most
 * 2^-24 (|x| + |d|) for the distance d), of x, the scaling and c' (under
 * 3 2^-24 |x|) and its own (2^-24 |d|): the pad covers the |x| parts
 * (cancellation near the origin), the relative factors the |d| parts with
 * room for the rcp's own rounding, so a near distance is at most d (1 -
 * 2^-16) and a far one at least d (1 + 2^-22) for d >= 0, as the former
 * multiplications after the accumulation gave (a negative far distance is
 * a miss either way, a negative near one stays below tmin). The entry is
 * the near accumulation itself, started at tmin (1 - 2^-16); the far one
 * starts at the float below tmax, so one compare, entry <= far, also says
 * entry < tmax (unused children: +inf > FLT_MAX). A zero direction
 * component (rcp +-inf) gives either the exact +-inf or NaN, which the
 * accumulation ignores (no culling on that axis): conservative. These
 * units may thus visit a box or two more than the others, never fewer
 * around a hit; hits are the triangle test's and stay bit-identical.
 * Their lanes hold the entry whether hit or not (the walks read only hit
 * lanes: a blend to +inf per half cost 0-1.6% on every view).
 *
 * Without FMA (SSE 4.2) each lane computes exactly what tt_rt_box_test_at
 * (rtree_packed.h) computes for one box, with the same operations in the
 * same order (no contraction: the units are compiled with
 * -ffp-contract=off): max(candidate, accumulator) and min(candidate,
 * accumulator) return the accumulator when either operand is NaN, exactly
 * tt_slab_near / tt_slab_far; the ordered compares are false on NaN like
 * the scalar <= and <. The far widening is the same tf + |tf| 2^-22 and
 * pad (tt_rt_planes.pad); the entry's tn - |tn| 2^-16 is the single
 * multiplication tn (1 - 2^-16), the same real value rounded once, so the
 * same float (tn >= tmin >= 0 always), less the pad. A lane's result is its entry distance
 * on a hit, +inf on a miss (FMA units: see above), and the returned mask has bit i set for a hit
 * of child i. */
#ifndef TT_ACCEL_RTREE_RTC_BOX_X86_H
#define TT_ACCEL_RTREE_RTC_BOX_X86_H

#include <immintrin.h>
#include <math.h>
#include <string.h>

#include "accel/rtree/layout/rtc_layout.h"

/* The ray broadcast to every lane once per ray (the widest register this
 * unit has; narrower kernels take its low part). */
typedef struct rtc_lanes {
#if defined(__AVX512F__)
    __m512 ox, oy, oz, ix, iy, iz, tmin, rn[3], rf[3], cn[3], cf[3], tmin_n;
#elif defined(__AVX2__)
    __m256 ox, oy, oz, ix, iy, iz, tmin, rn[3], rf[3], cn[3], cf[3], tmin_n;
#else
    __m128 ox, oy, oz, ix, iy, iz, tmin;
#endif
} rtc_lanes;

#if defined(__FMA__)
#define RTC_FAR (1.0f + 1.0f / 2097152.0f)
/* The FMA units' per-ray constants, the three axes at once in one SSE
 * register each (lane k: axis k; lane 3 is never used): the same float
 * operations per axis as the scalar form they replace (tt_wray's org and
 * rcp read four floats at a time, the fourth being dir[0] / tmin), so the
 * same constants. The scalar form's per-axis branches and broadcasts were
 * ~100 instructions a ray (callgrind, conference: 8% of the walk's).
 * Returns the mask of the axes that cull in the fused test (bit k): those
 * whose scaled rcp and offsets are finite, |rcp| RTC_FAR < inf and
 * |org rcp| (1 + 2^-19) < inf (an rcp of +-inf, a zero direction
 * component, keeps the former handling: exact +-inf or NaN, see above). */
static inline int rtc_axes_fused(const tt_wray *r, __m128 *rn, __m128 *rf, __m128 *cn, __m128 *cf)
{
    const __m128 abs = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128 inf = _mm_set1_ps(TT_INF);
    const __m128 near = _mm_set1_ps(1.0f - 1.0f / 65536.0f), far = _mm_set1_ps(RTC_FAR);
    const __m128 rcp = _mm_loadu_ps(r->rcp), x = _mm_mul_ps(_mm_loadu_ps(r->org), rcp);
    const __m128 arcp = _mm_and_ps(rcp, abs), ax = _mm_and_ps(x, abs);
    const __m128 fused =
        _mm_and_ps(_mm_cmplt_ps(_mm_mul_ps(arcp, far), inf),
                   _mm_cmplt_ps(_mm_mul_ps(ax, _mm_set1_ps(1.0f + 1.0f / 524288.0f)), inf));
    const __m128 pad = _mm_mul_ps(ax, _mm_set1_ps(1.0f / 2097152.0f));
    const __m128 neg = _mm_set1_ps(-0.0f);
    /* a finite rcp or offset whose scaled form would overflow: NaN, so the
     * accumulation ignores the axis (no culling) */
    const __m128 drop = _mm_andnot_ps(fused, _mm_cmplt_ps(arcp, inf));
    const __m128 nan = _mm_set1_ps(NAN);
    *rn = _mm_blendv_ps(_mm_mul_ps(rcp, near), nan, drop);
    *rf = _mm_blendv_ps(_mm_mul_ps(rcp, far), nan, drop);
    *cn = _mm_blendv_ps(_mm_sub_ps(_mm_xor_ps(_mm_mul_ps(x, near), neg), pad), nan, drop);
    *cf = _mm_blendv_ps(_mm_add_ps(_mm_xor_ps(_mm_mul_ps(x, far), neg), pad), nan, drop);
    return _mm_movemask_ps(fused) & 7;
}
#endif

static inline void rtc_lanes_init(rtc_lanes *s, const tt_wray *r)
{
#if defined(__AVX512F__)
#define RTC_SET1 _mm512_set1_ps
#define RTC_LANE(v, k) _mm512_broadcastss_ps(_mm_permute_ps((v), (k) * 0x55))
#elif defined(__AVX2__)
#define RTC_SET1 _mm256_set1_ps
#define RTC_LANE(v, k) _mm256_broadcastss_ps(_mm_permute_ps((v), (k) * 0x55))
#else
#define RTC_SET1 _mm_set1_ps
#endif
    s->ox = RTC_SET1(r->org[0]);
    s->oy = RTC_SET1(r->org[1]);
    s->oz = RTC_SET1(r->org[2]);
    s->ix = RTC_SET1(r->rcp[0]);
    s->iy = RTC_SET1(r->rcp[1]);
    s->iz = RTC_SET1(r->rcp[2]);
    s->tmin = RTC_SET1(r->tmin);
#if defined(__FMA__)
    __m128 rn, rf, cn, cf;
    (void)rtc_axes_fused(r, &rn, &rf, &cn, &cf);
    s->rn[0] = RTC_LANE(rn, 0), s->rn[1] = RTC_LANE(rn, 1), s->rn[2] = RTC_LANE(rn, 2);
    s->rf[0] = RTC_LANE(rf, 0), s->rf[1] = RTC_LANE(rf, 1), s->rf[2] = RTC_LANE(rf, 2);
    s->cn[0] = RTC_LANE(cn, 0), s->cn[1] = RTC_LANE(cn, 1), s->cn[2] = RTC_LANE(cn, 2);
    s->cf[0] = RTC_LANE(cf, 0), s->cf[1] = RTC_LANE(cf, 1), s->cf[2] = RTC_LANE(cf, 2);
    s->tmin_n = RTC_SET1(r->tmin * (1.0f - 1.0f / 65536.0f));
#undef RTC_LANE
#endif
#undef RTC_SET1
}

/* A ray none of whose axes culls in the fused test (rtc_axes_fused: all
 * three direction components below about 3e-39, denormal or zero, so rcp
 * is +-inf or too large to scale; or an origin so far out that org * rcp
 * overflows) leaves the FMA units nothing to cull with: every axis gives
 * NaN, which the accumulation ignores, so even an unused child (all bounds
 * +inf) would pass and its invalid reference be followed. Such rays (rare,
 * but the ray contract accepts them) are traced by the scalar kernel
 * instead, whose two-step slab test rejects unused children and gives the
 * same answers. One axis that culls suffices (an unused child's +inf
 * bounds then give +inf near or -inf far on it). */
#if defined(__FMA__)
static inline int rtc_box_needs_scalar(const tt_wray *r)
{
    __m128 rn, rf, cn, cf;
    return rtc_axes_fused(r, &rn, &rf, &cn, &cf) == 0;
}
#define RTC_BOX_NEEDS_SCALAR(r) rtc_box_needs_scalar(r)
#endif

#if defined(__AVX512F__)
#define RTC_LO128(x) _mm512_castps512_ps128(x)
#define RTC_LO256(x) _mm512_castps512_ps256(x)
#elif defined(__AVX2__)
#define RTC_LO128(x) _mm256_castps256_ps128(x)
#define RTC_LO256(x) (x)
#else
#define RTC_LO128(x) (x)
#endif

#if defined(__FMA__)
/* The float just below tmax (> 0 or +inf: FLT_MAX), the far accumulation's
 * start: entry <= it says entry < tmax. */
static inline float rtc_below(float tmax)
{
    uint32_t u;
    memcpy(&u, &tmax, sizeof u);
    u--;
    memcpy(&tmax, &u, sizeof u);
    return tmax;
}
#endif

/* Four children from g (a node's boxes plus the first child's position). */
static inline uint32_t rtc_box4(const rtc_lanes *s, const tt_rt_planes *p, const float *g,
                                float tmax, float *out)
{
    const __m128 ox = RTC_LO128(s->ox), oy = RTC_LO128(s->oy), oz = RTC_LO128(s->oz);
    const __m128 ix = RTC_LO128(s->ix), iy = RTC_LO128(s->iy), iz = RTC_LO128(s->iz);
    const __m128 tnx = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->n[0]), ox), ix);
    const __m128 tny = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->n[1]), oy), iy);
    const __m128 tnz = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->n[2]), oz), iz);
    const __m128 tfx = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->f[0]), ox), ix);
    const __m128 tfy = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->f[1]), oy), iy);
    const __m128 tfz = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->f[2]), oz), iz);
    const __m128 inf = _mm_set1_ps(TT_INF);
    const __m128 tn = _mm_max_ps(tnz, _mm_max_ps(tny, _mm_max_ps(tnx, RTC_LO128(s->tmin))));
    const __m128 tf0 = _mm_min_ps(tfz, _mm_min_ps(tfy, _mm_min_ps(tfx, inf)));
    /* tt_rt_box_test_at's margins (its pad: tt_rt_planes), the same
     * operations: tf0 + |tf0| 2^-22 (not tf0 (1 + 2^-22): tf0 < 0 can now
     * pass, padded) */
    const __m128 pad = _mm_set1_ps(p->pad);
    const __m128 atf = _mm_and_ps(tf0, _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)));
    const __m128 tf = _mm_add_ps(_mm_add_ps(tf0, _mm_mul_ps(atf, _mm_set1_ps(1.0f / 4194304.0f))), pad);
    const __m128 entry = _mm_sub_ps(_mm_mul_ps(tn, _mm_set1_ps(1.0f - 1.0f / 65536.0f)), pad);
    const __m128 hit = _mm_and_ps(_mm_cmple_ps(tn, tf), _mm_cmplt_ps(entry, _mm_set1_ps(tmax)));
    _mm_storeu_ps(out, _mm_or_ps(_mm_and_ps(hit, entry), _mm_andnot_ps(hit, inf)));
    return (uint32_t)_mm_movemask_ps(hit);
}

#if defined(__AVX2__)
/* Eight children. */
static inline uint32_t rtc_box8(const rtc_lanes *s, const tt_rt_planes *p, const float *g,
                                float tmax, float *out)
{
#define RTC_FMA8(row, r, c) _mm256_fmadd_ps(_mm256_loadu_ps(g + (row)), RTC_LO256(r), RTC_LO256(c))
    const __m256 tnx = RTC_FMA8(p->n[0], s->rn[0], s->cn[0]);
    const __m256 tny = RTC_FMA8(p->n[1], s->rn[1], s->cn[1]);
    const __m256 tnz = RTC_FMA8(p->n[2], s->rn[2], s->cn[2]);
    const __m256 tfx = RTC_FMA8(p->f[0], s->rf[0], s->cf[0]);
    const __m256 tfy = RTC_FMA8(p->f[1], s->rf[1], s->cf[1]);
    const __m256 tfz = RTC_FMA8(p->f[2], s->rf[2], s->cf[2]);
#undef RTC_FMA8
    const __m256 entry =
        _mm256_max_ps(tnz, _mm256_max_ps(tny, _mm256_max_ps(tnx, RTC_LO256(s->tmin_n))));
    const __m256 below = _mm256_set1_ps(rtc_below(tmax));
    const __m256 tf = _mm256_min_ps(tfz, _mm256_min_ps(tfy, _mm256_min_ps(tfx, below)));
    const __m256 hit = _mm256_cmp_ps(entry, tf, _CMP_LE_OQ);
    _mm256_storeu_ps(out, entry);
    return (uint32_t)_mm256_movemask_ps(hit);
}
#endif

#if defined(__AVX512F__)
/* Sixteen children. */
static inline uint32_t rtc_box16(const rtc_lanes *s, const tt_rt_planes *p, const float *g,
                                 float tmax, float *out)
{
    const __m512 tnx = _mm512_fmadd_ps(_mm512_loadu_ps(g + p->n[0]), s->rn[0], s->cn[0]);
    const __m512 tny = _mm512_fmadd_ps(_mm512_loadu_ps(g + p->n[1]), s->rn[1], s->cn[1]);
    const __m512 tnz = _mm512_fmadd_ps(_mm512_loadu_ps(g + p->n[2]), s->rn[2], s->cn[2]);
    const __m512 tfx = _mm512_fmadd_ps(_mm512_loadu_ps(g + p->f[0]), s->rf[0], s->cf[0]);
    const __m512 tfy = _mm512_fmadd_ps(_mm512_loadu_ps(g + p->f[1]), s->rf[1], s->cf[1]);
    const __m512 tfz = _mm512_fmadd_ps(_mm512_loadu_ps(g + p->f[2]), s->rf[2], s->cf[2]);
    const __m512 entry = _mm512_max_ps(tnz, _mm512_max_ps(tny, _mm512_max_ps(tnx, s->tmin_n)));
    const __m512 tf =
        _mm512_min_ps(tfz, _mm512_min_ps(tfy, _mm512_min_ps(tfx, _mm512_set1_ps(rtc_below(tmax)))));
    const __mmask16 hit = _mm512_cmp_ps_mask(entry, tf, _CMP_LE_OQ);
    _mm512_storeu_ps(out, entry);
    return (uint32_t)hit;
}
#endif

/* All S children of a node (S a multiple of 4, at most 16), the widest
 * kernels first; with S a constant the loops vanish. */
static inline uint32_t rtc_group_test(const rtc_lanes *s, const tt_rt_planes *p, const float *rec,
                                      uint32_t S, float tmax, float *out)
{
    uint32_t mask = 0, i = 0;
#if defined(__AVX512F__)
    for (; i + 16 <= S; i += 16) mask |= rtc_box16(s, p, rec + i, tmax, out + i) << i;
#endif
#if defined(__AVX2__)
    for (; i + 8 <= S; i += 8) mask |= rtc_box8(s, p, rec + i, tmax, out + i) << i;
#endif
    for (; i < S; i += 4) mask |= rtc_box4(s, p, rec + i, tmax, out + i) << i;
    return mask;
}

#endif
