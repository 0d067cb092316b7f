/* Top-down bulk loading by the surface area heuristic with every leaf on
 * one level (in the spirit of OMT, Lee & Lee 2003, whose slices are cut
 * here where the SAH says).
 *
 * Height: a subtree whose root is on level l holds between m^(l+1) and
 * M^(l+1) triangles (every node m..M entries); the root may hold 2..M
 * entries. The root goes on the smallest level L with M^(L+1) >= T, which
 * is also feasible from below: T > M^L >= 2 m^L for L >= 1 since M >= 2m.
 * The smallest height also keeps the complete level-order layout smallest.
 *
 * A node on level l >= 1 with n triangles gets k children, each a subtree
 * on level l - 1 holding [lo, hi] = [m^l, M^l] triangles: k lies in
 * [max(kmin, ceil(n/hi)), min(M, floor(n/lo))] (kmin = 2 at the root, m
 * elsewhere), a range the node's own capacity makes non-empty; choose_k
 * picks k in it (a level-1 node as many leaves as fit, the nodes above as
 * many children as subtrees of full nodes over leaves of M / 4 triangles
 * need, so the slack of the fixed height goes to the top). The node's
 * triangles are cut into its k groups by recursive binary cuts: a range
 * that must become k groups is cut into c and n - c triangles that become
 * k1 and k - k1 groups, with c in [k1 lo, k1 hi] and n - c in
 * [(k - k1) lo, (k - k1) hi] (always possible for some c when k lo <= n <=
 * k hi). Among such cuts the one of least A(left) c + A(right) (n - c)
 * wins, over the three axes: exact sweeps over the sorted centres for small
 * ranges, 32 bins per axis for large ones (a bin boundary whose count is not
 * feasible is moved to the nearest feasible count, its cost estimated with
 * the straddling bins on both sides). The cut itself is exact: a selection
 * puts the c triangles of least centre (ties by id) left.
 *
 * Results go into preallocated places only (the triangle order and one
 * byte per position saying which levels' nodes start there); the nodes are
 * then made level by level from those marks, so the tree is the same for
 * any number of threads. Subtrees are OpenMP tasks. */
#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_bulk.h"

#define BINS 32
#define SWEEP_MAX 64      /* ranges up to this size are swept exactly */
#define TASK_MIN 4096     /* subtrees of at least this many triangles are tasks */
#define PART_TASK_MIN 8192 /* so are both sides of a cut of at least this many */
/* Scenes of at least this many triangles are built on the context's threads
 * (the tree does not depend on their number). On the quiet 2-core machine,
 * two threads from 2^14 on took bunny's and Sibenik's builds from 1.53-1.82x
 * to 1.2-1.5x Embree's medium build (raybench, 8 runs each); under a load of
 * 10-20 they were 1.5-2.3x slower than one thread (a descheduled thread
 * holds a task the other waits for: notes/build.md), a cost only a
 * saturated machine pays. */
#define SAH_PARALLEL_MIN (1u << 14)
/* The triangles a leaf is aimed at when sizing the nodes above level 1 (see
 * choose_k): M / LEAF_AIM_DIV, 4 at the default M = 16 (half a block,
 * TT_TRI_BLOCK_W = 8). Measured at M = 16 on the shared views and the
 * unseen scenes against 2, 3, 5, 6, 8 (notes/rwidth.md): 3 and 5 lose on
 * some views, 6 and 8 on shadows. At M = 4 (aim 1) and M = 8 (aim 2) the
 * aimed trees lost on Sibenik and conference (a 4- or 8-box node test is
 * cheap against what fuller leaves cost; an aim of m, 2 at M = 16, was
 * mixed too): where M / 4 is not above m the nodes are the widest, as
 * before. */
#define LEAF_AIM_DIV 4

typedef struct sah {
    const float *tri_box;
    const float *cen; /* 3 floats a triangle */
    uint32_t *idx;    /* triangle ids, becoming leaf order */
    uint8_t *mark;    /* per position: 1 + the highest level whose node starts here; 0 none */
    uint64_t lo[TT_RT_BUILD_LEVELS], hi[TT_RT_BUILD_LEVELS]; /* subtree capacity by its level */
    uint64_t aim[TT_RT_BUILD_LEVELS]; /* choose_k's triangles of a subtree by its level */
    int m, M, root_level;
} sah;

/* The children of a node on `level` holding n triangles.
 *
 * A level-1 node gets as many leaves as fit, min(M, floor(n / m)): its
 * leaves share blocks and a record tests each block at most once
 * (rtc_trace_leaf.h), so more leaf boxes cost no triangle tests and cull
 * better; the node's own test costs the same for any count.
 *
 * Above it, what costs is nodes: every interior visit is a full M-box test
 * and a record (7 cache lines at M = 16) to fetch. The loader used to make
 * every node as wide as its capacity allows, which with the height fixed
 * left the slack at the bottom: on Sibenik and the bunny (T just above
 * M^4) level-1 nodes of ~18 triangles in 9 leaves of 2, 4200 records. Now
 * a node gets the children that subtrees of full nodes over leaves of
 * aim = M / 4 triangles need, ceil(n / (aim M^(l-1))), within the range
 * above, so the nodes below are full and the slack goes to the top (at
 * M = 16 a root of 4 to 16 entries once T > M^2). Sibenik: 990 records, interior visits a primary ray
 * 12.3 -> 9.6; measured faster on every shared and unseen view, whose
 * numbers are in notes/rwidth.md. */
