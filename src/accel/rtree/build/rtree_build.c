/* R-tree construction by successive insertion (Guttman 1984; Beckmann et al.
 * 1990, the R*-tree), in 3D, with the node-selection strategies of Feldmann
 * (2015), section 5.1, and forced reinsertion.
 *
 * Speed: nodes live in one pool (indices, no per-insert allocation; the pool
 * grows by doubling), bounds are structure-of-arrays per node, triangle
 * boxes are precomputed, and the quadratic overlap criterion is evaluated
 * only where the strategy asks for it (for the R* variants only in the
 * nodes just above the leaves). The R*-paper's restriction of that
 * criterion to the 32 entries of least enlargement is moot here: a node
 * never has more than M <= 16 entries to choose from. */
#include "accel/rtree/build/rtree_build.h"

#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/rtree/build/rtree_choose_overlap.h"
#include "accel/rtree/rtree_box.h"

/* ------------------------------------------------------------------ pool */

static tt_status grow_pool(rt_builder *b)
{
    uint32_t cap = b->node_cap ? b->node_cap * 2 : 64;
    if (cap < b->node_cap || cap > UINT32_MAX / 2)
        return tt_error(b->ctx, TT_ERR_OUT_OF_MEMORY, "rtree: node pool exceeds 2^31 nodes");
    rt_node_hdr *hdr = tt_realloc_array(b->ctx, b->hdr, cap, sizeof *hdr);
    if (!hdr) return tt_error(b->ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (node pool)");
    b->hdr = hdr;
    float *box = tt_realloc_array(b->ctx, b->box, (size_t)cap * 6, (size_t)b->cap * sizeof *box);
    if (!box) return tt_error(b->ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (node pool)");
    b->box = box;
    uint32_t *child = tt_realloc_array(b->ctx, b->child, cap, (size_t)b->cap * sizeof *child);
    if (!child) return tt_error(b->ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (node pool)");
    b->child = child;
    b->node_cap = cap;
    return TT_OK;
}

static tt_status new_node(rt_builder *b, int level, uint32_t *out)
{
    uint32_t n;
    if (b->free_count) { /* a node a deletion gave back (rtree/update/) */
        n = b->free_node[--b->free_count];
    } else {
        if (b->node_count == b->node_cap) {
            tt_status st = grow_pool(b);
            if (st != TT_OK) return st;
        }
        n = b->node_count++;
    }
    b->hdr[n].parent = TT_INVALID_ID;
    b->hdr[n].slot = 0;
    b->hdr[n].count = 0;
    b->hdr[n].level = (uint8_t)level;
    b->hdr[n].pad = 0;
    memset(rt_node_box(b, n), 0, 6 * (size_t)b->cap * sizeof(float));
    *out = n;
    return TT_OK;
}

tt_status rt_builder_init(rt_builder *b, tt_context *ctx, const tt_rtree_options *opt,
                          const float *tri_box, uint32_t triangle_count_hint)
{
    memset(b, 0, sizeof *b);
    b->ctx = ctx;
    b->m = opt->m;
    b->M = opt->M;
    /* room for M + 1 entries, rounded up to whole SIMD lanes (see
     * choose_entry); the extra lanes hold zeros or stale entries, never read
     * as entries */
    b->cap = (opt->M + 1 + 3) & ~3;
    b->strategy = opt->strategy;
    b->split = opt->split;
    b->reinsert = opt->reinsert;
    int p = (int)(opt->reinsert_fraction * (float)(opt->M + 1));
    b->reinsert_count = p < 1 ? 1 : p;
    b->reinsert_far = opt->reinsert_far;
    b->tri_box = tri_box;
    b->overlap_keys = rt_overlap_keys_best();
    /* A first guess of the pool (nodes about 70% full) saves the early
     * doublings; it grows as needed. */
    uint64_t guess = (uint64_t)triangle_count_hint * 2 / (uint64_t)opt->M + 64;
    while (b->node_cap < guess && b->node_cap < (1u << 30)) {
        tt_status st = grow_pool(b);
        if (st != TT_OK) return st;
    }
    return new_node(b, 0, &b->root);
}

void rt_builder_free(rt_builder *b)
{
    tt_free(b->ctx, b->hdr);
    tt_free(b->ctx, b->box);
    tt_free(b->ctx, b->child);
    b->hdr = NULL;
    b->box = NULL;
    b->child = NULL;
}

/* ---------------------------------------------------------- node helpers */

void rt_node_bounds(const rt_builder *b, uint32_t n, float out[6])
{
    const float *s = rt_node_box(b, n);
    int cap = b->cap, cnt = b->hdr[n].count;
#if defined(__SSE2__)
    /* four entries at a time, the last four loaded again for a count that
     * is not a multiple of four (min and max do not mind seeing an entry
     * twice); the spare lanes past the count are never read. The scalar
     * loop was a twelfth of an edits frame (the condense step's climb and
     * the insertion search's root) */
    if (cnt >= 4) {
        for (int k = 0; k < 6; k++) {
            const float *row = s + k * cap;
            __m128 acc = _mm_loadu_ps(row);
            int i = 4;
            if (k < 3) {
                for (; i + 4 <= cnt; i += 4) acc = _mm_min_ps(acc, _mm_loadu_ps(row + i));
                if (i < cnt) acc = _mm_min_ps(acc, _mm_loadu_ps(row + cnt - 4));
                acc = _mm_min_ps(acc, _mm_shuffle_ps(acc, acc, _MM_SHUFFLE(1, 0, 3, 2)));
                acc = _mm_min_ps(acc, _mm_shuffle_ps(acc, acc, _MM_SHUFFLE(2, 3, 0, 1)));
            } else {
                for (; i + 4 <= cnt; i += 4) acc = _mm_max_ps(acc, _mm_loadu_ps(row + i));
                if (i < cnt) acc = _mm_max_ps(acc, _mm_loadu_ps(row + cnt - 4));
                acc = _mm_max_ps(acc, _mm_shuffle_ps(acc, acc, _MM_SHUFFLE(1, 0, 3, 2)));
                acc = _mm_max_ps(acc, _mm_shuffle_ps(acc, acc, _MM_SHUFFLE(2, 3, 0, 1)));
            }
            out[k] = _mm_cvtss_f32(acc);
        }
        return;
    }
#endif
    rt_box_empty(out);
    for (int k = 0; k < 3; k++) {
        for (int i = 0; i < cnt; i++) {
            out[k] = rt_min(out[k], s[k * cap + i]);
            out[k + 3] = rt_max(out[k + 3], s[(k + 3) * cap + i]);
        }
    }
}

void rt_builder_put(rt_builder *b, uint32_t n, const float e[6], uint32_t c)
{
    int i = b->hdr[n].count++;
    rt_builder_touch(b, n);
    rt_soa_put(rt_node_box(b, n), b->cap, i, e);
    rt_node_child(b, n)[i] = c;
    if (b->hdr[n].level > 0) {
        b->hdr[c].parent = n;
        b->hdr[c].slot = (uint8_t)i;
    } else if (b->leaf_of) {
        b->leaf_of[c] = n; /* every triangle lands here, whatever moved it */
    }
}

/* Recomputes node n's box in its parent, and so on upwards, after n lost
 * entries: node boxes stay the minimal union of their entries. Stops where
 * a box does not change, since everything above was exact before. */
static void tighten(rt_builder *b, uint32_t n)
{
    while (b->hdr[n].parent != TT_INVALID_ID) {
        uint32_t p = b->hdr[n].parent;
        float nb[6], old[6];
        rt_node_bounds(b, n, nb);
        float *ps = rt_node_box(b, p);
        rt_soa_get(ps, b->cap, b->hdr[n].slot, old);
        if (rt_box_equal(old, nb)) return;
        rt_soa_put(ps, b->cap, b->hdr[n].slot, nb);
        rt_builder_touch(b, p);
        n = p;
    }
}

/* ------------------------------------------------------ choose subtree */

/* Which entry of node n (level > the insertion level) receives box e.
 *
 * Zero-volume boxes (a flat triangle, all of an axis-aligned planar scene)
 * make every volume-based measure 0, so the volume and overlap criteria
 * tie everywhere there; every volume-based key is therefore followed by the
 * surface-area enlargement and the surface area, which keeps such builds
 * as good as min-surface instead of degenerating to "the first entry".
 * Keys, compared lexicographically:
 *   min-surface, rstar-surface (interior): d surface, surface
 *   min-volume, rstar (interior):          d volume, volume, d surface, surface
 *   min-overlap (everywhere), rstar (above the leaves):
 *                                          d overlap, d volume, volume, d surface, surface
 *   rstar-surface (above the leaves):      d overlap, d surface, surface
 * Surface areas are computed without the factor 2, which changes no order. */

static int keys_less(const float *a, const float *b, int n)
{
    for (int i = 0; i < n; i++) {
        if (a[i] < b[i]) return 1;
        if (a[i] > b[i]) return 0;
    }
    return 0;
}

/* The measures of node n's entries, four at a time where SIMD is available
 * (the scalar code's operations in the same order, so the same trees):
 * surface areas (without the factor 2) into area[] and those of their
 * unions with box e into grown[]; with vol (the volume strategies) also the
 * volumes into vol[] and the unions' into grown_vol[]. cnt rounds up to
 * whole SIMD lanes: the pool's spare lanes are read, their results unused. */
static void entry_measures(const rt_builder *b, uint32_t n, const float e[6], float *area,
                           float *grown, float *vol, float *grown_vol)
{
    const float *s = rt_node_box(b, n);
    const int cap = b->cap, cnt = b->hdr[n].count;
    const float *lx = s, *ly = s + cap, *lz = s + 2 * cap;
    const float *hx = s + 3 * cap, *hy = s + 4 * cap, *hz = s + 5 * cap;
#if defined(__SSE2__)
    const __m128 e0 = _mm_set1_ps(e[0]), e1 = _mm_set1_ps(e[1]), e2 = _mm_set1_ps(e[2]);
    const __m128 e3 = _mm_set1_ps(e[3]), e4 = _mm_set1_ps(e[4]), e5 = _mm_set1_ps(e[5]);
    for (int i = 0; i < cnt; i += 4) {
        const __m128 Lx = _mm_loadu_ps(lx + i), Ly = _mm_loadu_ps(ly + i);
        const __m128 Lz = _mm_loadu_ps(lz + i), Hx = _mm_loadu_ps(hx + i);
        const __m128 Hy = _mm_loadu_ps(hy + i), Hz = _mm_loadu_ps(hz + i);
        const __m128 ex = _mm_sub_ps(Hx, Lx), ey = _mm_sub_ps(Hy, Ly), ez = _mm_sub_ps(Hz, Lz);
        const __m128 ux = _mm_sub_ps(_mm_max_ps(Hx, e3), _mm_min_ps(Lx, e0));
        const __m128 uy = _mm_sub_ps(_mm_max_ps(Hy, e4), _mm_min_ps(Ly, e1));
        const __m128 uz = _mm_sub_ps(_mm_max_ps(Hz, e5), _mm_min_ps(Lz, e2));
        _mm_storeu_ps(area + i, _mm_add_ps(_mm_add_ps(_mm_mul_ps(ex, ey), _mm_mul_ps(ey, ez)),
                                           _mm_mul_ps(ez, ex)));
        _mm_storeu_ps(grown + i, _mm_add_ps(_mm_add_ps(_mm_mul_ps(ux, uy), _mm_mul_ps(uy, uz)),
                                            _mm_mul_ps(uz, ux)));
        if (vol) {
            _mm_storeu_ps(vol + i, _mm_mul_ps(_mm_mul_ps(ex, ey), ez));
            _mm_storeu_ps(grown_vol + i, _mm_mul_ps(_mm_mul_ps(ux, uy), uz));
        }
    }
#else
    for (int i = 0; i < cnt; i++) {
        const float ex = hx[i] - lx[i], ey = hy[i] - ly[i], ez = hz[i] - lz[i];
        const float ux = rt_max(hx[i], e[3]) - rt_min(lx[i], e[0]);
        const float uy = rt_max(hy[i], e[4]) - rt_min(ly[i], e[1]);
        const float uz = rt_max(hz[i], e[5]) - rt_min(lz[i], e[2]);
        area[i] = ex * ey + ey * ez + ez * ex;
        grown[i] = ux * uy + uy * uz + uz * ux;
        if (vol) {
            vol[i] = ex * ey * ez;
            grown_vol[i] = ux * uy * uz;
        }
    }
#endif
}

static int choose_entry(const rt_builder *b, uint32_t n, const float e[6])
{
    const rt_node_hdr *h = &b->hdr[n];
    const int cnt = h->count;
    const tt_rtree_strategy st = b->strategy;
    if (st == TT_RTREE_RRSTAR) return rt_choose_rrstar(b, n, e);
    /* The R* variants minimise overlap only when choosing among leaves. */
    const int overlap = st == TT_RTREE_MIN_OVERLAP ||
                        (h->level == 1 && (st == TT_RTREE_RSTAR || st == TT_RTREE_RSTAR_SURFACE));
    const int surface_only = st == TT_RTREE_MIN_SURFACE || st == TT_RTREE_RSTAR_SURFACE;

    if (!overlap) {
        /* the hot path: the measures of all entries (entry_measures), their
         * growths, then the lexicographic minimum */
        float area[TT_RT_CAP + 3], darea[TT_RT_CAP + 3], vol[TT_RT_CAP + 3], dvol[TT_RT_CAP + 3];
        entry_measures(b, n, e, area, darea, surface_only ? NULL : vol, dvol);
        for (int i = 0; i < cnt; i++) {
            darea[i] -= area[i];
            if (!surface_only) dvol[i] -= vol[i];
        }
        int best_i = 0;
        for (int i = 1; i < cnt; i++) {
            if (surface_only) {
                if (darea[i] < darea[best_i] ||
                    (darea[i] == darea[best_i] && area[i] < area[best_i]))
                    best_i = i;
            } else {
                float key[4] = {dvol[i], vol[i], darea[i], area[i]};
                float best[4] = {dvol[best_i], vol[best_i], darea[best_i], area[best_i]};
                if (keys_less(key, best, 4)) best_i = i;
            }
        }
        return best_i;
    }

    return rt_choose_overlap(b, n, e);
}

/* ------------------------------------------------------------- insertion */

static tt_status insert_entry(rt_builder *b, const float e[6], uint32_t c, int level);
static tt_status overflow(rt_builder *b, uint32_t n);

/* Splits overflowing node n (M + 1 entries) in two; may overflow its parent. */
static tt_status split_node(rt_builder *b, uint32_t n)
{
    const int level = b->hdr[n].level;
    const int is_root = n == b->root;
    uint32_t n2, r = TT_INVALID_ID;
    tt_status st = new_node(b, level, &n2);
    if (st != TT_OK) return st;
    if (is_root) {
        st = new_node(b, level + 1, &r);
        if (st != TT_OK) return st;
    }
    uint8_t group[TT_RT_CAP];
    if (b->split == TT_RTREE_SPLIT_QUADRATIC) rt_split_quadratic(b, n, group);
    else rt_split_rstar(b, n, group);

    /* Group 0 stays in n (in its order), group 1 moves to n2. */
    float *s = rt_node_box(b, n);
    uint32_t *ch = rt_node_child(b, n);
    const int cnt = b->hdr[n].count, cap = b->cap;
    int kept = 0;
    for (int i = 0; i < cnt; i++) {
        float eb[6];
        rt_soa_get(s, cap, i, eb);
        if (group[i]) {
            rt_builder_put(b, n2, eb, ch[i]);
        } else {
            rt_soa_put(s, cap, kept, eb);
            ch[kept] = ch[i];
            if (level > 0) b->hdr[ch[kept]].slot = (uint8_t)kept;
            kept++;
        }
    }
    b->hdr[n].count = (uint8_t)kept;
    rt_builder_touch(b, n);

    float nb[6], n2b[6];
    rt_node_bounds(b, n, nb);
    rt_node_bounds(b, n2, n2b);
    if (is_root) {
        rt_builder_put(b, r, nb, n);
        rt_builder_put(b, r, n2b, n2);
        b->root = r;
        return TT_OK;
    }
    uint32_t p = b->hdr[n].parent;
    rt_soa_put(rt_node_box(b, p), cap, b->hdr[n].slot, nb);
    rt_builder_put(b, p, n2b, n2); /* touches p */
    /* overflow treatment propagates upwards */
    if (b->hdr[p].count > b->M) return overflow(b, p);
    return TT_OK;
}

/* Forced reinsert (R*-tree): ejects the p entries of overflowing node n
 * whose centres lie farthest from the centre of n's box and inserts them
 * again at their level, far ones first (far reinsert) or near ones first
 * (close reinsert). */
static tt_status reinsert(rt_builder *b, uint32_t n)
{
    const int cap = b->cap, cnt = b->hdr[n].count, level = b->hdr[n].level;
    float *s = rt_node_box(b, n);
    uint32_t *ch = rt_node_child(b, n);
    float nb[6];
    rt_node_bounds(b, n, nb);
    float dist[TT_RT_CAP];
    int order[TT_RT_CAP];
    for (int i = 0; i < cnt; i++) {
        float d = 0.0f;
        for (int k = 0; k < 3; k++) {
            /* twice the centre offsets: the factor does not change the order */
            float o = (s[k * cap + i] + s[(k + 3) * cap + i]) - (nb[k] + nb[k + 3]);
            d += o * o;
        }
        dist[i] = d;
        /* insertion sort by decreasing distance, stable */
        int j = i;
        while (j > 0 && dist[order[j - 1]] < d) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = i;
    }
    const int p = b->reinsert_count;
    float ej_box[TT_RT_CAP][6];
    uint32_t ej_child[TT_RT_CAP];
    uint8_t eject[TT_RT_CAP] = {0};
    for (int k = 0; k < p; k++) {
        int i = order[k];
        eject[i] = 1;
        rt_soa_get(s, cap, i, ej_box[k]);
        ej_child[k] = ch[i];
    }
    int kept = 0;
    for (int i = 0; i < cnt; i++) {
        if (eject[i]) continue;
        float eb[6];
        rt_soa_get(s, cap, i, eb);
        rt_soa_put(s, cap, kept, eb);
        ch[kept] = ch[i];
        if (level > 0) b->hdr[ch[kept]].slot = (uint8_t)kept;
        kept++;
    }
    b->hdr[n].count = (uint8_t)kept;
    rt_builder_touch(b, n);
    tighten(b, n);
    for (int k = 0; k < p; k++) {
        int e = b->reinsert_far ? k : p - 1 - k;
        tt_status st = insert_entry(b, ej_box[e], ej_child[e], level);
        if (st != TT_OK) return st;
    }
    return TT_OK;
}

static tt_status overflow(rt_builder *b, uint32_t n)
{
    int level = b->hdr[n].level;
    if (n != b->root && b->reinsert && level < 32 && !(b->reinserted_levels & (1u << level))) {
        b->reinserted_levels |= 1u << level;
        return reinsert(b, n);
    }
    return split_node(b, n);
}

/* Entry i of node n grown to hold box e (an insertion passing through it). */
static void grow_entry(rt_builder *b, uint32_t n, int i, const float e[6])
{
    float *s = rt_node_box(b, n);
    const int cap = b->cap;
    rt_builder_touch(b, n);
    for (int k = 0; k < 3; k++) {
        s[k * cap + i] = rt_min(s[k * cap + i], e[k]);
        s[(k + 3) * cap + i] = rt_max(s[(k + 3) * cap + i], e[k + 3]);
    }
}

/* Half the surface area, as entry_measures measures it. */
static float half_area(const float b[6])
{
    const float x = b[3] - b[0], y = b[4] - b[1], z = b[5] - b[2];
    return x * y + y * z + z * x;
}

/* The SIMD lanes a node's entries round up to (the pool's spare lanes are
 * read there, and their results set aside). */
#define LANES4(cnt) (((cnt) + 3) & ~3)

/* rt_builder.sah_leaves: the leaf of level-1 node n (of half area an,
 * before e) whose cost grows least by taking box e (of half area ae), or
 * -1 where a new leaf of e alone costs less; the cost into *cost. */
static int choose_leaf_sah(const rt_builder *b, uint32_t n, const float e[6], float ae, float an,
                           float *cost)
{
    const uint32_t *ch = rt_node_child(b, n);
    const int cnt = b->hdr[n].count, M = b->M;
    float area[TT_RT_CAP + 3], grown[TT_RT_CAP + 3];
    entry_measures(b, n, e, area, grown, NULL, NULL);
    /* a new leaf in a full node splits it: one more node to visit, about
     * as big as n (the same for a full leaf, whose split adds a leaf) */
    const float split = cnt >= M ? b->sah_split_cost * an : 0.0f;
    float best = ae + split;
    int best_i = -1;
#if defined(__SSE2__)
    /* the leaves' counts gathered, then every cost four at a time (the
     * scalar loop's operations in its order) and the first least one: a
     * third of the search's instructions were this loop, scalar */
    float kf[TT_RT_CAP + 3], sp[TT_RT_CAP + 3];
    int i = 0;
    for (; i < cnt; i++) {
        const int kc = b->hdr[ch[i]].count;
        kf[i] = (float)kc;
        sp[i] = kc >= M ? split : 0.0f;
    }
    for (; i < LANES4(cnt); i++) { /* spare lanes: cost +inf */
        kf[i] = 0.0f;
        sp[i] = TT_INF;
    }
    const __m128 one = _mm_set1_ps(1.0f);
    __m128 lo = _mm_set1_ps(TT_INF), cv[(TT_RT_CAP + 3) / 4];
    for (i = 0; i < cnt; i += 4) {
        const __m128 k = _mm_loadu_ps(kf + i);
        const __m128 c = _mm_add_ps(_mm_sub_ps(_mm_mul_ps(_mm_loadu_ps(grown + i), _mm_add_ps(k, one)),
                                               _mm_mul_ps(_mm_loadu_ps(area + i), k)),
                                    _mm_loadu_ps(sp + i));
        cv[i / 4] = c;
        lo = _mm_min_ps(c, lo); /* a NaN cost is never chosen, as in the scalar loop */
    }
    lo = _mm_min_ps(lo, _mm_shuffle_ps(lo, lo, _MM_SHUFFLE(1, 0, 3, 2)));
    lo = _mm_min_ps(lo, _mm_shuffle_ps(lo, lo, _MM_SHUFFLE(2, 3, 0, 1)));
    const float m = _mm_cvtss_f32(lo);
    if (m < best) {
        best = m;
        for (i = 0; i < cnt; i += 4) {
            const int eq = _mm_movemask_ps(_mm_cmpeq_ps(cv[i / 4], lo));
            if (eq) {
                best_i = i + __builtin_ctz((unsigned)eq);
                break;
            }
        }
    }
#else
    for (int i = 0; i < cnt; i++) {
        const int kc = b->hdr[ch[i]].count;
        const float k = (float)kc;
        const float c = grown[i] * (k + 1.0f) - area[i] * k + (kc >= M ? split : 0.0f);
        if (c < best) {
            best = c;
            best_i = i;
        }
    }
#endif
    *cost = best;
    return best_i;
}

/* Node n's entries against box e, as entry_measures measures them: half
 * areas into area[], the growth by e into d[]; the lanes past the count
 * get +inf growth, so that no choice or bound takes them. */
static void entry_growth(const rt_builder *b, uint32_t n, const float e[6], float *area, float *d)
{
    const int cnt = b->hdr[n].count;
    float grown[TT_RT_CAP + 3];
    entry_measures(b, n, e, area, grown, NULL, NULL);
#if defined(__SSE2__)
    const __m128 inf = _mm_set1_ps(TT_INF), lane = _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f);
    const __m128 count = _mm_set1_ps((float)cnt);
    for (int i = 0; i < cnt; i += 4) {
        const __m128 g = _mm_sub_ps(_mm_loadu_ps(grown + i), _mm_loadu_ps(area + i));
        const __m128 out = _mm_cmpge_ps(_mm_add_ps(lane, _mm_set1_ps((float)i)), count);
        _mm_storeu_ps(d + i, _mm_or_ps(_mm_and_ps(out, inf), _mm_andnot_ps(out, g)));
    }
#else
    for (int i = 0; i < cnt; i++) d[i] = grown[i] - area[i];
    for (int i = cnt; i < LANES4(cnt); i++) d[i] = TT_INF;
#endif
}

/* The greedy choice among cnt entries: the least growth, then the least
 * area, then the first. */
static int greedy_pick(const float *area, const float *d, int cnt)
{
#if defined(__SSE2__)
    __m128 lo = _mm_set1_ps(TT_INF);
    for (int i = 0; i < cnt; i += 4) lo = _mm_min_ps(_mm_loadu_ps(d + i), lo);
    lo = _mm_min_ps(lo, _mm_shuffle_ps(lo, lo, _MM_SHUFFLE(1, 0, 3, 2)));
    lo = _mm_min_ps(lo, _mm_shuffle_ps(lo, lo, _MM_SHUFFLE(2, 3, 0, 1)));
    /* among the least growths, the least area; only the entries' lanes:
     * where every growth is +inf (boxes whose areas overflow a float) the
     * spare lanes' +inf equals the least too, and their areas are the
     * pool's leftovers */
    const __m128 inf = _mm_set1_ps(TT_INF), lane = _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f);
    const __m128 count = _mm_set1_ps((float)cnt);
    __m128 la = inf;
    for (int i = 0; i < cnt; i += 4) {
        const __m128 live = _mm_cmplt_ps(_mm_add_ps(lane, _mm_set1_ps((float)i)), count);
        const __m128 eq = _mm_and_ps(live, _mm_cmpeq_ps(_mm_loadu_ps(d + i), lo));
        la = _mm_min_ps(_mm_or_ps(_mm_and_ps(eq, _mm_loadu_ps(area + i)), _mm_andnot_ps(eq, inf)),
                        la);
    }
    la = _mm_min_ps(la, _mm_shuffle_ps(la, la, _MM_SHUFFLE(1, 0, 3, 2)));
    la = _mm_min_ps(la, _mm_shuffle_ps(la, la, _MM_SHUFFLE(2, 3, 0, 1)));
    for (int i = 0; i < cnt; i += 4) {
        const int live = cnt - i >= 4 ? 0xf : (1 << (cnt - i)) - 1;
        const int hit = live & _mm_movemask_ps(_mm_and_ps(_mm_cmpeq_ps(_mm_loadu_ps(d + i), lo),
                                                          _mm_cmpeq_ps(_mm_loadu_ps(area + i), la)));
        if (hit) return i + __builtin_ctz((unsigned)hit);
    }
#endif
    int bi = 0; /* the scalar choice (also where the lanes found none: NaN) */
    for (int i = 1; i < cnt; i++)
        if (d[i] < d[bi] || (d[i] == d[bi] && area[i] < area[bi])) bi = i;
    return bi;
}

/* Bit i set where ind + d[i] + ae < best: entry i's subtree may hold a
 * place cheaper than the best so far. */
static unsigned promising(const float *d, int cnt, float ind, float ae, float best)
{
    unsigned mask = 0;
#if defined(__SSE2__)
    const __m128 vi = _mm_set1_ps(ind), va = _mm_set1_ps(ae), vb = _mm_set1_ps(best);
    for (int i = 0; i < cnt; i += 4)
        mask |= (unsigned)_mm_movemask_ps(
                    _mm_cmplt_ps(_mm_add_ps(_mm_add_ps(vi, _mm_loadu_ps(d + i)), va), vb))
                << i;
#else
    for (int i = 0; i < cnt; i++) mask |= (unsigned)(ind + d[i] + ae < best) << i;
#endif
    return mask;
}

typedef struct sah_cand {
    float lb, ind, area; /* bound, the path's growth, the node's half area */
    uint32_t n;
} sah_cand;
#define SAH_HEAP 512

static void heap_push(sah_cand *h, int *cnt, sah_cand c)
{
    if (*cnt == SAH_HEAP) return; /* full: the candidate is dropped */
    int i = (*cnt)++;
    while (i > 0 && h[(i - 1) / 2].lb > c.lb) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = c;
}

static sah_cand heap_pop(sah_cand *h, int *cnt)
{
    sah_cand top = h[0], last = h[--*cnt];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= *cnt) break;
        if (c + 1 < *cnt && h[c + 1].lb < h[c].lb) c++;
        if (h[c].lb >= last.lb) break;
        h[i] = h[c];
        i = c;
    }
    if (*cnt) h[i] = last;
    return top;
}

