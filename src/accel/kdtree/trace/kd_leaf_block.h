/* The kd-tree's leaf test eight triangles at a time (AVX2 intrinsics, also
 * compiled into the AVX-512 unit), for the fast traversal variants of
 * kd_trace_avx2.c / kd_trace_avx512.c. Include only from those units.
 *
 * A leaf's triangles are read from its blocks (kd_blocks.h: the engine's
 * copy, in reference order, eight lanes a block, structure of arrays), one
 * aligned load a coordinate row. Before, they were read through refs[]
 * from the scene's flat array (eight loads and an 8x8 transpose a group,
 * once nine gathers): every triangle a dependent load and a cache line of
 * its own; see the notes of the commit that made the blocks for the
 * measured gain and the memory they cost.
 *
 * Bit-identical to tt_intersect_triangle lane by lane: the same operations
 * in the same order (no FMA: the unit is compiled with -ffp-contract=off),
 * IEEE division for 1 / det. A lane with a zero edge function, where the
 * scalar test recomputes in double precision, is re-tested by
 * tt_intersect_triangle itself on the scene's triangle. Zero-area
 * triangles and unused lanes are NaN in the blocks, so they fail the t
 * test (tt_intersect_triangle refuses the former after it). The closest
 * hit is then chosen as the scalar loop over refs[] would: in reference
 * order (lane order), a triangle replacing the best so far only when
 * strictly nearer, so ties between and within leaves resolve as before.
 * Every lane is tested on the leaf's entry [tmin, best), a superset of
 * what the loop would test each triangle on, and the choice re-applies
 * the running bound, so the result is the same. */
#include <immintrin.h>

#include "accel/kdtree/kd_lines.h"
#include "geometry/tri_block.h"

/* The edge functions of a block's eight triangles for one ray, the part
 * kd_block8 and kd_block8_any share: the vertices relative to the origin in
 * the shear's axis order, sheared (U, V, W as tt_intersect_triangle forms
 * them, in the same order), det = U + V + W, the lanes with a zero edge
 * function (redo: the scalar test re-tests those) and the lanes whose edge
 * functions have both signs (out: no hit). az, bz, cz stay for the depth. */
typedef struct kd_edges8 {
    __m256 U, V, W, det, az, bz, cz, out;
    unsigned redo;
} kd_edges8;

TT_TRI_KERNEL void kd_block8_edges(const tt_tri_block *b, int kx, int ky, int kz, __m256 ox,
                                   __m256 oy, __m256 oz, __m256 sx, __m256 sy, kd_edges8 *e)
{
    const __m256 ax = _mm256_sub_ps(_mm256_load_ps(b->v[kx]), ox),
                 ay = _mm256_sub_ps(_mm256_load_ps(b->v[ky]), oy),
                 az = _mm256_sub_ps(_mm256_load_ps(b->v[kz]), oz);
    const __m256 bx = _mm256_sub_ps(_mm256_load_ps(b->v[3 + kx]), ox),
                 by = _mm256_sub_ps(_mm256_load_ps(b->v[3 + ky]), oy),
                 bz = _mm256_sub_ps(_mm256_load_ps(b->v[3 + kz]), oz);
    const __m256 cx = _mm256_sub_ps(_mm256_load_ps(b->v[6 + kx]), ox),
                 cy = _mm256_sub_ps(_mm256_load_ps(b->v[6 + ky]), oy),
                 cz = _mm256_sub_ps(_mm256_load_ps(b->v[6 + kz]), oz);
    const __m256 Ax = _mm256_sub_ps(ax, _mm256_mul_ps(sx, az)),
                 Ay = _mm256_sub_ps(ay, _mm256_mul_ps(sy, az));
    const __m256 Bx = _mm256_sub_ps(bx, _mm256_mul_ps(sx, bz)),
                 By = _mm256_sub_ps(by, _mm256_mul_ps(sy, bz));
    const __m256 Cx = _mm256_sub_ps(cx, _mm256_mul_ps(sx, cz)),
                 Cy = _mm256_sub_ps(cy, _mm256_mul_ps(sy, cz));
    const __m256 U = _mm256_sub_ps(_mm256_mul_ps(Cx, By), _mm256_mul_ps(Cy, Bx));
    const __m256 V = _mm256_sub_ps(_mm256_mul_ps(Ax, Cy), _mm256_mul_ps(Ay, Cx));
    const __m256 W = _mm256_sub_ps(_mm256_mul_ps(Bx, Ay), _mm256_mul_ps(By, Ax));
    const __m256 zero = _mm256_setzero_ps();
    const __m256 anyzero =
        _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_EQ_OQ), _mm256_cmp_ps(V, zero, _CMP_EQ_OQ)),
                     _mm256_cmp_ps(W, zero, _CMP_EQ_OQ));
    const __m256 anyneg =
        _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_LT_OQ), _mm256_cmp_ps(V, zero, _CMP_LT_OQ)),
                     _mm256_cmp_ps(W, zero, _CMP_LT_OQ));
    const __m256 anypos =
        _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(U, zero, _CMP_GT_OQ), _mm256_cmp_ps(V, zero, _CMP_GT_OQ)),
                     _mm256_cmp_ps(W, zero, _CMP_GT_OQ));
    e->U = U;
    e->V = V;
    e->W = W;
    e->det = _mm256_add_ps(_mm256_add_ps(U, V), W);
    e->az = az;
    e->bz = bz;
    e->cz = cz;
    e->out = _mm256_and_ps(anyneg, anypos);
    e->redo = (unsigned)_mm256_movemask_ps(anyzero);
}