static int choose_k(const sah *s, uint64_t n, int level)
{
    const uint64_t lo = s->lo[level - 1], hi = s->hi[level - 1];
    uint64_t kmax = n / lo;
    if (kmax > (uint64_t)s->M) kmax = (uint64_t)s->M;
    if (level == 1 || s->aim[0] == 0) return (int)kmax;
    uint64_t kmin = (n + hi - 1) / hi;
    const uint64_t least = level == s->root_level ? 2 : (uint64_t)s->m;
    if (kmin < least) kmin = least;
    const uint64_t aim = s->aim[level - 1];
    uint64_t k = (n + aim - 1) / aim;
    if (k < kmin) k = kmin;
    if (k > kmax) k = kmax;
    return (int)k;
}

/* ------------------------------------------------------------ feasibility */

/* The group counts k1 for a left side of c of n triangles becoming k groups
 * of lo..hi: [*a, *b], empty when *a > *b. */
static void k1_range(uint64_t n, uint64_t c, int k, uint64_t lo, uint64_t hi, int *a, int *b)
{
    const uint64_t r = n - c;
    int64_t A = 1, B = k - 1;
    int64_t t = (int64_t)((c + hi - 1) / hi); /* ceil(c / hi) */
    if (t > A) A = t;
    t = (int64_t)k - (int64_t)(r / lo);
    if (t > A) A = t;
    t = (int64_t)(c / lo);
    if (t < B) B = t;
    t = (int64_t)k - (int64_t)((r + hi - 1) / hi);
    if (t < B) B = t;
    *a = (int)A;
    *b = (int)B;
}

/* k1 for a feasible cut c (the one nearest proportional), 0 if infeasible. */
static int pick_k1(uint64_t n, uint64_t c, int k, uint64_t lo, uint64_t hi)
{
    if (c == 0 || c >= n) return 0;
    int a, b;
    k1_range(n, c, k, lo, hi, &a, &b);
    if (a > b) return 0;
    int p = (int)((c * (uint64_t)k + n / 2) / n);
    return p < a ? a : p > b ? b : p;
}

/* The cuts c for which the left side becomes k1 groups: [*a, *b]; 0 if
 * there are none. */
static int cut_interval(uint64_t n, int k, int k1, uint64_t lo, uint64_t hi, uint64_t *a_out,
                        uint64_t *b_out)
{
    const uint64_t k2 = (uint64_t)(k - k1);
    uint64_t a = (uint64_t)k1 * lo, b = (uint64_t)k1 * hi;
    if (n > k2 * hi && n - k2 * hi > a) a = n - k2 * hi;
    if (n - k2 * lo < b) b = n - k2 * lo; /* n >= k lo > k2 lo */
    *a_out = a;
    *b_out = b;
    return a <= b;
}

/* The feasible cut nearest c. */
static uint64_t nearest_cut(uint64_t n, uint64_t c, int k, uint64_t lo, uint64_t hi)
{
    uint64_t best = 0, dist = UINT64_MAX;
    for (int k1 = 1; k1 < k; k1++) {
        uint64_t a, b;
        if (!cut_interval(n, k, k1, lo, hi, &a, &b)) continue;
        uint64_t x = c < a ? a : c > b ? b : c;
        uint64_t d = x > c ? x - c : c - x;
        if (d < dist) dist = d, best = x;
    }
    return best;
}

/* The feasible cuts of a range (n triangles becoming k groups of lo..hi)
 * as intervals, computed once per cut: the binned cut asks for the nearest
 * feasible cut at every bin boundary of every axis (3 x 31 questions), and
 * recomputing the k - 1 intervals for each was a third of the loader's
 * time on small ranges. */
typedef struct cut_set {
    int count;
    uint64_t a[TT_RT_MAX_M], b[TT_RT_MAX_M];
} cut_set;

static void cut_set_init(cut_set *cs, uint64_t n, int k, uint64_t lo, uint64_t hi)
{
    cs->count = 0;
    for (int k1 = 1; k1 < k; k1++) {
        uint64_t a, b;
        if (!cut_interval(n, k, k1, lo, hi, &a, &b)) continue;
        /* both ends grow with k1: an interval that overlaps or touches the
         * last one extends it (the nearest cut stays the same; mostly one
         * interval is left, so each question is one clamp) */
        if (cs->count > 0 && a <= cs->b[cs->count - 1] + 1) {
            if (b > cs->b[cs->count - 1]) cs->b[cs->count - 1] = b;
            continue;
        }
        cs->a[cs->count] = a;
        cs->b[cs->count++] = b;
    }
}

/* nearest_cut(n, c, k, lo, hi) from the precomputed intervals (the same
 * answer: the same intervals in the same order, the first nearest kept). */
static uint64_t cut_set_nearest(const cut_set *cs, uint64_t c)
{
    uint64_t best = 0, dist = UINT64_MAX;
    for (int i = 0; i < cs->count; i++) {
        const uint64_t a = cs->a[i], b = cs->b[i];
        uint64_t x = c < a ? a : c > b ? b : c;
        uint64_t d = x > c ? x - c : c - x;
        if (d < dist) dist = d, best = x;
    }
    return best;
}

/* ---------------------------------------------------------- ordering */

static inline int before(const sah *s, int axis, uint32_t a, uint32_t b)
{
    const float ca = s->cen[3 * (size_t)a + axis], cb = s->cen[3 * (size_t)b + axis];
    return ca < cb || (ca == cb && a < b);
}

