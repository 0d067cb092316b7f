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

#include "geometry/tri_block.h"

/* Lanes of one block: returns the valid-hit mask and leaves t, u, v per
 * lane in the arrays. */
static inline unsigned kd_block8(const tt_kd_view *T, const tt_tri_block *b, const tt_wray *r,
                                 float tmax, float *t_out, float *u_out, float *v_out)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const __m256 ox = _mm256_set1_ps(r->org[kx]), oy = _mm256_set1_ps(r->org[ky]),
                 oz = _mm256_set1_ps(r->org[kz]);
    const __m256 ax = _mm256_sub_ps(_mm256_load_ps(b->v[kx]), ox),
                 ay = _mm256_sub_ps(_mm256_load_ps(b->v[ky]), oy),
                 az = _mm256_sub_ps(_mm256_load_ps(b->v[kz]), oz);
    const __m256 bx = _mm256_sub_ps(_mm256_load_ps(b->v[3 + kx]), ox),
                 by = _mm256_sub_ps(_mm256_load_ps(b->v[3 + ky]), oy),
                 bz = _mm256_sub_ps(_mm256_load_ps(b->v[3 + kz]), oz);
    const __m256 cx = _mm256_sub_ps(_mm256_load_ps(b->v[6 + kx]), ox),
                 cy = _mm256_sub_ps(_mm256_load_ps(b->v[6 + ky]), oy),
                 cz = _mm256_sub_ps(_mm256_load_ps(b->v[6 + kz]), oz);
    const __m256 sx = _mm256_set1_ps(r->sx), sy = _mm256_set1_ps(r->sy),
                 sz = _mm256_set1_ps(r->sz);
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
    const __m256 det = _mm256_add_ps(_mm256_add_ps(U, V), W);
    /* Most blocks a ray meets hold no lane inside all three edges (every
     * block of an unoccluded shadow ray): stop before the depth and the
     * division. A lane can only hit where its edge functions agree in sign
     * and det is a nonzero number (NaN lanes: padding, zero area), or where
     * one is zero (the scalar re-test below), so skipping the rest changes
     * no answer. */
    const unsigned redo = (unsigned)_mm256_movemask_ps(anyzero);
    const __m256 maybe =
        _mm256_andnot_ps(_mm256_and_ps(anyneg, anypos), _mm256_cmp_ps(det, zero, _CMP_NEQ_OQ));
    if (!(_mm256_movemask_ps(maybe) | redo)) return 0;
    const __m256 T3 = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(U, _mm256_mul_ps(sz, az)), _mm256_mul_ps(V, _mm256_mul_ps(sz, bz))),
        _mm256_mul_ps(W, _mm256_mul_ps(sz, cz)));
    const __m256 inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
    const __m256 t = _mm256_mul_ps(T3, inv_det);
    __m256 ok = _mm256_andnot_ps(_mm256_and_ps(anyneg, anypos), _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
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

static inline int kd_leaf_block(const tt_kd_view *T, tt_kd_node leaf, const tt_wray *r, int any,
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
