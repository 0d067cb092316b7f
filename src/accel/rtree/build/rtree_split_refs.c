/* Early split clipping: references of cut triangles (rtree_split_refs.h). */
#include "accel/rtree/build/rtree_split_refs.h"

#include <math.h>
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "geometry/tri_block.h"

/* A polygon of a triangle clipped by up to 7 planes has at most 10 vertices. */
#define POLY_MAX 12

/* Sutherland-Hodgman against one plane: keeps the side x[axis] <= s
 * (below = 1) or >= s. A vertex made on the plane gets exactly s there. */
static int clip(const float (*in)[3], int n, int axis, float s, int below, float (*out)[3])
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        const float *p = in[i], *q = in[(i + 1) % n];
        const int pin = below ? p[axis] <= s : p[axis] >= s;
        const int qin = below ? q[axis] <= s : q[axis] >= s;
        if (pin) memcpy(out[m++], p, 3 * sizeof(float));
        if (pin != qin) {
            const float t = (s - p[axis]) / (q[axis] - p[axis]);
            for (int k = 0; k < 3; k++) out[m][k] = p[k] + t * (q[k] - p[k]);
            out[m++][axis] = s;
        }
    }
    return m;
}

static void poly_bounds(const float (*p)[3], int n, float b[6])
{
    rt_box_empty(b);
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            b[k] = rt_min(b[k], p[i][k]);
            b[k + 3] = rt_max(b[k + 3], p[i][k]);
        }
}

/* A cut of a piece: its two boxes and the area it saves. */
typedef struct cut {
    float gain;
    float l[6], r[6];
} cut;

/* The best midpoint cut of the piece with box pb of the triangle v (box
 * tb); 0 when no cut saves area. */
static int best_cut(const float *v, const float tb[6], const float pb[6], cut *out)
{
    float a[POLY_MAX][3], b[POLY_MAX][3];
    memcpy(a[0], v, 9 * sizeof(float));
    int n = 3;
    /* the triangle's part in the piece (the whole triangle's box clips
     * nothing) */
    if (!rt_box_equal(pb, tb)) {
        for (int k = 0; k < 6 && n > 0; k++) {
            n = clip((const float(*)[3])a, n, k % 3, pb[k], k < 3 ? 0 : 1, b);
            memcpy(a, b, (size_t)n * sizeof a[0]);
        }
    }
    if (n < 3) return 0;
    /* widening of bounds from clipped vertices: interpolation between the
     * triangle's vertices loses a few ulps of their magnitude a clip, and a
     * piece goes through up to 7 clips */
    float e[3];
    for (int k = 0; k < 3; k++)
        e[k] = rt_max(fabsf(tb[k]), fabsf(tb[k + 3])) * 0x1p-16f + 0x1p-100f;
    const float area = rt_box_area(pb);
    int found = 0;
    out->gain = 0.0f;
    for (int ax = 0; ax < 3; ax++) {
        const float s = 0.5f * (pb[ax] + pb[ax + 3]);
        if (!(s > pb[ax] && s < pb[ax + 3])) continue;
        float lo[POLY_MAX][3], hi[POLY_MAX][3];
        const int nl = clip((const float(*)[3])a, n, ax, s, 1, lo);
        const int nh = clip((const float(*)[3])a, n, ax, s, 0, hi);
        if (nl < 1 || nh < 1) continue;
        float L[6], R[6];
        poly_bounds((const float(*)[3])lo, nl, L);
        poly_bounds((const float(*)[3])hi, nh, R);
        for (int k = 0; k < 3; k++) {
            L[k] -= e[k], L[k + 3] += e[k];
            R[k] -= e[k], R[k + 3] += e[k];
        }
        L[ax + 3] = s; /* the plane is exact on both sides */
        R[ax] = s;
        for (int k = 0; k < 3; k++) { /* never past the parent piece */
            L[k] = rt_max(L[k], pb[k]), L[k + 3] = rt_min(L[k + 3], pb[k + 3]);
            R[k] = rt_max(R[k], pb[k]), R[k + 3] = rt_min(R[k + 3], pb[k + 3]);
        }
        const float g = area - rt_box_area(L) - rt_box_area(R);
        if (g > out->gain) {
            out->gain = g;
            memcpy(out->l, L, sizeof L);
            memcpy(out->r, R, sizeof R);
            found = 1;
        }
    }
    return found;
}

/* ------------------------------------------------------- max-heap of cuts */

typedef struct item {
    float gain;
    uint32_t piece;
} item;

static inline int above(item x, item y) /* x before y: more gain, then lower piece */
{
    return x.gain > y.gain || (x.gain == y.gain && x.piece < y.piece);
}

static void sift_down(item *h, uint32_t n, uint32_t i)
{
    const item x = h[i];
    for (;;) {
        uint32_t c = 2 * i + 1;
        if (c >= n) break;
        if (c + 1 < n && above(h[c + 1], h[c])) c++;
        if (!above(h[c], x)) break;
        h[i] = h[c];
        i = c;
    }
    h[i] = x;
}