/* Puts the c triangles of least (centre on axis, id) first in v[0 .. n). */
static void select_first(const sah *s, int axis, uint32_t *v, uint32_t n, uint32_t c)
{
    uint32_t lo = 0, hi = n; /* the c-th lies in [lo, hi) */
    while (hi - lo > 16) {
        uint32_t mid = lo + (hi - lo) / 2;
        /* median of three as pivot, moved to lo */
        uint32_t a = v[lo], b = v[mid], d = v[hi - 1], p;
        if (before(s, axis, a, b)) p = before(s, axis, b, d) ? mid : before(s, axis, a, d) ? hi - 1 : lo;
        else p = before(s, axis, a, d) ? lo : before(s, axis, b, d) ? hi - 1 : mid;
        uint32_t t = v[lo];
        v[lo] = v[p];
        v[p] = t;
        const uint32_t pivot = v[lo];
        uint32_t i = lo + 1, j = hi - 1;
        for (;;) { /* all ids differ: strict order, no element equals the pivot */
            while (i <= j && before(s, axis, v[i], pivot)) i++;
            while (i <= j && before(s, axis, pivot, v[j])) j--;
            if (i >= j) break;
            t = v[i], v[i] = v[j], v[j] = t;
            i++, j--;
        }
        /* v[lo+1 .. j] < pivot < v[j+1 ..]: put the pivot at j */
        v[lo] = v[j];
        v[j] = pivot;
        if (j == c) return;
        if (j < c) lo = j + 1;
        else hi = j;
    }
    for (uint32_t i = lo + 1; i < hi; i++) { /* insertion sort of the rest */
        uint32_t x = v[i], j = i;
        while (j > lo && before(s, axis, x, v[j - 1])) {
            v[j] = v[j - 1];
            j--;
        }
        v[j] = x;
    }
}

#if !defined(__SSE2__) /* the SSE2 code has sbox_nonempty and sbox_area */
static inline float area_of(const float b[6])
{
    return b[3] >= b[0] ? rt_box_area(b) : 0.0f;
}
#endif

/* A growing box for the sweeps. With SSE2 it is two registers (lanes 0..2
 * of lo the minima, lanes 1..3 of hi the maxima, as in cut_binned), so that
 * growing by a triangle box is two loads, a min and a max; the area is
 * computed in rt_box_area's order, so every cost is bit-identical to the
 * scalar code's. */
#if defined(__SSE2__)
typedef struct sbox {
    __m128 lo, hi;
} sbox;
static inline void sbox_empty(sbox *b)
{
    b->lo = _mm_set1_ps(TT_INF);
    b->hi = _mm_set1_ps(-TT_INF);
}
static inline void sbox_grow(sbox *b, const float *tb)
{
    b->lo = _mm_min_ps(b->lo, _mm_loadu_ps(tb));
    b->hi = _mm_max_ps(b->hi, _mm_loadu_ps(tb + 2));
}
static inline float sbox_area(const sbox *b)
{
    const __m128 d = _mm_sub_ps(_mm_shuffle_ps(b->hi, b->hi, _MM_SHUFFLE(3, 3, 2, 1)), b->lo);
    const __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));
    const float xy = _mm_cvtss_f32(p), yz = _mm_cvtss_f32(_mm_shuffle_ps(p, p, 1)),
                zx = _mm_cvtss_f32(_mm_movehl_ps(p, p));
    return 2.0f * (xy + yz + zx);
}
/* area_of's test: hi x >= lo x */
static inline int sbox_nonempty(const sbox *b)
{
    return _mm_cvtss_f32(_mm_shuffle_ps(b->hi, b->hi, 1)) >= _mm_cvtss_f32(b->lo);
}
static inline void sbox_store(const sbox *b, float out[6])
{
    float l[4], h[4];
    _mm_storeu_ps(l, b->lo);
    _mm_storeu_ps(h, b->hi);
    const float b6[6] = {l[0], l[1], l[2], h[1], h[2], h[3]};
    memcpy(out, b6, sizeof b6);
}
#else
typedef struct sbox {
    float b[6];
} sbox;
static inline void sbox_empty(sbox *b) { rt_box_empty(b->b); }
static inline void sbox_grow(sbox *b, const float *tb) { rt_box_grow(b->b, tb); }
static inline float sbox_area(const sbox *b) { return rt_box_area(b->b); }
static inline void sbox_store(const sbox *b, float out[6]) { memcpy(out, b->b, sizeof b->b); }
#endif

/* ----------------------------------------------------------------- cuts */

/* (centre, id) as one integer: the float's order in the high half, the id
 * in the low half, so small ranges sort on plain integer compares. */
static inline uint64_t item_key(float c, uint32_t id)
{
    return (uint64_t)rt_float_key(c) << 32 | id;
}

static void sort_keys(uint64_t *a, uint32_t n) /* n is small */
{
    for (uint32_t i = 1; i < n; i++) {
        uint64_t x = a[i];
        uint32_t j = i;
        while (j > 0 && x < a[j - 1]) {
            a[j] = a[j - 1];
            j--;
        }
        a[j] = x;
    }
}

/* Cuts v[0 .. n), which must become k groups of lo..hi, into a left part
 * v[0 .. *c) of *k1 groups: small ranges by an exact sweep. */
