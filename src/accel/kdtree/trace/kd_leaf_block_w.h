/* One width of the kd leaf test (kd_leaf_block.h includes this twice): the
 * edge functions, the closest-hit test and the any-hit test of a block of
 * KDW lanes, as 8-lane (AVX, tt_tri_block) or 4-lane (SSE, tt_kd_block4)
 * vectors. One text for both widths, so the small leaves' 4-lane copies
 * keep the same operations in the same order as the 8-lane blocks (the
 * same lanes pass with the same t, u, v). The includer defines:
 *   KDW               8 or 4 (names: kd_block8, kd_block4, ...)
 *   KDW_BLOCK         the block type
 *   KDW_V             the vector type
 *   KDW_OP(op)        the intrinsic of that width: _mm256_##op / _mm_##op
 *   KDW_RAY(x)        a kd_bray broadcast (__m256) at this width
 * and this file undefines them. */
#define KDW_CAT3(a, b, c) a##b##c
#define KDW_NAME3(a, w, c) KDW_CAT3(a, w, c)
#define KDW_EDGES KDW_NAME3(kd_edges, KDW, )
#define KDW_EDGES_FN KDW_NAME3(kd_block, KDW, _edges)
#define KDW_TEST_FN KDW_NAME3(kd_block, KDW, )
#define KDW_ANY_FN KDW_NAME3(kd_block, KDW, _any)
#define KDW_SUB KDW_OP(sub_ps)
#define KDW_MUL KDW_OP(mul_ps)
#define KDW_ADD KDW_OP(add_ps)
#define KDW_CMP KDW_OP(cmp_ps)
#define KDW_OR KDW_OP(or_ps)
#define KDW_AND KDW_OP(and_ps)
#define KDW_ANDNOT KDW_OP(andnot_ps)
#define KDW_MASK KDW_OP(movemask_ps)
#define KDW_LOAD KDW_OP(load_ps)
#define KDW_SET1 KDW_OP(set1_ps)
#define KDW_ZERO KDW_OP(setzero_ps)

/* The edge functions of a block's triangles for one ray, the part the
 * closest-hit and any-hit tests share: the vertices relative to the origin
 * in the shear's axis order, sheared (U, V, W as tt_intersect_triangle
 * forms them, in the same order), det = U + V + W, the lanes with a zero
 * edge function (redo: the scalar test re-tests those) and the lanes whose
 * edge functions have both signs (out: no hit). az, bz, cz stay for the
 * depth. */
typedef struct KDW_EDGES {
    KDW_V U, V, W, det, az, bz, cz, out;
    unsigned redo;
} KDW_EDGES;

