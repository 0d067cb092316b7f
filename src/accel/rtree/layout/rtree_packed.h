/* The packed R-tree of Feldmann (2015), section 4, shared by the CPU and the
 * GPU traversals: the complete M-ary tree of height L + 1 numbered in level
 * order (root 0, then its M child slots, ...), empty slots included, in one
 * array. Navigation is pure index arithmetic:
 *
 *   Delta_L(l) = first slot of level l = sum_{i=0}^{L-l-1} M^i  (0 for l = L)
 *   n_e(n)     = (n - Delta_L(l)) * M + Delta_L(l - 1)     first child
 *   n_p(n)     = (n - Delta_L(l)) / M + Delta_L(l + 1)     parent
 *   chi(n)     = (n - Delta_L(l)) mod M                    position in parent
 *
 * Storage of the slot array (all plain arrays, no pointers between nodes):
 *  - box: the slots' boxes, structure of arrays per sibling group. Slot n
 *    lives in group (n + M - 1) / M at position (n + M - 1) mod M: the root
 *    alone in group 0 (position M - 1), and the M children of any node form
 *    exactly one group, so a node's children are six contiguous runs of M
 *    floats (lo x[M], lo y[M], lo z[M], hi x[M], hi y[M], hi z[M]) that the
 *    ordered and stack traversals test together. An empty slot has all six
 *    bounds +inf (a point at infinity: every slab test misses it) — that is
 *    the "empty" mark.
 *  - count: entries of every slot on levels >= 1 (slots 0 .. Delta_L(0)-1);
 *    0 for an empty slot. A node's entries are always its first count
 *    child slots.
 *  - leaf_start: the triangles of leaf slot Delta_L(0) + j are
 *    tri[leaf_start[j] .. leaf_start[j + 1]) (prefix sums over all M^L leaf
 *    slots, so an empty leaf has an empty range).
 *  - tri: the triangles' 9 floats in leaf order, a separate array rather than
 *    inline in the slots: most leaf slots are empty (the complete tree is
 *    much bigger than the real one), and inline storage would pay M * 36
 *    bytes for each of them; separately the triangles cost exactly 36 bytes
 *    each and a leaf's triangles are still contiguous.
 *  - prim: the triangles' load-order ids, in leaf order.
 * Indices are 32-bit; the builder refuses trees of 2^32 slots or more. */
#ifndef TT_ACCEL_RTREE_PACKED_H
#define TT_ACCEL_RTREE_PACKED_H

#include <stddef.h>
#include <stdint.h>

#include "geometry/aabb.h"
#include "geometry/hd.h"
#include "geometry/ray.h"
#include "treetrace/treetrace.h" /* tt_hit */

/* For a traversal body that must be inlined into each caller, so that its
 * specialisation for a constant M folds. */
#ifdef __CUDACC__
#define TT_RT_INLINE static __forceinline__ __host__ __device__
#else
#define TT_RT_INLINE static inline __attribute__((always_inline))
#endif

/* Entries per node: the options allow 4 <= M <= 16. */
#define TT_RT_MAX_M 16
/* At most 16 levels (L <= 15): with M >= 4 the slot count M^L already
 * reaches 2^30 at L = 15, far beyond any memory budget. */
#define TT_RT_MAX_LEVELS 16
/* Entries of the traversal stacks: (L + 1) * M for every tree the packer
 * accepts (it checks). */
#define TT_RT_STACK_SIZE 160

typedef struct tt_rtree_packed {
    uint32_t M;                          /* entries per node                  */
    uint32_t L;                          /* root level (leaves: level 0)      */
    uint32_t m_shift;                    /* log2 M when M is a power of 2, else 0 */
    uint32_t slots;                      /* N = (M^(L+1) - 1) / (M - 1)       */
    uint32_t leaf_slots;                 /* M^L                               */
    uint32_t triangles;
    uint32_t delta[TT_RT_MAX_LEVELS + 1]; /* Delta_L(l), l = 0 .. L          */
    /* group of the first slot of level l: (Delta_L(l) - 1) / M + 1 for
     * l < L, 0 for the root; a slot's group follows from its level-relative
     * index k = n - Delta_L(l) as gfirst[l] + k / M, without dividing n */
    uint32_t gfirst[TT_RT_MAX_LEVELS + 1];
    const float *box;          /* 6 * M floats a group, groups = (N + M - 1) / M */
    const uint8_t *count;      /* Delta_L(0) entries                            */
    const uint32_t *leaf_start; /* leaf_slots + 1 entries                       */
    const float *tri;          /* 9 floats a triangle, leaf order               */
    const uint32_t *prim;      /* load-order id of each triangle, leaf order    */
} tt_rtree_packed;