static void cut_sweep(const sah *s, uint32_t *v, uint32_t n, int k, uint64_t lo, uint64_t hi,
                      uint32_t *c_out, int *k1_out)
{
    uint64_t sorted[3][SWEEP_MAX];
    float right[SWEEP_MAX];
    /* the feasible cuts, once (the union over k1 of the intervals) */
    uint8_t ok[SWEEP_MAX];
    memset(ok, 0, n);
    for (int k1 = 1; k1 < k; k1++) {
        uint64_t a, b;
        if (cut_interval(n, k, k1, lo, hi, &a, &b))
            for (uint64_t c = a; c <= b; c++) ok[c] = 1;
    }
    float best = TT_INF;
    int best_axis = -1;
    uint32_t best_c = 0;
    for (int axis = 0; axis < 3; axis++) {
        uint64_t *a = sorted[axis];
        for (uint32_t i = 0; i < n; i++) a[i] = item_key(s->cen[3 * (size_t)v[i] + axis], v[i]);
        sort_keys(a, n);
        sbox b;
        sbox_empty(&b);
        for (uint32_t i = n; i-- > 1;) {
            sbox_grow(&b, s->tri_box + 6 * (size_t)(uint32_t)a[i]);
            right[i] = sbox_area(&b);
        }
        sbox_empty(&b);
        for (uint32_t c = 1; c < n; c++) {
            sbox_grow(&b, s->tri_box + 6 * (size_t)(uint32_t)a[c - 1]);
            if (!ok[c]) continue;
            float cost = sbox_area(&b) * (float)c + right[c] * (float)(n - c);
            if (cost < best) best = cost, best_axis = axis, best_c = c;
        }
    }
    if (best_axis < 0) { /* cannot happen for a feasible range; keep the order */
        best_axis = 0;
        best_c = (uint32_t)nearest_cut(n, n / 2, k, lo, hi);
    }
    for (uint32_t i = 0; i < n; i++) v[i] = (uint32_t)sorted[best_axis][i];
    *c_out = best_c;
    *k1_out = pick_k1(n, best_c, k, lo, hi);
}

static void centre_bounds(const sah *s, const uint32_t *v, uint32_t n, float cb[6])
{
    rt_box_empty(cb);
    for (uint32_t i = 0; i < n; i++) {
        const float *c = s->cen + 3 * (size_t)v[i];
        for (int a = 0; a < 3; a++) {
            cb[a] = rt_min(cb[a], c[a]);
            cb[a + 3] = rt_max(cb[a + 3], c[a]);
        }
    }
}

#if !defined(__SSE2__) /* the SSE2 code computes three at once, the same way */
static inline int bin_of(float c, float lo, float scale)
{
    int j = (int)((c - lo) * scale);
    return j < 0 ? 0 : j >= BINS ? BINS - 1 : j;
}
#endif

/* The same for large ranges, by binning the centres (whose bounds are cb);
 * also returns the centre bounds of both sides. */
static void cut_binned(const sah *s, uint32_t *v, uint32_t n, int k, uint64_t lo, uint64_t hi,
                       const float cb[6], uint32_t *c_out, int *k1_out, float cbl[6], float cbr[6])
{
    float scale[3];
    uint32_t cnt[3][BINS];
#if !defined(__SSE2__)
    float box[3][BINS][6];
#endif
    memset(cnt, 0, sizeof cnt);
    for (int a = 0; a < 3; a++)
        scale[a] = cb[a + 3] > cb[a] ? (float)BINS / (cb[a + 3] - cb[a]) : 0.0f;
#if defined(__SSE2__)
    /* a bin's bounds as two 4-lane registers: lanes 0..2 of lo hold the
     * minima (lane 3 unused), lanes 1..3 of hi the maxima (lane 0 unused),
     * so that one triangle box (6 floats) is two unaligned loads */
    __m128 blo[3][BINS], bhi[3][BINS];
    for (int a = 0; a < 3; a++)
        for (int j = 0; j < BINS; j++) {
            blo[a][j] = _mm_set1_ps(TT_INF);
            bhi[a][j] = _mm_set1_ps(-TT_INF);
        }
    /* the three bins of a centre at once: the scalar code's bin_of
     * arithmetic, clamped in float before the conversion (the same bins:
     * the products are the same, and the clamp only moves values whose bin
     * is clamped anyway); the centres are padded by a float, so the
     * 4-float load is safe */
    const __m128 clo4 = _mm_setr_ps(cb[0], cb[1], cb[2], 0.0f);
    const __m128 sc4 = _mm_setr_ps(scale[0], scale[1], scale[2], 0.0f);
    const __m128 zero4 = _mm_setzero_ps(), top4 = _mm_set1_ps((float)(BINS - 1));
    for (uint32_t i = 0; i < n; i++) {
        const float *c = s->cen + 3 * (size_t)v[i], *tb = s->tri_box + 6 * (size_t)v[i];
        const __m128 lo4 = _mm_loadu_ps(tb), hi4 = _mm_loadu_ps(tb + 2);
        const __m128 x = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(c), clo4), sc4);
        int jj[4];
        _mm_storeu_si128((__m128i *)jj, _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(x, zero4), top4)));
        for (int a = 0; a < 3; a++) {
            const int j = jj[a];
            cnt[a][j]++;
            blo[a][j] = _mm_min_ps(blo[a][j], lo4);
            bhi[a][j] = _mm_max_ps(bhi[a][j], hi4);
        }
    }
#else
    for (int a = 0; a < 3; a++)
        for (int j = 0; j < BINS; j++) rt_box_empty(box[a][j]);
    for (uint32_t i = 0; i < n; i++) {
        const float *c = s->cen + 3 * (size_t)v[i], *tb = s->tri_box + 6 * (size_t)v[i];
        for (int a = 0; a < 3; a++) {
            const int j = bin_of(c[a], cb[a], scale[a]);
            cnt[a][j]++;
            rt_box_grow(box[a][j], tb);
        }
    }
