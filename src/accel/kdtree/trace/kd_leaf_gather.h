/* The kd-tree's leaf test eight triangles at a time (AVX2 intrinsics, also
 * compiled into the AVX-512 unit), for the fast traversal variants of
 * kd_trace_avx2.c / kd_trace_avx512.c. Include only from those units.
 *
 * Why gathers and not tri_block.h's blocks: a leaf's triangles are found
 * through refs[] in the scene's flat array, and packing them per leaf
 * (36 bytes a reference instead of 4) more than doubled the tree's memory
 * (bunny 10.6 -> 24.4 MB) for no measured gain. So the eight lanes are
 * gathered from tri[9 id + c] straight away.
 *
 * Bit-identical to tt_intersect_triangle lane by lane: the same operations
 * in the same order (no FMA: the unit is compiled with -ffp-contract=off),
 * IEEE division for 1 / det. A lane with a zero edge function, where the
 * scalar test recomputes in double precision, is re-tested by
 * tt_intersect_triangle itself. The closest hit is then chosen as the
 * scalar loop would: in reference order, a triangle replacing the best so
 * far only when strictly nearer. Every lane is tested on the leaf's entry
 * [tmin, best), a superset of what the loop would test each triangle on,
 * and the choice re-applies the running bound, so the result is the same. */
#include <immintrin.h>

/* Leaves with fewer references than this take the scalar loop: with 2 the
 * gathered path was 3-10% slower than scalar on bunny, sibenik and
 * conference (1 thread, CPU time), with 4 level with it (+-3%). */
#ifndef TT_KD_GATHER_MIN
#define TT_KD_GATHER_MIN 4u
#endif

/* Lanes of one group of up to 8 references: returns the valid-hit mask
 * and leaves t, u, v per lane in the arrays. */