/* Division and remainder by M: shifts for the usual powers of two. */
TT_HD uint32_t tt_rt_div(const tt_rtree_packed *t, uint32_t x)
{
    return t->m_shift ? x >> t->m_shift : x / t->M;
}
TT_HD uint32_t tt_rt_mod(const tt_rtree_packed *t, uint32_t x)
{
    return t->m_shift ? x & (t->M - 1) : x % t->M;
}

/* Division and remainder by M where the caller may know M at compile time
 * (the traversals are specialised for the default M = 4): shifts then. */
TT_HD uint32_t tt_rt_div_m(const tt_rtree_packed *t, uint32_t M, uint32_t x)
{
    return M == 4 ? x >> 2 : tt_rt_div(t, x);
}
TT_HD uint32_t tt_rt_mod_m(const tt_rtree_packed *t, uint32_t M, uint32_t x)
{
    return M == 4 ? x & 3 : tt_rt_mod(t, x);
}

/* The paper's index arithmetic (slot n on level l); the _m forms take M
 * (== t->M) from the caller, which may know it at compile time. */
TT_HD uint32_t tt_rt_first_child_m(const tt_rtree_packed *t, uint32_t M, uint32_t n, uint32_t l)
{
    return (n - t->delta[l]) * M + t->delta[l - 1];
}
TT_HD uint32_t tt_rt_first_child(const tt_rtree_packed *t, uint32_t n, uint32_t l)
{
    return tt_rt_first_child_m(t, t->M, n, l);
}
TT_HD uint32_t tt_rt_parent(const tt_rtree_packed *t, uint32_t n, uint32_t l)
{
    return tt_rt_div(t, n - t->delta[l]) + t->delta[l + 1];
}
TT_HD uint32_t tt_rt_chi(const tt_rtree_packed *t, uint32_t n, uint32_t l)
{
    return tt_rt_mod(t, n - t->delta[l]);
}

/* The first float of slot n's group and n's position in it. */
TT_HD const float *tt_rt_group(const tt_rtree_packed *t, uint32_t n, uint32_t *pos)
{
    uint32_t i = n + t->M - 1;
    *pos = tt_rt_mod(t, i);
    return t->box + (size_t)tt_rt_div(t, i) * 6 * t->M;
}

/* The group holding the M child slots of slot n on level l > 0 (they fill
 * it exactly: n_e(n) is the first slot of group gfirst[l-1] + n - Delta_L(l)). */
TT_HD const float *tt_rt_child_group_m(const tt_rtree_packed *t, uint32_t M, uint32_t n,
                                       uint32_t l)
{
    return t->box + (size_t)(t->gfirst[l - 1] + (n - t->delta[l])) * 6 * M;
}
TT_HD const float *tt_rt_child_group(const tt_rtree_packed *t, uint32_t n, uint32_t l)
{
    return tt_rt_child_group_m(t, t->M, n, l);
}

/* Where each axis's near and far planes are for one ray: the offsets (in
 * floats from a group's start) of the bound arrays k (lo) and k + 3 (hi),
 * chosen by the direction's sign — computed once per ray, so that a box
 * test is straight-line code. */
typedef struct tt_rt_planes {
    uint32_t n[3], f[3];
    /* The box test's absolute margin, 2^-21 max_k |org_k rcp_k| over the
     * axes where that is finite (the FMA kernels' pad, rtc_box_x86.h): the
     * watertight test's t errs by about the vertices' distance from the
     * origin times 2^-24 (its translated coordinates), not by a fraction
     * of t, so a short ray can find its hit on a triangle lying in a flat
     * box's face a little before the box's entry; the relative 2^-16
     * alone dropped such boxes (Sibenik, shadow rays ending on their
     * occluder: bruteforce hit, the scalar and SSE R-tree missed). */
    float pad;
} tt_rt_planes;