#endif
    float best = TT_INF;
    int best_axis = -1, best_bin = 0;
    uint32_t best_c = 0;
    cut_set cs;
    cut_set_init(&cs, n, k, lo, hi);
    for (int axis = 0; axis < 3; axis++) {
        if (!(cb[axis + 3] > cb[axis])) continue;
        /* prefix: bins [0, j); suffix: bins [j, BINS) */
        float pre_a[BINS + 1], suf_a[BINS + 1];
        uint32_t pre_c[BINS + 1];
        pre_a[0] = 0.0f;
        pre_c[0] = 0;
        suf_a[BINS] = 0.0f;
#if defined(__SSE2__)
        /* on the bins' registers (the same min/max operands and area
         * arithmetic as area_of on the stored boxes, so the same floats) */
        sbox b;
        sbox_empty(&b);
        for (int j = 0; j < BINS; j++) {
            b.lo = _mm_min_ps(b.lo, blo[axis][j]);
            b.hi = _mm_max_ps(b.hi, bhi[axis][j]);
            pre_a[j + 1] = sbox_nonempty(&b) ? sbox_area(&b) : 0.0f;
            pre_c[j + 1] = pre_c[j] + cnt[axis][j];
        }
        sbox_empty(&b);
        for (int j = BINS; j-- > 0;) {
            b.lo = _mm_min_ps(b.lo, blo[axis][j]);
            b.hi = _mm_max_ps(b.hi, bhi[axis][j]);
            suf_a[j] = sbox_nonempty(&b) ? sbox_area(&b) : 0.0f;
        }
#else
        float b[6];
        rt_box_empty(b);
        for (int j = 0; j < BINS; j++) {
            rt_box_grow(b, box[axis][j]);
            pre_a[j + 1] = area_of(b);
            pre_c[j + 1] = pre_c[j] + cnt[axis][j];
        }
        rt_box_empty(b);
        for (int j = BINS; j-- > 0;) {
            rt_box_grow(b, box[axis][j]);
            suf_a[j] = area_of(b);
        }
#endif
        for (int j = 1; j < BINS; j++) {
            uint32_t c = pre_c[j];
            uint32_t f = (uint32_t)cut_set_nearest(&cs, c);
            float al = pre_a[j], ar = suf_a[j];
            if (f > c) { /* the left side reaches into later bins */
                int e = j;
                while (e < BINS && pre_c[e] < f) e++;
                al = pre_a[e];
            } else if (f < c) { /* the right side reaches into earlier bins */
                int e = j;
                while (e > 0 && pre_c[e] > f) e--;
                ar = suf_a[e];
            }
            float cost = al * (float)f + ar * (float)(n - f);
            if (cost < best) best = cost, best_axis = axis, best_c = f, best_bin = f == c ? j : -1;
        }
    }
    if (best_axis >= 0 && best_bin >= 0) {
        /* the cut is a bin boundary: one partitioning pass, which also
         * bounds both sides' centres */
        const int a = best_axis;
        uint32_t i = 0, j = n;
#if defined(__SSE2__)
        /* the bin as the binning loop computed it, the centres' bounds in
         * registers */
        __m128 llo = _mm_set1_ps(TT_INF), lhi = _mm_set1_ps(-TT_INF);
        __m128 rlo = llo, rhi = lhi;
        while (i < j) {
            const __m128 c4 = _mm_loadu_ps(s->cen + 3 * (size_t)v[i]);
            const __m128 x = _mm_mul_ps(_mm_sub_ps(c4, clo4), sc4);
            int jj[4];
            _mm_storeu_si128((__m128i *)jj,
                             _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(x, zero4), top4)));
            if (jj[a] < best_bin) {
                llo = _mm_min_ps(llo, c4);
                lhi = _mm_max_ps(lhi, c4);
                i++;
            } else {
                rlo = _mm_min_ps(rlo, c4);
                rhi = _mm_max_ps(rhi, c4);
                uint32_t t = v[i];
                v[i] = v[--j];
                v[j] = t;
            }
        }
        float t4[4];
        _mm_storeu_ps(t4, llo);
        memcpy(cbl, t4, 3 * sizeof(float));
        _mm_storeu_ps(t4, lhi);
        memcpy(cbl + 3, t4, 3 * sizeof(float));
        _mm_storeu_ps(t4, rlo);
        memcpy(cbr, t4, 3 * sizeof(float));
        _mm_storeu_ps(t4, rhi);
        memcpy(cbr + 3, t4, 3 * sizeof(float));
#else
        rt_box_empty(cbl);
        rt_box_empty(cbr);
        while (i < j) {
            const float *c = s->cen + 3 * (size_t)v[i];
            if (bin_of(c[a], cb[a], scale[a]) < best_bin) {
                for (int d = 0; d < 3; d++) {
                    cbl[d] = rt_min(cbl[d], c[d]);
                    cbl[d + 3] = rt_max(cbl[d + 3], c[d]);
                }
                i++;
            } else {
                for (int d = 0; d < 3; d++) {
                    cbr[d] = rt_min(cbr[d], c[d]);
                    cbr[d + 3] = rt_max(cbr[d + 3], c[d]);
                }
                uint32_t t = v[i];
                v[i] = v[--j];
                v[j] = t;
            }
        }
#endif
    } else {
        if (best_axis < 0) { /* all centres equal: any cut, by id */
            best_axis = 0;
            best_c = (uint32_t)nearest_cut(n, (uint64_t)n * (uint64_t)(k / 2) / (uint64_t)k, k,
                                           lo, hi);
        }
        select_first(s, best_axis, v, n, best_c);
        centre_bounds(s, v, best_c, cbl);
        centre_bounds(s, v + best_c, n - best_c, cbr);
    }
    *c_out = best_c;
    *k1_out = pick_k1(n, best_c, k, lo, hi);
}

/* A group of a node's partition: where it starts, and its centres' bounds
 * (known for the groups cut from bins, which are the large ones). */
typedef struct group {
    uint32_t start;
    float cb[6];
} group;