/* The entries of node n (their growths d[], areas area[], the path's
 * growth ind above n) that may beat `best` onto the heap, but `skip`. */
static void push_promising(const rt_builder *b, uint32_t n, const float *area, const float *d,
                           float ind, float ae, float best, int skip, sah_cand *heap, int *cnt)
{
    const uint32_t *ch = rt_node_child(b, n);
    unsigned mask = promising(d, b->hdr[n].count, ind, ae, best);
    if (skip >= 0) mask &= ~(1u << skip);
    while (mask) {
        const int i = __builtin_ctz(mask);
        mask &= mask - 1;
        const float in = ind + d[i];
        heap_push(heap, cnt, (sah_cand){in + ae, in, area[i], ch[i]});
    }
}

/* Where the SAH search puts a triangle: a level-1 node and its leaf
 * there (-1: a new leaf). */
typedef struct sah_place {
    uint32_t n;
    int leaf;
} sah_place;

/* rt_builder.sah_leaves: the level-1 node where box e costs least
 * (Bittner et al. 2013's search: best first by the area the path's boxes
 * grow, bounded by the least a leaf can cost, A(e)), and the leaf there.
 * The greedy descent (least growth at each level) goes first: its cost
 * bounds the search, and the entries it passed by go on the heap with the
 * measures it took, so the search never measures the greedy path again
 * (measuring it twice was a quarter of the search's instructions). A
 * node's entries are measured and screened four at a time (entry_growth,
 * greedy_pick, promising): only the entries that pass are touched one by
 * one. */