TT_HD void tt_rt_planes_init(tt_rt_planes *p, const tt_wray *r, uint32_t M)
{
    for (uint32_t k = 0; k < 3; k++) {
        const int neg = r->rcp[k] < 0.0f;
        p->n[k] = (neg ? k + 3 : k) * M;
        p->f[k] = (neg ? k : k + 3) * M;
    }
    float pad = 0.0f;
    for (uint32_t k = 0; k < 3; k++) {
        const float x = fabsf(r->org[k] * r->rcp[k]); /* NaN or inf: no cull on k */
        if (x < TT_INF && x > pad) pad = x;
    }
    p->pad = pad * (1.0f / 2097152.0f);
}

/* Slab test of the box whose lo x bound is at b (a group's start plus the
 * slot's position): exactly tt_ray_box (geometry/aabb.h) — the exact scheme
 * with the true inverse direction, sign-selected near/far planes and
 * NaN-ignoring accumulation, so a ray lying in a face plane is kept — on the
 * group's SoA bounds. */
TT_HD float tt_rt_box_test_at(const tt_wray *r, const tt_rt_planes *p, const float *b, float tmax)
{
    const float tn0 = (TT_LDG(b + p->n[0]) - r->org[0]) * r->rcp[0];
    const float tn1 = (TT_LDG(b + p->n[1]) - r->org[1]) * r->rcp[1];
    const float tn2 = (TT_LDG(b + p->n[2]) - r->org[2]) * r->rcp[2];
    const float tf0 = (TT_LDG(b + p->f[0]) - r->org[0]) * r->rcp[0];
    const float tf1 = (TT_LDG(b + p->f[1]) - r->org[1]) * r->rcp[1];
    const float tf2 = (TT_LDG(b + p->f[2]) - r->org[2]) * r->rcp[2];
    const float tnear = tt_slab_near(tn2, tt_slab_near(tn1, tt_slab_near(tn0, r->tmin)));
    float tfar = tt_slab_far(tf2, tt_slab_far(tf1, tt_slab_far(tf0, TT_INF)));
    tfar += fabsf(tfar) * (1.0f / 4194304.0f); /* widened away from 0, as in tt_ray_box */
    tfar += p->pad;
    /* The entry distance is compared with hit distances from the triangle
     * test, a different computation: a triangle inside the box can come out
     * a few ulps nearer than the box's rounded entry (e.g. a flat box and a
     * ray whose tmax ends just behind the plane). The entry is lowered by a
     * relative 2^-16 and by the pad (tt_rt_planes.pad: that error grows
     * with the vertices' distance from the origin, not with t). A parallel
     * ray outside a slab has tnear = +inf and entry NaN (inf - inf): a miss. */
    const float entry = tnear - fabsf(tnear) * (1.0f / 65536.0f) - p->pad;
    return (tnear <= tfar && entry < tmax) ? entry : TT_INF;
}

/* The same for the box at position pos of group g. */
TT_HD float tt_rt_box_test(const tt_wray *r, const float *g, uint32_t M, uint32_t pos,
                           float tmax)
{
    tt_rt_planes p;
    tt_rt_planes_init(&p, r, M);
    return tt_rt_box_test_at(r, &p, g + pos, tmax);
}

/* The slab test of four consecutive slots of a group (stride M between the
 * six bound arrays). Identical per slot to tt_rt_box_test: on x86 CPUs as
 * SSE instructions, elsewhere (and on the GPU) as a plain loop. The ray is
 * broadcast to SIMD lanes once per ray (tt_rt_lanes_init); its near and far
 * plane offsets (tt_rt_planes) come along. maxps(a, b) and minps(a, b) return b
 * when either operand is NaN, so with the candidate first and the
 * accumulator second they are exactly tt_slab_near and tt_slab_far (no FMA
 * contraction under ISO C). Defining TT_NO_SIMD forces the plain loop on
 * the CPU too: the single-source test (tests/cuda/test_single_source.c)
 * compiles the traversals that way, so the CPU runs exactly the code the
 * GPU runs. */
#if defined(__SSE2__) && !defined(__CUDACC__) && !defined(TT_NO_SIMD)
#include <emmintrin.h>
typedef struct tt_rt_lanes {
    __m128 ox, oy, oz, ix, iy, iz, tmin;
} tt_rt_lanes;

TT_HD void tt_rt_lanes_init(tt_rt_lanes *s, const tt_wray *r)
{
    s->ox = _mm_set1_ps(r->org[0]);
    s->oy = _mm_set1_ps(r->org[1]);
    s->oz = _mm_set1_ps(r->org[2]);
    s->ix = _mm_set1_ps(r->rcp[0]);
    s->iy = _mm_set1_ps(r->rcp[1]);
    s->iz = _mm_set1_ps(r->rcp[2]);
    s->tmin = _mm_set1_ps(r->tmin);
}