/* Cuts v[0 .. n) (centre bounds cb, needed when n > SWEEP_MAX) into k groups
 * of lo..hi triangles, written to out[g .. g + k). The two sides of a large
 * cut are cut as tasks: each writes its own groups, so the result does not
 * depend on which thread cuts which. */
static void partition(const sah *s, uint32_t *v, uint32_t off, uint32_t n, int k, uint64_t lo,
                      uint64_t hi, const float cb[6], group *out, int g)
{
    if (k == 1) {
        out[g].start = off;
        memcpy(out[g].cb, cb, sizeof out[g].cb);
        return;
    }
    uint32_t c;
    int k1;
    float cbl[6], cbr[6];
    if (n <= SWEEP_MAX) {
        cut_sweep(s, v, n, k, lo, hi, &c, &k1);
        rt_box_empty(cbl); /* not needed below: the parts are swept too */
        rt_box_empty(cbr);
    } else {
        cut_binned(s, v, n, k, lo, hi, cb, &c, &k1, cbl, cbr);
    }
    if (n >= PART_TASK_MIN) {
#pragma omp task firstprivate(c, k1, cbl)
        partition(s, v, off, c, k1, lo, hi, cbl, out, g);
        partition(s, v + c, off + c, n - c, k - k1, lo, hi, cbr, out, g + k1);
#pragma omp taskwait
    } else {
        partition(s, v, off, c, k1, lo, hi, cbl, out, g);
        partition(s, v + c, off + c, n - c, k - k1, lo, hi, cbr, out, g + k1);
    }
}

/* ------------------------------------------------------ small subtrees */

/* A whole subtree of at most SWEEP_MAX triangles is built on three lists of
 * its triangles sorted by centre along each axis, sorted once: a cut takes
 * the first c of one list and stably partitions the other two, so every
 * range keeps its three sorted lists and no cut sorts again. Entries are
 * local indices (ties between equal centres go by them). */
typedef struct small {
    const sah *s;
    uint32_t first;             /* position of the subtree in idx */
    uint32_t id[SWEEP_MAX];     /* local index -> triangle id */
    uint8_t list[3][SWEEP_MAX]; /* local indices in centre order per axis */
    uint8_t left[SWEEP_MAX];    /* scratch: on the left of the cut */
} small;

/* The exact sweep of cut_sweep on the range [a, a + n) of the lists. */
static void small_cut(small *sm, uint32_t a, uint32_t n, int k, uint64_t lo, uint64_t hi,
                      uint32_t *c_out, int *k1_out)
{
    const sah *s = sm->s;
    uint8_t ok[SWEEP_MAX];
    memset(ok, 0, n);
    for (int k1 = 1; k1 < k; k1++) {
        uint64_t x, y;
        if (cut_interval(n, k, k1, lo, hi, &x, &y))
            for (uint64_t c = x; c <= y; c++) ok[c] = 1;
    }
    float right[SWEEP_MAX], best = TT_INF;
    int best_axis = -1;
    uint32_t best_c = 0;
    for (int axis = 0; axis < 3; axis++) {
        const uint8_t *l = sm->list[axis] + a;
        sbox b;
        sbox_empty(&b);
        for (uint32_t i = n; i-- > 1;) {
            sbox_grow(&b, s->tri_box + 6 * (size_t)sm->id[l[i]]);
            right[i] = sbox_area(&b);
        }
        sbox_empty(&b);
        for (uint32_t c = 1; c < n; c++) {
            sbox_grow(&b, s->tri_box + 6 * (size_t)sm->id[l[c - 1]]);
            if (!ok[c]) continue;
            float cost = sbox_area(&b) * (float)c + right[c] * (float)(n - c);
            if (cost < best) best = cost, best_axis = axis, best_c = c;
        }
    }
    if (best_axis < 0) { /* cannot happen for a feasible range */
        best_axis = 0;
        best_c = (uint32_t)nearest_cut(n, n / 2, k, lo, hi);
    }
    const uint8_t *l = sm->list[best_axis] + a;
    for (uint32_t i = 0; i < n; i++) sm->left[l[i]] = i < best_c;
    for (int axis = 0; axis < 3; axis++) {
        if (axis == best_axis) continue;
        uint8_t *m = sm->list[axis] + a, tmp[SWEEP_MAX];
        uint32_t nl = 0, nr = 0;
        for (uint32_t i = 0; i < n; i++) {
            if (sm->left[m[i]]) m[nl++] = m[i];
            else tmp[nr++] = m[i];
        }
        memcpy(m + nl, tmp, nr);
    }
    *c_out = best_c;
    *k1_out = pick_k1(n, best_c, k, lo, hi);
}

static void small_partition(small *sm, uint32_t a, uint32_t n, int k, uint64_t lo, uint64_t hi,
                            uint32_t *starts, int *g)
{
    if (k == 1) {
        starts[(*g)++] = a;
        return;
    }
    uint32_t c;
    int k1;
    small_cut(sm, a, n, k, lo, hi, &c, &k1);
    small_partition(sm, a, c, k1, lo, hi, starts, g);
    small_partition(sm, a + c, n - c, k - k1, lo, hi, starts, g);
}

static void small_node(small *sm, uint32_t a, uint32_t n, int level)
{
    const sah *s = sm->s;
    const uint64_t lo = s->lo[level - 1], hi = s->hi[level - 1];
    uint32_t starts[TT_RT_MAX_M + 1];
    int g = 0;
    small_partition(sm, a, n, choose_k(s, n, level), lo, hi, starts, &g);
    starts[g] = a + n;
    for (int j = 1; j < g; j++) s->mark[sm->first + starts[j]] = (uint8_t)level;
    if (level == 1) return;
    for (int j = 0; j < g; j++) small_node(sm, starts[j], starts[j + 1] - starts[j], level - 1);
}