static void sift_up(item *h, uint32_t i)
{
    const item x = h[i];
    while (i > 0) {
        const uint32_t p = (i - 1) / 2;
        if (!above(x, h[p])) break;
        h[i] = h[p];
        i = p;
    }
    h[i] = x;
}

tt_status rt_split_refs(tt_context *ctx, const float *tri, const float *tri_box, uint32_t T,
                        float budget, rt_refs *out)
{
    memset(out, 0, sizeof *out);
    uint64_t cap64 = (uint64_t)T + (uint64_t)((double)budget * (double)T);
    if (cap64 > ((uint64_t)1 << 31)) cap64 = (uint64_t)1 << 31;
    const uint32_t cap = (uint32_t)(cap64 ? cap64 : 1);
    out->box = tt_alloc_array(ctx, cap, 6 * sizeof(float));
    out->tri = tt_alloc_array(ctx, cap, sizeof(uint32_t));
    item *heap = tt_alloc_array(ctx, cap, sizeof *heap);
    if (!out->box || !out->tri || !heap) {
        tt_free(ctx, heap);
        rt_refs_free(ctx, out);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (%u split references)",
                        cap);
    }
    memcpy(out->box, tri_box, (size_t)T * 6 * sizeof(float));
    for (uint32_t i = 0; i < T; i++) out->tri[i] = i;
    /* every triangle's best cut (independent: in parallel) */
    const int threads = rt_bulk_threads(ctx);
#pragma omp parallel for schedule(static) num_threads(threads) if (T >= RT_BULK_PARALLEL_MIN / 4)
    for (uint32_t i = 0; i < T; i++) {
        const float *v = tri + 9 * (size_t)i, *tb = tri_box + 6 * (size_t)i;
        cut c;
        heap[i].piece = i;
        /* a flat box (a triangle in an axis plane: floors, walls) is left
         * whole: cutting it saves in-plane area, but its pieces then widen
         * every subtree they land in (conference's floor and ceiling were
         * cut into 64 pieces each and primary interior visits rose 7.1 ->
         * 9.7; sibenik's primary visits fell 11.2 -> 9.8 without them) */
        float lo_ext = TT_INF, hi_ext = 0.0f;
        for (int k = 0; k < 3; k++) {
            lo_ext = rt_min(lo_ext, tb[k + 3] - tb[k]);
            hi_ext = rt_max(hi_ext, tb[k + 3] - tb[k]);
        }
        const int flat = !(lo_ext > 0x1p-10f * hi_ext);
        heap[i].gain = !flat && !tt_tri_is_degenerate(v, v + 3, v + 6) && best_cut(v, tb, tb, &c)
                           ? c.gain : 0.0f;
    }
    uint32_t n = 0; /* keep the cuts that save area */
    for (uint32_t i = 0; i < T; i++)
        if (heap[i].gain > 0.0f) heap[n++] = heap[i];
    for (uint32_t i = n / 2; i-- > 0;) sift_down(heap, n, i);
    uint32_t R = T;
    while (R < cap && n > 0) {
        const uint32_t p = heap[0].piece, id = out->tri[p];
        heap[0] = heap[--n];
        if (n > 0) sift_down(heap, n, 0);
        const float *v = tri + 9 * (size_t)id, *tb = tri_box + 6 * (size_t)id;
        cut c, d;
        if (!best_cut(v, tb, out->box + 6 * (size_t)p, &c)) continue; /* as when pushed */
        memcpy(out->box + 6 * (size_t)p, c.l, sizeof c.l);
        memcpy(out->box + 6 * (size_t)R, c.r, sizeof c.r);
        out->tri[R] = id;
        const uint32_t q = R++;
        /* the heap holds at most one entry a piece, so it never outgrows cap */
        if (best_cut(v, tb, c.l, &d)) {
            heap[n] = (item){d.gain, p};
            sift_up(heap, n++);
        }
        if (best_cut(v, tb, c.r, &d)) {
            heap[n] = (item){d.gain, q};
            sift_up(heap, n++);
        }
    }
    out->count = R;
    tt_free(ctx, heap);
    return TT_OK;
}

void rt_refs_free(tt_context *ctx, rt_refs *r)
{
    tt_free(ctx, r->box);
    tt_free(ctx, r->tri);
    memset(r, 0, sizeof *r);
}

void rt_bulk_levels_merge_refs(rt_bulk_levels *lv, const uint32_t *ref_tri, uint32_t T)
{
    uint32_t *order = lv->order_mem, *first = lv->first[0], w = 0;
    for (uint32_t j = 0; j < lv->count[0]; j++) {
        const uint32_t a = first[j], e = first[j + 1]; /* w <= a: in place */
        first[j] = w;
        for (uint32_t p = a; p < e; p++) {
            const uint32_t id = ref_tri[order[p]];
            uint32_t k = first[j];
            while (k < w && order[k] != id) k++;
            if (k == w) order[w++] = id;
        }
    }
    first[lv->count[0]] = w;
    lv->triangles = T;
}