/* Lanes of one block: returns the valid-hit mask and leaves t, u, v per
 * lane in the arrays. */
TT_TRI_KERNEL unsigned kd_block8(const tt_kd_view *T, const tt_tri_block *b, const tt_wray *r,
                                 float tmax, float *t_out, float *u_out, float *v_out)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const __m256 sz = _mm256_set1_ps(r->sz);
    kd_edges8 e;
    kd_block8_edges(b, kx, ky, kz, _mm256_set1_ps(r->org[kx]), _mm256_set1_ps(r->org[ky]),
                    _mm256_set1_ps(r->org[kz]), _mm256_set1_ps(r->sx), _mm256_set1_ps(r->sy), &e);
    const __m256 U = e.U, V = e.V, W = e.W, det = e.det, az = e.az, bz = e.bz, cz = e.cz;
    const __m256 zero = _mm256_setzero_ps();
    /* Most blocks a ray meets hold no lane inside all three edges (every
     * block of an unoccluded shadow ray): stop before the depth and the
     * division. A lane can only hit where its edge functions agree in sign
     * and det is a nonzero number (NaN lanes: padding, zero area), or where
     * one is zero (the scalar re-test below), so skipping the rest changes
     * no answer. */
    const unsigned redo = e.redo;
    const __m256 maybe = _mm256_andnot_ps(e.out, _mm256_cmp_ps(det, zero, _CMP_NEQ_OQ));
    if (!(_mm256_movemask_ps(maybe) | redo)) return 0;
    const __m256 T3 = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(U, _mm256_mul_ps(sz, az)), _mm256_mul_ps(V, _mm256_mul_ps(sz, bz))),
        _mm256_mul_ps(W, _mm256_mul_ps(sz, cz)));
    const __m256 inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
    const __m256 t = _mm256_mul_ps(T3, inv_det);
    __m256 ok = _mm256_andnot_ps(e.out, _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(t, _mm256_set1_ps(r->tmin), _CMP_GE_OQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(t, _mm256_set1_ps(tmax), _CMP_LT_OQ));
    /* NaN lanes compare unequal to zero: never re-tested. */
    unsigned hits = (unsigned)_mm256_movemask_ps(ok) & ~redo;
    if (hits) {
        _mm256_storeu_ps(t_out, t);
        _mm256_storeu_ps(u_out, _mm256_mul_ps(V, inv_det));
        _mm256_storeu_ps(v_out, _mm256_mul_ps(W, inv_det));
    }
    /* Lanes the scalar test recomputes in double precision: the scalar test. */
    for (unsigned m = redo; m; m &= m - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(m);
        const float *p = T->tri + 9 * (size_t)b->prim[i];
        if (tt_intersect_triangle(r, p, p + 3, p + 6, tmax, &t_out[i], &u_out[i], &v_out[i]))
            hits |= 1u << i;
    }
    return hits;
}

