/* The kd-tree's leaf test eight triangles at a time (AVX2 intrinsics, also
 * compiled into the AVX-512 unit), for the fast traversal variants of
 * kd_trace_avx2.c / kd_trace_avx512.c. Include only from those units.
 *
 * Why not tri_block.h's blocks: a leaf's triangles are found through
 * refs[] in the scene's flat array, and packing them per leaf (36 bytes a
 * reference instead of 4) more than doubled the tree's memory (bunny
 * 10.6 -> 24.4 MB) for no measured gain. So the eight lanes are read from
 * tri[9 id + c] straight away: once with hardware gathers, now with plain
 * loads and a transpose (kd_load8), which are faster on AMD Zen 5.
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

/* Triangle j's nine floats, as component vectors: lane j of c[k] holds
 * tri[9 ids[j] + k]. Eight unaligned loads of a triangle's first eight
 * floats and an 8x8 transpose (24 shuffles), the ninth float loaded apart:
 * on the AMD Zen 5 the project measures on, this is about 25% faster per
 * leaf than nine hardware gathers (cornell:main, 1 thread, CPU time), and
 * the values are the same floats, so the test stays bit-identical. */
static inline void kd_load8(const float *tri, const uint32_t ids[8], __m256 c[9])
{
    __m256 r[8];
    for (int j = 0; j < 8; j++) r[j] = _mm256_loadu_ps(tri + 9 * (size_t)ids[j]);
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
    const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
    const __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xEE);
    const __m256 s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xEE);
    const __m256 s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xEE);
    const __m256 s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xEE);
    c[0] = _mm256_permute2f128_ps(s0, s4, 0x20);
    c[1] = _mm256_permute2f128_ps(s1, s5, 0x20);
    c[2] = _mm256_permute2f128_ps(s2, s6, 0x20);
    c[3] = _mm256_permute2f128_ps(s3, s7, 0x20);
    c[4] = _mm256_permute2f128_ps(s0, s4, 0x31);
    c[5] = _mm256_permute2f128_ps(s1, s5, 0x31);
    c[6] = _mm256_permute2f128_ps(s2, s6, 0x31);
    c[7] = _mm256_permute2f128_ps(s3, s7, 0x31);
    c[8] = _mm256_setr_ps(tri[9 * (size_t)ids[0] + 8], tri[9 * (size_t)ids[1] + 8],
                          tri[9 * (size_t)ids[2] + 8], tri[9 * (size_t)ids[3] + 8],
                          tri[9 * (size_t)ids[4] + 8], tri[9 * (size_t)ids[5] + 8],
                          tri[9 * (size_t)ids[6] + 8], tri[9 * (size_t)ids[7] + 8]);
}

/* Lanes of one group of up to 8 references: returns the valid-hit mask
 * and leaves t, u, v per lane in the arrays. Lanes past n repeat the first
 * triangle and are masked out. */
static inline unsigned kd_gather8(const tt_kd_view *T, const uint32_t *refs, uint32_t n,
                                  const tt_wray *r, float tmax, float *t_out, float *u_out,
                                  float *v_out)
{
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i live = _mm256_cmpgt_epi32(_mm256_set1_epi32((int)n), lane);
    const __m256 livef = _mm256_castsi256_ps(live);
    const float *tri = T->tri;
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    uint32_t ids[8];
    for (uint32_t j = 0; j < 8; j++) ids[j] = refs[j < n ? j : 0];
    __m256 comp[9];
    kd_load8(tri, ids, comp);
    const __m256 a0 = comp[0], a1 = comp[1], a2 = comp[2];
    const __m256 b0 = comp[3], b1 = comp[4], b2 = comp[5];
    const __m256 c0 = comp[6], c1 = comp[7], c2 = comp[8];
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