static sah_place find_level1_sah(const rt_builder *b, const float e[6])
{
    sah_cand heap[SAH_HEAP];
    int cnt = 0, evals = 1; /* the greedy node is the first evaluated */
    const float ae = half_area(e);
    /* the path's nodes, their entries' measures, the greedy choice and the
     * path's growth above them */
    float area[TT_RT_BUILD_LEVELS][TT_RT_CAP + 3], d[TT_RT_BUILD_LEVELS][TT_RT_CAP + 3];
    uint32_t path[TT_RT_BUILD_LEVELS];
    float path_ind[TT_RT_BUILD_LEVELS];
    int pick[TT_RT_BUILD_LEVELS], depth = 0;
    uint32_t n = b->root;
    float ind = 0.0f, na = 0.0f;
    if (b->hdr[n].level <= 1) { /* the root is the level-1 node: its own area */
        float rb[6];
        rt_node_bounds(b, n, rb);
        na = half_area(rb);
    }
    while (b->hdr[n].level > 1) {
        float *ar = area[depth], *dd = d[depth];
        entry_growth(b, n, e, ar, dd);
        const int bi = greedy_pick(ar, dd, b->hdr[n].count);
        path[depth] = n;
        path_ind[depth] = ind;
        pick[depth++] = bi;
        ind += dd[bi];
        na = ar[bi];
        n = rt_node_child(b, n)[bi];
    }
    float lc;
    sah_place best_p = {n, choose_leaf_sah(b, n, e, ae, na, &lc)};
    float best = ind + lc;
    for (int k = 0; k < depth; k++)
        push_promising(b, path[k], area[k], d[k], path_ind[k], ae, best, pick[k], heap, &cnt);
    int pops = 0;
    while (cnt) {
        const sah_cand c = heap_pop(heap, &cnt);
        if (c.lb >= best || evals >= b->sah_max_evals) break;
        if (b->sah_max_pops && pops++ >= b->sah_max_pops) break;
        const uint32_t m = c.n;
        if (b->hdr[m].level == 1) {
            const int li = choose_leaf_sah(b, m, e, ae, c.area, &lc);
            if (c.ind + lc < best) {
                best = c.ind + lc;
                best_p = (sah_place){m, li};
            }
            evals++;
            continue;
        }
        float ar[TT_RT_CAP + 3], dd[TT_RT_CAP + 3];
        entry_growth(b, m, e, ar, dd);
        push_promising(b, m, ar, dd, c.ind, ae, best, -1, heap, &cnt);
    }
    return best_p;
}