TT_TRI_KERNEL int kd_leaf_block(const tt_kd_view *T, tt_kd_node leaf, const tt_wray *r, int any,
                                tt_kd_best *best)
{
    const tt_tri_block *b = T->blocks + leaf.u.first;
    const tt_tri_block *end = b + tt_tri_block_count(tt_kd_leaf_count(leaf.bits));
    for (; b != end; b++) {
        float t[8], u[8], v[8];
        for (unsigned hits = kd_block8(T, b, r, best->t, t, u, v); hits; hits &= hits - 1u) {
            const unsigned i = (unsigned)__builtin_ctz(hits);
            if (t[i] < best->t) {
                best->t = t[i];
                best->u = u[i];
                best->v = v[i];
                best->prim = b->prim[i];
                if (any) return 1;
            }
        }
    }
    return 0;
}

/* The ray's broadcasts for the any-hit test below, made once a ray instead
 * of once a block: the origin in the shear's axis order (kx, ky, kz) and
 * the shear constants. */
typedef struct kd_bray {
    __m256 ox, oy, oz, sx, sy, sz, tmin, tmax;
} kd_bray;

TT_TRI_KERNEL void kd_bray_init(kd_bray *q, const tt_wray *r)
{
    q->ox = _mm256_set1_ps(r->org[r->kx]);
    q->oy = _mm256_set1_ps(r->org[r->ky]);
    q->oz = _mm256_set1_ps(r->org[r->kz]);
    q->sx = _mm256_set1_ps(r->sx);
    q->sy = _mm256_set1_ps(r->sy);
    q->sz = _mm256_set1_ps(r->sz);
    q->tmin = _mm256_set1_ps(r->tmin);
    q->tmax = _mm256_set1_ps(r->tmax);
}

/* kd_block8 for occlusion: 1 when some lane holds a hit on [tmin, tmax).
 * The same operations in the same order as kd_block8 (the same lanes pass),
 * less what only the closest hit needs (u, v, the stores). An occlusion
 * ray's bound stays r->tmax until its first hit, which ends the walk, so
 * kd_block8's tmax argument is always r->tmax here. */
TT_TRI_KERNEL int kd_block8_any(const tt_kd_view *T, const tt_tri_block *b, const tt_wray *r,
                                const kd_bray *q)
{
    kd_edges8 e;
    kd_block8_edges(b, r->kx, r->ky, r->kz, q->ox, q->oy, q->oz, q->sx, q->sy, &e);
    const __m256 U = e.U, V = e.V, W = e.W, det = e.det, az = e.az, bz = e.bz, cz = e.cz;
    const unsigned redo = e.redo;
    const __m256 maybe = _mm256_andnot_ps(e.out, _mm256_cmp_ps(det, _mm256_setzero_ps(), _CMP_NEQ_OQ));
    const unsigned cand = (unsigned)_mm256_movemask_ps(maybe) & ~redo;
    if (!(cand | redo)) return 0;
    if (cand) {
        const __m256 T3 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(U, _mm256_mul_ps(q->sz, az)),
                                                      _mm256_mul_ps(V, _mm256_mul_ps(q->sz, bz))),
                                        _mm256_mul_ps(W, _mm256_mul_ps(q->sz, cz)));
        const __m256 inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
        const __m256 t = _mm256_mul_ps(T3, inv_det);
        const __m256 ok = _mm256_and_ps(_mm256_cmp_ps(t, q->tmin, _CMP_GE_OQ),
                                        _mm256_cmp_ps(t, q->tmax, _CMP_LT_OQ));
        if ((unsigned)_mm256_movemask_ps(ok) & cand) return 1;
    }
    for (unsigned m = redo; m; m &= m - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(m);
        const float *p = T->tri + 9 * (size_t)b->prim[i];
        float t, u, v;
        if (tt_intersect_triangle(r, p, p + 3, p + 6, r->tmax, &t, &u, &v)) return 1;
    }
    return 0;
}

/* The any-hit leaf: blocks [first, first + count). */
TT_TRI_KERNEL int kd_leaf_block_any(const tt_kd_view *T, uint32_t first, uint32_t count,
                                    const tt_wray *r, const kd_bray *q)
{
    const tt_tri_block *b = T->blocks + first, *end = b + count;
    for (; b != end; b++)
        if (kd_block8_any(T, b, r, q)) return 1;
    return 0;
}

/* The 4-lane blocks of small leaves (tt_kd_block4, kd_lines.h), for the
 * line walks: kd_block8_edges, kd_block8 and kd_block8_any in 128-bit
 * vectors, the same operations in the same order lane by lane, so the same
 * lanes pass with the same t, u, v. */