static inline unsigned kd_gather8(const tt_kd_view *T, const uint32_t *refs, uint32_t n,
                                  const tt_wray *r, float tmax, float *t_out, float *u_out,
                                  float *v_out)
{
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i live = _mm256_cmpgt_epi32(_mm256_set1_epi32((int)n), lane);
    const __m256i ids = _mm256_maskload_epi32((const int *)refs, live);
    const __m256i base = _mm256_mullo_epi32(ids, _mm256_set1_epi32(9));
    const __m256 livef = _mm256_castsi256_ps(live);
    const __m256 nan = _mm256_set1_ps(__builtin_nanf(""));
    const float *tri = T->tri;
    const int kx = r->kx, ky = r->ky, kz = r->kz;
#define KD_G(c) _mm256_mask_i32gather_ps(nan, tri, _mm256_add_epi32(base, _mm256_set1_epi32(c)), livef, 4)
    const __m256 a0 = KD_G(0), a1 = KD_G(1), a2 = KD_G(2);
    const __m256 b0 = KD_G(3), b1 = KD_G(4), b2 = KD_G(5);
    const __m256 c0 = KD_G(6), c1 = KD_G(7), c2 = KD_G(8);
#undef KD_G
    const __m256 av[3] = {a0, a1, a2}, bv[3] = {b0, b1, b2}, cv[3] = {c0, c1, c2};
    const __m256 ox = _mm256_set1_ps(r->org[kx]), oy = _mm256_set1_ps(r->org[ky]),
                 oz = _mm256_set1_ps(r->org[kz]);
    const __m256 ax = _mm256_sub_ps(av[kx], ox), ay = _mm256_sub_ps(av[ky], oy),
                 az = _mm256_sub_ps(av[kz], oz);
    const __m256 bx = _mm256_sub_ps(bv[kx], ox), by = _mm256_sub_ps(bv[ky], oy),
                 bz = _mm256_sub_ps(bv[kz], oz);
    const __m256 cx = _mm256_sub_ps(cv[kx], ox), cy = _mm256_sub_ps(cv[ky], oy),
                 cz = _mm256_sub_ps(cv[kz], oz);
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
    const __m256 T3 = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(U, _mm256_mul_ps(sz, az)), _mm256_mul_ps(V, _mm256_mul_ps(sz, bz))),
        _mm256_mul_ps(W, _mm256_mul_ps(sz, cz)));
    const __m256 inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
    const __m256 t = _mm256_mul_ps(T3, inv_det);
    __m256 ok = _mm256_andnot_ps(_mm256_and_ps(anyneg, anypos), livef);
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(t, _mm256_set1_ps(r->tmin), _CMP_GE_OQ));
    ok = _mm256_and_ps(ok, _mm256_cmp_ps(t, _mm256_set1_ps(tmax), _CMP_LT_OQ));
    const unsigned redo = (unsigned)_mm256_movemask_ps(_mm256_and_ps(anyzero, livef));
    unsigned hits = (unsigned)_mm256_movemask_ps(ok) & ~redo;
    if (hits) {
        /* tt_intersect_triangle's zero-area refusal, for the candidates. */
        const __m256 e1x = _mm256_sub_ps(b0, a0), e1y = _mm256_sub_ps(b1, a1),
                     e1z = _mm256_sub_ps(b2, a2);
        const __m256 e2x = _mm256_sub_ps(c0, a0), e2y = _mm256_sub_ps(c1, a1),
                     e2z = _mm256_sub_ps(c2, a2);
        const __m256 nx = _mm256_sub_ps(_mm256_mul_ps(e1y, e2z), _mm256_mul_ps(e1z, e2y));
        const __m256 ny = _mm256_sub_ps(_mm256_mul_ps(e1z, e2x), _mm256_mul_ps(e1x, e2z));
        const __m256 nz = _mm256_sub_ps(_mm256_mul_ps(e1x, e2y), _mm256_mul_ps(e1y, e2x));
        const __m256 flat = _mm256_and_ps(
            _mm256_and_ps(_mm256_cmp_ps(nx, zero, _CMP_EQ_OQ), _mm256_cmp_ps(ny, zero, _CMP_EQ_OQ)),
            _mm256_cmp_ps(nz, zero, _CMP_EQ_OQ));
        hits &= ~(unsigned)_mm256_movemask_ps(flat);
        _mm256_storeu_ps(t_out, t);
        _mm256_storeu_ps(u_out, _mm256_mul_ps(V, inv_det));
        _mm256_storeu_ps(v_out, _mm256_mul_ps(W, inv_det));
    }
    /* Lanes the scalar test recomputes in double precision: the scalar test. */
    for (unsigned m = redo; m; m &= m - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(m);
        const float *p = tri + 9 * (size_t)refs[i];
        if (tt_intersect_triangle(r, p, p + 3, p + 6, tmax, &t_out[i], &u_out[i], &v_out[i]))
            hits |= 1u << i;
    }
    return hits;
}

static inline int kd_leaf_gather(const tt_kd_view *T, tt_kd_node leaf, const tt_wray *r, int any,
                                 tt_kd_best *best)
{
    uint32_t count = tt_kd_leaf_count(leaf.bits);
    const uint32_t *refs = T->refs + leaf.u.first;
    if (count < TT_KD_GATHER_MIN) {
        uint32_t tested;
        return tt_kd_leaf_refs(T, refs, count, r, any, best, &tested);
    }
    for (; count; refs += 8) {
        const uint32_t n = count < 8u ? count : 8u;
        float t[8], u[8], v[8];
        unsigned hits = kd_gather8(T, refs, n, r, best->t, t, u, v);
        count -= n;
        for (; hits; hits &= hits - 1u) {
            const unsigned i = (unsigned)__builtin_ctz(hits);
            if (t[i] < best->t) {
                best->t = t[i];
                best->u = u[i];
                best->v = v[i];
                best->prim = refs[i];
                if (any) return 1;
            }
        }
    }
    return 0;
}