TT_TRI_KERNEL void KDW_EDGES_FN(const KDW_BLOCK *b, int kx, int ky, int kz, KDW_V ox, KDW_V oy,
                                KDW_V oz, KDW_V sx, KDW_V sy, KDW_EDGES *e)
{
    const KDW_V ax = KDW_SUB(KDW_LOAD(b->v[kx]), ox), ay = KDW_SUB(KDW_LOAD(b->v[ky]), oy),
                az = KDW_SUB(KDW_LOAD(b->v[kz]), oz);
    const KDW_V bx = KDW_SUB(KDW_LOAD(b->v[3 + kx]), ox), by = KDW_SUB(KDW_LOAD(b->v[3 + ky]), oy),
                bz = KDW_SUB(KDW_LOAD(b->v[3 + kz]), oz);
    const KDW_V cx = KDW_SUB(KDW_LOAD(b->v[6 + kx]), ox), cy = KDW_SUB(KDW_LOAD(b->v[6 + ky]), oy),
                cz = KDW_SUB(KDW_LOAD(b->v[6 + kz]), oz);
    const KDW_V Ax = KDW_SUB(ax, KDW_MUL(sx, az)), Ay = KDW_SUB(ay, KDW_MUL(sy, az));
    const KDW_V Bx = KDW_SUB(bx, KDW_MUL(sx, bz)), By = KDW_SUB(by, KDW_MUL(sy, bz));
    const KDW_V Cx = KDW_SUB(cx, KDW_MUL(sx, cz)), Cy = KDW_SUB(cy, KDW_MUL(sy, cz));
    const KDW_V U = KDW_SUB(KDW_MUL(Cx, By), KDW_MUL(Cy, Bx));
    const KDW_V V = KDW_SUB(KDW_MUL(Ax, Cy), KDW_MUL(Ay, Cx));
    const KDW_V W = KDW_SUB(KDW_MUL(Bx, Ay), KDW_MUL(By, Ax));
    const KDW_V zero = KDW_ZERO();
    const KDW_V anyzero = KDW_OR(KDW_OR(KDW_CMP(U, zero, _CMP_EQ_OQ), KDW_CMP(V, zero, _CMP_EQ_OQ)),
                                 KDW_CMP(W, zero, _CMP_EQ_OQ));
    const KDW_V anyneg = KDW_OR(KDW_OR(KDW_CMP(U, zero, _CMP_LT_OQ), KDW_CMP(V, zero, _CMP_LT_OQ)),
                                KDW_CMP(W, zero, _CMP_LT_OQ));
    const KDW_V anypos = KDW_OR(KDW_OR(KDW_CMP(U, zero, _CMP_GT_OQ), KDW_CMP(V, zero, _CMP_GT_OQ)),
                                KDW_CMP(W, zero, _CMP_GT_OQ));
    e->U = U;
    e->V = V;
    e->W = W;
    e->det = KDW_ADD(KDW_ADD(U, V), W);
    e->az = az;
    e->bz = bz;
    e->cz = cz;
    e->out = KDW_AND(anyneg, anypos);
    e->redo = (unsigned)KDW_MASK(anyzero);
}

/* Lanes of one block: returns the valid-hit mask and leaves t, u, v per
 * lane in the arrays. */