/* The subtree on `level` holding idx[first .. first + n), n <= SWEEP_MAX. */
static void build_small(const sah *s, uint32_t first, uint32_t n, int level)
{
    small sm;
    sm.s = s;
    sm.first = first;
    uint32_t *v = s->idx + first;
    for (uint32_t i = 0; i < n; i++) sm.id[i] = v[i];
    for (int axis = 0; axis < 3; axis++) {
        uint64_t key[SWEEP_MAX];
        for (uint32_t i = 0; i < n; i++) key[i] = item_key(s->cen[3 * (size_t)v[i] + axis], i);
        sort_keys(key, n);
        for (uint32_t i = 0; i < n; i++) sm.list[axis][i] = (uint8_t)key[i];
    }
    small_node(&sm, 0, n, level);
    for (uint32_t i = 0; i < n; i++) v[i] = sm.id[sm.list[0][i]];
}

/* The node on `level` holding idx[first .. first + n), centre bounds cb,
 * with choose_k's children (the widest node at every level, measured
 * earlier against the fewest, ceil(n / hi), and halfway between, had been
 * the best of those three rules). */
static void build_node(const sah *s, uint32_t first, uint32_t n, int level, const float cb[6])
{
    if (n <= SWEEP_MAX) {
        build_small(s, first, n, level);
        return;
    }
    const uint64_t lo = s->lo[level - 1], hi = s->hi[level - 1];
    const int k = choose_k(s, n, level);
    group grp[TT_RT_MAX_M + 1];
    const int g = k;
    partition(s, s->idx + first, first, n, k, lo, hi, cb, grp, 0);
    grp[g].start = first + n;
    for (int j = 1; j < g; j++) s->mark[grp[j].start] = (uint8_t)level; /* level - 1, plus one */
    if (level == 1) return;
    for (int j = 0; j < g; j++) {
        const uint32_t f = grp[j].start, cn = grp[j + 1].start - grp[j].start;
        if (cn >= TASK_MIN) {
            group one = grp[j];
#pragma omp task firstprivate(f, cn, one)
            build_node(s, f, cn, level - 1, one.cb);
        } else {
            build_node(s, f, cn, level - 1, grp[j].cb);
        }
    }
}

/* Runs the SAH loader: *s gets the triangle order (idx) and the node marks
 * (mark), and the root level; s->cen, s->idx, s->mark are allocated here
 * (sah_free). */
static tt_status sah_run(sah *s, tt_context *ctx, const tt_rtree_options *opt,
                         const float *tri_box, uint32_t T)
{
    memset(s, 0, sizeof *s);
    s->tri_box = tri_box;
    s->m = opt->m;
    s->M = opt->M;
    /* capacities by level; the root level: smallest L with M^(L+1) >= T */
    int L = 0;
    for (int l = 0; l < TT_RT_BUILD_LEVELS; l++) {
        s->lo[l] = l == 0 ? (uint64_t)opt->m : s->lo[l - 1] * (uint64_t)opt->m;
        s->hi[l] = l == 0 ? (uint64_t)opt->M : s->hi[l - 1] * (uint64_t)opt->M;
        if (s->lo[l] > ((uint64_t)1 << 40)) s->lo[l] = (uint64_t)1 << 40; /* beyond any T */
        if (s->hi[l] > ((uint64_t)1 << 40)) s->hi[l] = (uint64_t)1 << 40;
        /* aim 0: the widest nodes (choose_k) */
        s->aim[l] = l == 0 ? (opt->M / LEAF_AIM_DIV > opt->m ? (uint64_t)(opt->M / LEAF_AIM_DIV) : 0)
                           : s->aim[l - 1] * (uint64_t)opt->M;
        if (s->aim[l] > ((uint64_t)1 << 40)) s->aim[l] = (uint64_t)1 << 40;
    }
    while (s->hi[L] < T) L++;
    s->root_level = L;
    const int threads = rt_bulk_threads(ctx);
    const size_t n = T ? T : 1;
    float *cen = NULL;
    tt_status st = rt_bulk_centres(ctx, tri_box, T, &cen);
    s->cen = cen;
    s->idx = tt_alloc_array(ctx, n, sizeof *s->idx);
    s->mark = tt_calloc(ctx, n, 1);
    if (st == TT_OK && (!s->idx || !s->mark))
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (SAH build, %u triangles)", T);
    if (st != TT_OK) return st;
    for (uint32_t i = 0; i < T; i++) s->idx[i] = i;
    if (T > 0) s->mark[0] = (uint8_t)(L + 1);
    if (L > 0) {
        float cb[6];
        centre_bounds(s, s->idx, T, cb);
#pragma omp parallel num_threads(threads) if (T >= SAH_PARALLEL_MIN)
#pragma omp single
        build_node(s, 0, T, L, cb);
    }
    return TT_OK;
}

static void sah_free(tt_context *ctx, sah *s)
{
    tt_free(ctx, (void *)s->cen);
    tt_free(ctx, s->idx);
    tt_free(ctx, s->mark);
    s->cen = NULL;
    s->idx = NULL;
    s->mark = NULL;
}