TT_HD void tt_rt_box_test4(const tt_rt_lanes *s, const tt_rt_planes *p,
                           const float *TT_RESTRICT g, float tmax, float *TT_RESTRICT out)
{
    const __m128 tnx = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->n[0]), s->ox), s->ix);
    const __m128 tny = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->n[1]), s->oy), s->iy);
    const __m128 tnz = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->n[2]), s->oz), s->iz);
    const __m128 tfx = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->f[0]), s->ox), s->ix);
    const __m128 tfy = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->f[1]), s->oy), s->iy);
    const __m128 tfz = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(g + p->f[2]), s->oz), s->iz);
    const __m128 tn = _mm_max_ps(tnz, _mm_max_ps(tny, _mm_max_ps(tnx, s->tmin)));
    const __m128 tf0 = _mm_min_ps(tfz, _mm_min_ps(tfy, _mm_min_ps(tfx, _mm_set1_ps(TT_INF))));
    const __m128 absmask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128 pad = _mm_set1_ps(p->pad);
    const __m128 tf = _mm_add_ps(
        _mm_add_ps(tf0, _mm_mul_ps(_mm_and_ps(tf0, absmask), _mm_set1_ps(1.0f / 4194304.0f))), pad);
    const __m128 abs_tn = _mm_and_ps(tn, absmask);
    const __m128 entry =
        _mm_sub_ps(_mm_sub_ps(tn, _mm_mul_ps(abs_tn, _mm_set1_ps(1.0f / 65536.0f))), pad);
    const __m128 hit = _mm_and_ps(_mm_cmple_ps(tn, tf), _mm_cmplt_ps(entry, _mm_set1_ps(tmax)));
    _mm_storeu_ps(out, _mm_or_ps(_mm_and_ps(hit, entry), _mm_andnot_ps(hit, _mm_set1_ps(TT_INF))));
}
#else
typedef struct tt_rt_lanes {
    const tt_wray *r;
} tt_rt_lanes;

TT_HD void tt_rt_lanes_init(tt_rt_lanes *s, const tt_wray *r) { s->r = r; }

TT_HD void tt_rt_box_test4(const tt_rt_lanes *s, const tt_rt_planes *p,
                           const float *TT_RESTRICT g, float tmax, float *TT_RESTRICT out)
{
    for (uint32_t i = 0; i < 4; i++) out[i] = tt_rt_box_test_at(s->r, p, g + i, tmax);
}
#endif

/* The slab test of all M slots of one group at once (a node's children):
 * out[i] is slot i's entry distance or +inf. Four at a time when M is a
 * multiple of 4, one at a time otherwise. */
TT_HD void tt_rt_group_test(const tt_rt_lanes *s, const tt_wray *r, const tt_rt_planes *p,
                            const float *TT_RESTRICT g, uint32_t M, float tmax,
                            float *TT_RESTRICT out)
{
    if ((M & 3) == 0) {
        for (uint32_t i = 0; i < M; i += 4) tt_rt_box_test4(s, p, g + i, tmax, out + i);
    } else {
        for (uint32_t i = 0; i < M; i++) out[i] = tt_rt_box_test_at(r, p, g + i, tmax);
    }
}

/* Lowest set bit of a nonzero mask (a GPU intrinsic in nvcc's device pass,
 * a compiler builtin — one instruction — on the CPU). */
TT_HD uint32_t tt_rt_ctz(uint32_t x)
{
#ifdef __CUDA_ARCH__
    return (uint32_t)(__ffs((int)x) - 1);
#else
    return (uint32_t)__builtin_ctz(x);
#endif
}


/* The closing step every traversal shares: the closest hit found (leaf
 * triangle slot `found`, or TT_INVALID_ID) written to *hit in the scene's
 * triangle ids; nothing is written for any-hit queries. Returns whether a
 * triangle was hit. */
TT_HD int tt_rt_finish(const tt_rtree_packed *TT_RESTRICT t, int any, uint32_t found, float best,
                       float bu, float bv, tt_hit *hit)
{
    if (!any) {
        hit->t = found == TT_INVALID_ID ? TT_INF : best;
        hit->u = bu;
        hit->v = bv;
        hit->prim = found == TT_INVALID_ID ? TT_INVALID_ID : TT_LDG(t->prim + found);
    }
    return found != TT_INVALID_ID;
}

#endif