static tt_status overflow(rt_builder *b, uint32_t n);

/* rt_builder.sah_leaves: triangle entry (e, c) into the leaf or new leaf
 * the search found; the boxes on the way up grown to hold e (the level-1
 * node's own entries do not change by that, so the search's choice of
 * leaf stands). */
static tt_status insert_triangle_sah(rt_builder *b, const float e[6], uint32_t c)
{
    const sah_place at = find_level1_sah(b, e);
    const uint32_t n = at.n;
    for (uint32_t m = n; b->hdr[m].parent != TT_INVALID_ID; m = b->hdr[m].parent) {
        const uint32_t p = b->hdr[m].parent;
        float *s = rt_node_box(b, p);
        const int cap = b->cap, i = b->hdr[m].slot;
        rt_builder_touch(b, p);
        for (int k = 0; k < 3; k++) {
            s[k * cap + i] = rt_min(s[k * cap + i], e[k]);
            s[(k + 3) * cap + i] = rt_max(s[(k + 3) * cap + i], e[k + 3]);
        }
    }
    const int i = at.leaf;
    if (i < 0) { /* a leaf of its own, entered in n */
        uint32_t leaf;
        tt_status st = new_node(b, 0, &leaf);
        if (st != TT_OK) return st;
        rt_builder_put(b, leaf, e, c);
        rt_builder_put(b, n, e, leaf);
        if (b->hdr[n].count > b->M) return overflow(b, n);
        return TT_OK;
    }
    grow_entry(b, n, i, e);
    const uint32_t leaf = rt_node_child(b, n)[i];
    rt_builder_put(b, leaf, e, c);
    if (b->hdr[leaf].count > b->M) return overflow(b, leaf);
    return TT_OK;
}