typedef struct kd_edges4 {
    __m128 U, V, W, det, az, bz, cz, out;
    unsigned redo;
} kd_edges4;

TT_TRI_KERNEL void kd_block4_edges(const tt_kd_block4 *b, int kx, int ky, int kz, __m128 ox,
                                   __m128 oy, __m128 oz, __m128 sx, __m128 sy, kd_edges4 *e)
{
    const __m128 ax = _mm_sub_ps(_mm_load_ps(b->v[kx]), ox),
                 ay = _mm_sub_ps(_mm_load_ps(b->v[ky]), oy),
                 az = _mm_sub_ps(_mm_load_ps(b->v[kz]), oz);
    const __m128 bx = _mm_sub_ps(_mm_load_ps(b->v[3 + kx]), ox),
                 by = _mm_sub_ps(_mm_load_ps(b->v[3 + ky]), oy),
                 bz = _mm_sub_ps(_mm_load_ps(b->v[3 + kz]), oz);
    const __m128 cx = _mm_sub_ps(_mm_load_ps(b->v[6 + kx]), ox),
                 cy = _mm_sub_ps(_mm_load_ps(b->v[6 + ky]), oy),
                 cz = _mm_sub_ps(_mm_load_ps(b->v[6 + kz]), oz);
    const __m128 Ax = _mm_sub_ps(ax, _mm_mul_ps(sx, az)), Ay = _mm_sub_ps(ay, _mm_mul_ps(sy, az));
    const __m128 Bx = _mm_sub_ps(bx, _mm_mul_ps(sx, bz)), By = _mm_sub_ps(by, _mm_mul_ps(sy, bz));
    const __m128 Cx = _mm_sub_ps(cx, _mm_mul_ps(sx, cz)), Cy = _mm_sub_ps(cy, _mm_mul_ps(sy, cz));
    const __m128 U = _mm_sub_ps(_mm_mul_ps(Cx, By), _mm_mul_ps(Cy, Bx));
    const __m128 V = _mm_sub_ps(_mm_mul_ps(Ax, Cy), _mm_mul_ps(Ay, Cx));
    const __m128 W = _mm_sub_ps(_mm_mul_ps(Bx, Ay), _mm_mul_ps(By, Ax));
    const __m128 zero = _mm_setzero_ps();
    const __m128 anyzero = _mm_or_ps(_mm_or_ps(_mm_cmp_ps(U, zero, _CMP_EQ_OQ), _mm_cmp_ps(V, zero, _CMP_EQ_OQ)),
                                     _mm_cmp_ps(W, zero, _CMP_EQ_OQ));
    const __m128 anyneg = _mm_or_ps(_mm_or_ps(_mm_cmp_ps(U, zero, _CMP_LT_OQ), _mm_cmp_ps(V, zero, _CMP_LT_OQ)),
                                    _mm_cmp_ps(W, zero, _CMP_LT_OQ));
    const __m128 anypos = _mm_or_ps(_mm_or_ps(_mm_cmp_ps(U, zero, _CMP_GT_OQ), _mm_cmp_ps(V, zero, _CMP_GT_OQ)),
                                    _mm_cmp_ps(W, zero, _CMP_GT_OQ));
    e->U = U;
    e->V = V;
    e->W = W;
    e->det = _mm_add_ps(_mm_add_ps(U, V), W);
    e->az = az;
    e->bz = bz;
    e->cz = cz;
    e->out = _mm_and_ps(anyneg, anypos);
    e->redo = (unsigned)_mm_movemask_ps(anyzero);
}