TT_TRI_KERNEL unsigned KDW_TEST_FN(const tt_kd_view *T, const KDW_BLOCK *b, const tt_wray *r,
                                   float tmax, float *t_out, float *u_out, float *v_out)
{
    const int kx = r->kx, ky = r->ky, kz = r->kz;
    const KDW_V sz = KDW_SET1(r->sz);
    KDW_EDGES e;
    KDW_EDGES_FN(b, kx, ky, kz, KDW_SET1(r->org[kx]), KDW_SET1(r->org[ky]), KDW_SET1(r->org[kz]),
                 KDW_SET1(r->sx), KDW_SET1(r->sy), &e);
    const KDW_V U = e.U, V = e.V, W = e.W, det = e.det, az = e.az, bz = e.bz, cz = e.cz;
    const KDW_V zero = KDW_ZERO();
    /* Most blocks a ray meets hold no lane inside all three edges (every
     * block of an unoccluded shadow ray): stop before the depth and the
     * division. A lane can only hit where its edge functions agree in sign
     * and det is a nonzero number (NaN lanes: padding, zero area), or where
     * one is zero (the scalar re-test below), so skipping the rest changes
     * no answer. */
    const unsigned redo = e.redo;
    const KDW_V maybe = KDW_ANDNOT(e.out, KDW_CMP(det, zero, _CMP_NEQ_OQ));
    if (!(KDW_MASK(maybe) | redo)) return 0;
    const KDW_V T3 = KDW_ADD(KDW_ADD(KDW_MUL(U, KDW_MUL(sz, az)), KDW_MUL(V, KDW_MUL(sz, bz))),
                             KDW_MUL(W, KDW_MUL(sz, cz)));
    const KDW_V inv_det = KDW_OP(div_ps)(KDW_SET1(1.0f), det);
    const KDW_V t = KDW_MUL(T3, inv_det);
    KDW_V ok = KDW_ANDNOT(e.out, KDW_CMP(det, zero, _CMP_NEQ_UQ));
    ok = KDW_AND(ok, KDW_CMP(t, KDW_SET1(r->tmin), _CMP_GE_OQ));
    ok = KDW_AND(ok, KDW_CMP(t, KDW_SET1(tmax), _CMP_LT_OQ));
    /* NaN lanes compare unequal to zero: never re-tested. */
    unsigned hits = (unsigned)KDW_MASK(ok) & ~redo;
    if (hits) {
        KDW_OP(storeu_ps)(t_out, t);
        KDW_OP(storeu_ps)(u_out, KDW_MUL(V, inv_det));
        KDW_OP(storeu_ps)(v_out, KDW_MUL(W, inv_det));
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

/* The closest-hit test for occlusion: 1 when some lane holds a hit on
 * [tmin, tmax). The same operations in the same order (the same lanes
 * pass), less what only the closest hit needs (u, v, the stores). An
 * occlusion ray's bound stays r->tmax until its first hit, which ends the
 * walk, so the closest-hit test's tmax argument is always r->tmax here. */
TT_TRI_KERNEL int KDW_ANY_FN(const tt_kd_view *T, const KDW_BLOCK *b, const tt_wray *r,
                             const kd_bray *q)
{
    KDW_EDGES e;
    KDW_EDGES_FN(b, r->kx, r->ky, r->kz, KDW_RAY(q->ox), KDW_RAY(q->oy), KDW_RAY(q->oz),
                 KDW_RAY(q->sx), KDW_RAY(q->sy), &e);
    const KDW_V U = e.U, V = e.V, W = e.W, det = e.det, az = e.az, bz = e.bz, cz = e.cz;
    const unsigned redo = e.redo;
    const KDW_V maybe = KDW_ANDNOT(e.out, KDW_CMP(det, KDW_ZERO(), _CMP_NEQ_OQ));
    const unsigned cand = (unsigned)KDW_MASK(maybe) & ~redo;
    if (!(cand | redo)) return 0;
    if (cand) {
        const KDW_V sz = KDW_RAY(q->sz);
        const KDW_V T3 = KDW_ADD(KDW_ADD(KDW_MUL(U, KDW_MUL(sz, az)), KDW_MUL(V, KDW_MUL(sz, bz))),
                                 KDW_MUL(W, KDW_MUL(sz, cz)));
        const KDW_V inv_det = KDW_OP(div_ps)(KDW_SET1(1.0f), det);
        const KDW_V t = KDW_MUL(T3, inv_det);
        const KDW_V ok =
            KDW_AND(KDW_CMP(t, KDW_RAY(q->tmin), _CMP_GE_OQ), KDW_CMP(t, KDW_RAY(q->tmax), _CMP_LT_OQ));
        if ((unsigned)KDW_MASK(ok) & cand) return 1;
    }
    for (unsigned m = redo; m; m &= m - 1u) {
        const unsigned i = (unsigned)__builtin_ctz(m);
        const float *p = T->tri + 9 * (size_t)b->prim[i];
        float t, u, v;
        if (tt_intersect_triangle(r, p, p + 3, p + 6, r->tmax, &t, &u, &v)) return 1;
    }
    return 0;
}

#undef KDW_CAT3
#undef KDW_NAME3
#undef KDW_EDGES
#undef KDW_EDGES_FN
#undef KDW_TEST_FN
#undef KDW_ANY_FN
#undef KDW_SUB
#undef KDW_MUL
#undef KDW_ADD
#undef KDW_CMP
#undef KDW_OR
#undef KDW_AND
#undef KDW_ANDNOT
#undef KDW_MASK
#undef KDW_LOAD
#undef KDW_SET1
#undef KDW_ZERO
#undef KDW
#undef KDW_BLOCK
#undef KDW_V
#undef KDW_OP
#undef KDW_RAY