/* Inserts entry (box e, child c) into a node at `level`, descending from the
 * root by the strategy and growing the boxes on the way (they then hold e). */
static tt_status insert_entry(rt_builder *b, const float e[6], uint32_t c, int level)
{
    if (b->sah_leaves && level == 0 && b->hdr[b->root].level >= 1)
        return insert_triangle_sah(b, e, c);
    uint32_t n = b->root;
    while (b->hdr[n].level > level) {
        const int i = choose_entry(b, n, e);
        grow_entry(b, n, i, e);
        n = rt_node_child(b, n)[i];
    }
    rt_builder_put(b, n, e, c);
    if (b->hdr[n].count > b->M) return overflow(b, n);
    return TT_OK;
}

tt_status rt_builder_insert_triangle(rt_builder *b, uint32_t id)
{
    b->reinserted_levels = 0;
    tt_status st = insert_entry(b, b->tri_box + 6 * (size_t)id, id, 0);
    if (st == TT_OK) b->triangles++;
    return st;
}

tt_status rt_builder_new_node(rt_builder *b, int level, uint32_t *out)
{
    return new_node(b, level, out);
}

tt_status rt_builder_insert_entry(rt_builder *b, const float e[6], uint32_t c, int level)
{
    b->reinserted_levels = 0;
    return insert_entry(b, e, c, level);
}