/* kd_block8 over a 4-lane block. */
TT_TRI_KERNEL unsigned kd_block4(const tt_kd_view *T, const tt_kd_block4 *b, const tt_wray *r,
                                 float tmax, float *t_out, float *u_out, float *v_out)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const __m128 sz = _mm_set1_ps(r->sz);
    kd_edges4 e;
    kd_block4_edges(b, kx, ky, kz, _mm_set1_ps(r->org[kx]), _mm_set1_ps(r->org[ky]),
                    _mm_set1_ps(r->org[kz]), _mm_set1_ps(r->sx), _mm_set1_ps(r->sy), &e);
    const __m128 U = e.U, V = e.V, W = e.W, det = e.det, az = e.az, bz = e.bz, cz = e.cz;
    const __m128 zero = _mm_setzero_ps();
    const unsigned redo = e.redo;
    const __m128 maybe = _mm_andnot_ps(e.out, _mm_cmp_ps(det, zero, _CMP_NEQ_OQ));
    if (!(_mm_movemask_ps(maybe) | redo)) return 0;
    const __m128 T3 = _mm_add_ps(
        _mm_add_ps(_mm_mul_ps(U, _mm_mul_ps(sz, az)), _mm_mul_ps(V, _mm_mul_ps(sz, bz))),
        _mm_mul_ps(W, _mm_mul_ps(sz, cz)));
    const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
    const __m128 t = _mm_mul_ps(T3, inv_det);
    __m128 ok = _mm_andnot_ps(e.out, _mm_cmp_ps(det, zero, _CMP_NEQ_UQ));
    ok = _mm_and_ps(ok, _mm_cmp_ps(t, _mm_set1_ps(r->tmin), _CMP_GE_OQ));
    ok = _mm_and_ps(ok, _mm_cmp_ps(t, _mm_set1_ps(tmax), _CMP_LT_OQ));
    unsigned hits = (unsigned)_mm_movemask_ps(ok) & ~redo;
    if (hits) {
        _mm_storeu_ps(t_out, t);
        _mm_storeu_ps(u_out, _mm_mul_ps(V, inv_det));
        _mm_storeu_ps(v_out, _mm_mul_ps(W, inv_det));
    }
    for (unsigned m = redo; m; m &= m - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(m);
        const float *p = T->tri + 9 * (size_t)b->prim[i];
        if (tt_intersect_triangle(r, p, p + 3, p + 6, tmax, &t_out[i], &u_out[i], &v_out[i]))
            hits |= 1u << i;
    }
    return hits;
}

/* kd_leaf_block over a small leaf's 4-lane block. */
TT_TRI_KERNEL int kd_leaf_block4(const tt_kd_view *T, const tt_kd_block4 *b, const tt_wray *r,
                                 int any, tt_kd_best *best)
{
    float t[4], u[4], v[4];
    for (unsigned hits = kd_block4(T, b, r, best->t, t, u, v); hits; hits &= hits - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(hits);
        if (t[i] < best->t) {
            best->t = t[i];
            best->u = u[i];
            best->v = v[i];
            best->prim = b->prim[i];
            if (any) return 1;
        }
    }
    return 0;
}

/* kd_block8_any over a 4-lane block. */
TT_TRI_KERNEL int kd_block4_any(const tt_kd_view *T, const tt_kd_block4 *b, const tt_wray *r,
                                const kd_bray *q)
{
    kd_edges4 e;
    kd_block4_edges(b, r->kx, r->ky, r->kz, _mm256_castps256_ps128(q->ox),
                    _mm256_castps256_ps128(q->oy), _mm256_castps256_ps128(q->oz),
                    _mm256_castps256_ps128(q->sx), _mm256_castps256_ps128(q->sy), &e);
    const __m128 U = e.U, V = e.V, W = e.W, det = e.det, az = e.az, bz = e.bz, cz = e.cz;
    const unsigned redo = e.redo;
    const __m128 maybe = _mm_andnot_ps(e.out, _mm_cmp_ps(det, _mm_setzero_ps(), _CMP_NEQ_OQ));
    const unsigned cand = (unsigned)_mm_movemask_ps(maybe) & ~redo;
    if (!(cand | redo)) return 0;
    if (cand) {
        const __m128 sz = _mm256_castps256_ps128(q->sz);
        const __m128 T3 = _mm_add_ps(
            _mm_add_ps(_mm_mul_ps(U, _mm_mul_ps(sz, az)), _mm_mul_ps(V, _mm_mul_ps(sz, bz))),
            _mm_mul_ps(W, _mm_mul_ps(sz, cz)));
        const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
        const __m128 t = _mm_mul_ps(T3, inv_det);
        const __m128 ok = _mm_and_ps(_mm_cmp_ps(t, _mm256_castps256_ps128(q->tmin), _CMP_GE_OQ),
                                     _mm_cmp_ps(t, _mm256_castps256_ps128(q->tmax), _CMP_LT_OQ));
        if ((unsigned)_mm_movemask_ps(ok) & cand) return 1;
    }
    for (unsigned m = redo; m; m &= m - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(m);
        const float *p = T->tri + 9 * (size_t)b->prim[i];
        float t, u, v;
        if (tt_intersect_triangle(r, p, p + 3, p + 6, r->tmax, &t, &u, &v)) return 1;
    }
    return 0;
}