tt_status rt_bulk_sah(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                      const float *tri_box, uint32_t T)
{
    sah s;
    tt_status st = sah_run(&s, ctx, opt, tri_box, T);
    const int L = s.root_level, threads = rt_bulk_threads(ctx);
    /* T + 2: an empty scene's single empty leaf writes start[0] and start[1] */
    uint32_t *start = st == TT_OK ? tt_alloc_array(ctx, (size_t)T + 2, sizeof *start) : NULL;
    if (st == TT_OK && !start)
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (SAH build, %u triangles)", T);
    if (st == TT_OK) {
        /* nodes per level from the marks: a level-l node starts where
         * mark > l */
        uint32_t count[TT_RT_BUILD_LEVELS] = {0};
        uint64_t nodes = 0;
        for (int l = 0; l <= L; l++) {
            uint32_t c = 0;
            for (uint32_t p = 0; p < T; p++) c += s.mark[p] > l;
            count[l] = T ? c : 1;
            nodes += count[l];
        }
        st = rt_bulk_pool(b, ctx, opt, tri_box, T, (uint32_t)nodes);
        if (st == TT_OK) {
            /* leaves: their starts in the triangle order */
            uint32_t g = 0;
            for (uint32_t p = 0; p < T; p++)
                if (s.mark[p] > 0) start[g++] = p;
            start[g] = T;
            if (T == 0) start[0] = 0, start[1] = 0;
            rt_bulk_make_level(b, 0, s.idx, start, count[0], 0, threads);
            /* level l: its nodes group the level l-1 nodes starting where
             * mark > l; the level l-1 nodes' starts are rebuilt per level */
            uint32_t first = 0;
            for (int l = 1; l <= L; l++) {
                uint32_t below = count[l - 1], j = 0, gg = 0;
                for (uint32_t p = 0; p < T; p++) {
                    if (s.mark[p] > l - 1) {
                        if (s.mark[p] > l) start[gg++] = j;
                        s.idx[j] = first + j; /* the order is used up: reuse as ids */
                        j++;
                    }
                }
                start[gg] = below;
                rt_bulk_make_level(b, l, s.idx, start, count[l], first + below, threads);
                first += below;
            }
        }
    }
    sah_free(ctx, &s);
    tt_free(ctx, start);
    return st;
}

void rt_bulk_levels_free(tt_context *ctx, rt_bulk_levels *lv)
{
    tt_free(ctx, lv->order_mem);
    tt_free(ctx, lv->first_mem);
    tt_free(ctx, lv->box_mem);
    memset(lv, 0, sizeof *lv);
}

tt_status rt_bulk_sah_levels(rt_bulk_levels *lv, tt_context *ctx, const tt_rtree_options *opt,
                             const float *tri_box, uint32_t T)
{
    memset(lv, 0, sizeof *lv);
    sah s;
    tt_status st = sah_run(&s, ctx, opt, tri_box, T);
    const int L = s.root_level;
    if (st == TT_OK && (T == 0 || L == 0))
        st = tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                      "rtree: the level form needs a root above the leaves (%u triangles)", T);
    if (st != TT_OK) {
        sah_free(ctx, &s);
        return st;
    }
    /* nodes per level: a level-l node starts where mark > l */
    uint64_t total = 0;
    for (uint32_t p = 0; p < T; p++)
        for (int l = 0; l < s.mark[p]; l++) lv->count[l]++;
    for (int l = 0; l <= L; l++) total += lv->count[l];
    lv->first_mem = tt_alloc_array(ctx, total + (uint64_t)L + 1, sizeof(uint32_t));
    lv->box_mem = tt_alloc_array(ctx, total, 6 * sizeof(float));
    uint32_t *pos = tt_alloc_array(ctx, lv->count[0] + 1, sizeof *pos);
    if (!lv->first_mem || !lv->box_mem || !pos) {
        sah_free(ctx, &s);
        tt_free(ctx, pos);
        rt_bulk_levels_free(ctx, lv);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (SAH levels, %u triangles)",
                        T);
    }
    lv->height = (uint32_t)L;
    lv->M = (uint32_t)opt->M;
    lv->triangles = T;
    lv->order = lv->order_mem = s.idx;
    s.idx = NULL;
    {
        uint32_t *f = lv->first_mem;
        float *bx = lv->box_mem;
        for (int l = 0; l <= L; l++) {
            lv->first[l] = f;
            lv->box[l] = bx;
            f += lv->count[l] + 1;
            bx += 6 * (size_t)lv->count[l];
        }
    }
    /* leaves: their triangle ranges and boxes */
    uint32_t g = 0;
    for (uint32_t p = 0; p < T; p++)
        if (s.mark[p] > 0) lv->first[0][g++] = p;
    lv->first[0][g] = T;
    for (uint32_t j = 0; j < g; j++) {
        sbox b;
        sbox_empty(&b);
        for (uint32_t p = lv->first[0][j]; p < lv->first[0][j + 1]; p++)
            sbox_grow(&b, tri_box + 6 * (size_t)lv->order[p]);
        sbox_store(&b, lv->box[0] + 6 * (size_t)j);
        pos[j] = lv->first[0][j];
    }
    /* level l: groups the level l-1 nodes whose start (pos) has mark > l;
     * pos is rewritten in place to the level's own starts */
    for (int l = 1; l <= L; l++) {
        const uint32_t below = lv->count[l - 1];
        uint32_t gg = 0;
        for (uint32_t j = 0; j < below; j++)
            if (s.mark[pos[j]] > l) {
                lv->first[l][gg] = j;
                pos[gg++] = pos[j];
            }
        lv->first[l][gg] = below;
        const float *cb = lv->box[l - 1];
        for (uint32_t k = 0; k < gg; k++) {
            sbox b;
            sbox_empty(&b);
            for (uint32_t j = lv->first[l][k]; j < lv->first[l][k + 1]; j++)
                sbox_grow(&b, cb + 6 * (size_t)j);
            sbox_store(&b, lv->box[l] + 6 * (size_t)k);
        }
    }
    tt_free(ctx, pos);
    sah_free(ctx, &s);
    return TT_OK;
}
