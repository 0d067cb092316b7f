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
 * elsewhere), a range the node's own capacity makes non-empty. The node's
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
#include <stdlib.h>
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/rtree_bulk.h"

#define BINS 32
#define SWEEP_MAX 64      /* ranges up to this size are swept exactly */
#define TASK_MIN 4096     /* subtrees of at least this many triangles are tasks */

typedef struct sah {
    const float *tri_box;
    const float *cen; /* 3 floats a triangle */
    uint32_t *idx;    /* triangle ids, becoming leaf order */
    uint8_t *mark;    /* per position: 1 + the highest level whose node starts here; 0 none */
    uint64_t lo[TT_RT_BUILD_LEVELS], hi[TT_RT_BUILD_LEVELS]; /* subtree capacity by its level */
    int m, M, root_level;
} sah;

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

/* The feasible cut nearest c. */
static uint64_t nearest_cut(uint64_t n, uint64_t c, int k, uint64_t lo, uint64_t hi)
{
    uint64_t best = 0, dist = UINT64_MAX;
    for (int k1 = 1; k1 < k; k1++) {
        const uint64_t k2 = (uint64_t)(k - k1);
        uint64_t a = (uint64_t)k1 * lo, b = (uint64_t)k1 * hi;
        if (n > k2 * hi && n - k2 * hi > a) a = n - k2 * hi;
        if (n - k2 * lo < b) b = n - k2 * lo; /* n >= k lo > k2 lo */
        if (a > b) continue;
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

static void sort_axis(const sah *s, int axis, uint32_t *v, uint32_t n)
{
    for (uint32_t i = 1; i < n; i++) {
        uint32_t x = v[i], j = i;
        while (j > 0 && before(s, axis, x, v[j - 1])) {
            v[j] = v[j - 1];
            j--;
        }
        v[j] = x;
    }
}

static inline float area_of(const float b[6])
{
    return b[3] >= b[0] ? rt_box_area(b) : 0.0f;
}

/* ----------------------------------------------------------------- cuts */

/* Cuts v[0 .. n), which must become k groups of lo..hi, into a left part
 * v[0 .. *c) of *k1 groups: small ranges by an exact sweep. */
static void cut_sweep(const sah *s, uint32_t *v, uint32_t n, int k, uint64_t lo, uint64_t hi,
                      uint32_t *c_out, int *k1_out)
{
    uint32_t sorted[3][SWEEP_MAX];
    float right[SWEEP_MAX];
    float best = TT_INF;
    int best_axis = -1;
    uint32_t best_c = 0;
    for (int axis = 0; axis < 3; axis++) {
        memcpy(sorted[axis], v, n * sizeof *v);
        sort_axis(s, axis, sorted[axis], n);
        float b[6];
        rt_box_empty(b);
        for (uint32_t i = n; i-- > 1;) {
            rt_box_grow(b, s->tri_box + 6 * (size_t)sorted[axis][i]);
            right[i] = rt_box_area(b);
        }
        rt_box_empty(b);
        for (uint32_t c = 1; c < n; c++) {
            rt_box_grow(b, s->tri_box + 6 * (size_t)sorted[axis][c - 1]);
            if (!pick_k1(n, c, k, lo, hi)) continue;
            float cost = rt_box_area(b) * (float)c + right[c] * (float)(n - c);
            if (cost < best) best = cost, best_axis = axis, best_c = c;
        }
    }
    if (best_axis < 0) { /* cannot happen for a feasible range; keep the order */
        best_axis = 0;
        best_c = (uint32_t)nearest_cut(n, n / 2, k, lo, hi);
    }
    memcpy(v, sorted[best_axis], n * sizeof *v);
    *c_out = best_c;
    *k1_out = pick_k1(n, best_c, k, lo, hi);
}

/* The same for large ranges, by binning the centres. */
static void cut_binned(const sah *s, uint32_t *v, uint32_t n, int k, uint64_t lo, uint64_t hi,
                       uint32_t *c_out, int *k1_out)
{
    float clo[3] = {TT_INF, TT_INF, TT_INF}, chi[3] = {-TT_INF, -TT_INF, -TT_INF};
    for (uint32_t i = 0; i < n; i++) {
        const float *c = s->cen + 3 * (size_t)v[i];
        for (int a = 0; a < 3; a++) {
            clo[a] = rt_min(clo[a], c[a]);
            chi[a] = rt_max(chi[a], c[a]);
        }
    }
    float best = TT_INF;
    int best_axis = -1;
    uint32_t best_c = 0;
    for (int axis = 0; axis < 3; axis++) {
        if (!(chi[axis] > clo[axis])) continue;
        const float scale = (float)BINS / (chi[axis] - clo[axis]);
        uint32_t cnt[BINS] = {0};
        float box[BINS][6];
        for (int j = 0; j < BINS; j++) rt_box_empty(box[j]);
        for (uint32_t i = 0; i < n; i++) {
            int j = (int)((s->cen[3 * (size_t)v[i] + axis] - clo[axis]) * scale);
            j = j < 0 ? 0 : j >= BINS ? BINS - 1 : j;
            cnt[j]++;
            rt_box_grow(box[j], s->tri_box + 6 * (size_t)v[i]);
        }
        /* prefix: bins [0, j); suffix: bins [j, BINS) */
        float pre_a[BINS + 1], suf_a[BINS + 1];
        uint32_t pre_c[BINS + 1];
        float b[6];
        rt_box_empty(b);
        pre_a[0] = 0.0f;
        pre_c[0] = 0;
        for (int j = 0; j < BINS; j++) {
            rt_box_grow(b, box[j]);
            pre_a[j + 1] = area_of(b);
            pre_c[j + 1] = pre_c[j] + cnt[j];
        }
        rt_box_empty(b);
        suf_a[BINS] = 0.0f;
        for (int j = BINS; j-- > 0;) {
            rt_box_grow(b, box[j]);
            suf_a[j] = area_of(b);
        }
        for (int j = 1; j < BINS; j++) {
            uint32_t c = pre_c[j];
            uint32_t f = (uint32_t)nearest_cut(n, c, k, lo, hi);
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
            if (cost < best) best = cost, best_axis = axis, best_c = f;
        }
    }
    if (best_axis < 0) { /* all centres equal: any cut, by id */
        best_axis = 0;
        best_c = (uint32_t)nearest_cut(n, (uint64_t)n * (uint64_t)(k / 2) / (uint64_t)k, k, lo, hi);
    }
    select_first(s, best_axis, v, n, best_c);
    *c_out = best_c;
    *k1_out = pick_k1(n, best_c, k, lo, hi);
}

/* Cuts v[0 .. n) into k groups of lo..hi triangles; their starts (offsets
 * from v) are appended to starts[*g]. */
static void partition(const sah *s, uint32_t *v, uint32_t off, uint32_t n, int k, uint64_t lo,
                      uint64_t hi, uint32_t *starts, int *g)
{
    if (k == 1) {
        starts[(*g)++] = off;
        return;
    }
    uint32_t c;
    int k1;
    if (n <= SWEEP_MAX) cut_sweep(s, v, n, k, lo, hi, &c, &k1);
    else cut_binned(s, v, n, k, lo, hi, &c, &k1);
    partition(s, v, off, c, k1, lo, hi, starts, g);
    partition(s, v + c, off + c, n - c, k - k1, lo, hi, starts, g);
}

/* The node on `level` holding idx[first .. first + n). */
static void build_node(const sah *s, uint32_t first, uint32_t n, int level)
{
    const uint64_t lo = s->lo[level - 1], hi = s->hi[level - 1];
    const int kmin = level == s->root_level ? 2 : s->m;
    uint64_t kmax = n / lo;
    if (kmax > (uint64_t)s->M) kmax = (uint64_t)s->M;
    uint64_t kneed = (n + hi - 1) / hi;
    if (kneed < (uint64_t)kmin) kneed = (uint64_t)kmin;
    static int policy = -1;
    if (policy < 0) { const char *e = getenv("RTB_K"); policy = e ? atoi(e) : 0; }
    const int k = policy == 0 ? (int)kmax : policy == 1 ? (int)kneed : (int)((kmax + kneed + 1) / 2);
    uint32_t starts[TT_RT_MAX_M + 1];
    int g = 0;
    partition(s, s->idx + first, first, n, k, lo, hi, starts, &g);
    starts[g] = first + n;
    for (int j = 1; j < g; j++) s->mark[starts[j]] = (uint8_t)level; /* level - 1, plus one */
    if (level == 1) return;
    for (int j = 0; j < g; j++) {
        const uint32_t f = starts[j], cn = starts[j + 1] - starts[j];
        if (cn >= TASK_MIN) {
#pragma omp task firstprivate(f, cn)
            build_node(s, f, cn, level - 1);
        } else {
            build_node(s, f, cn, level - 1);
        }
    }
}

tt_status rt_bulk_sah(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                      const float *tri_box, uint32_t T)
{
    sah s;
    memset(&s, 0, sizeof s);
    s.tri_box = tri_box;
    s.m = opt->m;
    s.M = opt->M;
    /* capacities by level; the root level: smallest L with M^(L+1) >= T */
    int L = 0;
    for (int l = 0; l < TT_RT_BUILD_LEVELS; l++) {
        s.lo[l] = l == 0 ? (uint64_t)opt->m : s.lo[l - 1] * (uint64_t)opt->m;
        s.hi[l] = l == 0 ? (uint64_t)opt->M : s.hi[l - 1] * (uint64_t)opt->M;
        if (s.lo[l] > ((uint64_t)1 << 40)) s.lo[l] = (uint64_t)1 << 40; /* beyond any T */
        if (s.hi[l] > ((uint64_t)1 << 40)) s.hi[l] = (uint64_t)1 << 40;
    }
    while (s.hi[L] < T) L++;
    s.root_level = L;
    const int threads = rt_bulk_threads(ctx);
    const size_t n = T ? T : 1;
    float *cen = NULL;
    tt_status st = rt_bulk_centres(ctx, tri_box, T, &cen);
    s.cen = cen;
    s.idx = tt_alloc_array(ctx, n, sizeof *s.idx);
    s.mark = tt_calloc(ctx, n, 1);
    uint32_t *start = tt_alloc_array(ctx, n + 1, sizeof *start);
    if (st == TT_OK && (!s.idx || !s.mark || !start))
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (SAH build, %u triangles)", T);
    if (st == TT_OK) {
        for (uint32_t i = 0; i < T; i++) s.idx[i] = i;
        if (T > 0) s.mark[0] = (uint8_t)(L + 1);
        if (L > 0) {
#pragma omp parallel num_threads(threads)
#pragma omp single
            build_node(&s, 0, T, L);
        }
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
    tt_free(ctx, cen);
    tt_free(ctx, s.idx);
    tt_free(ctx, s.mark);
    tt_free(ctx, start);
    return st;
}
