/* Packet traversal of the kd-tree (HTR, kd_trace_htr.h): up to
 * TT_PACKET_MAX rays (a batch's 16 x 16 tile) traced together, SIMD across
 * rays (PK_L = 8 lanes for AVX2, 16 for AVX-512), a template compiled once
 * per ISA unit (kd_packet_avx2.c, _avx512.c) and once per statistics
 * variant (accel/stats_variant.h).
 *
 * Method: coherent ray tracing of kd-trees (Wald, Slusallek, Benthin &
 * Wagner 2001, "Interactive rendering with coherent ray tracing": the rays
 * of a packet share the traversal order, each keeps its own [tnear, tfar],
 * a node is descended near child first, the far child pushed with the
 * per-ray intervals, rays whose interval is empty go inactive); the
 * packet is split into groups of one direction octant first, as Reshetov,
 * Soupikov & Hurley 2005 (MLRTA) require of a packet sharing one traversal
 * order.
 *  - Groups: the rays of one direction octant AND one dominant axis kz.
 *    The octant fixes the near child of every split for the whole group;
 *    the dominant axis (with the octant) fixes the watertight test's axis
 *    permutation (kx, ky, kz: tt_wray_init), so a leaf's triangle test is
 *    straight-line SIMD code for the whole group. A group of fewer than
 *    KP_MIN_RAYS rays, and every ray with a zero direction component (HTR's
 *    general loop, with per-plane rounding bands), go ray by ray through
 *    the single-ray kernel of the unit.
 *  - A group is cut into walks of KP_RAYS rays (KP_K vectors) in the
 *    caller's order (a tile's rows: a walk is one row of 16 for AVX2, two
 *    for AVX-512).
 *    Reordering a group along a Morton curve of its rays' (sx, sy) made
 *    walks of 4 x 4 / 8 x 4 rays, which visited more nodes with fewer
 *    active lanes on bunny, sibenik and conference (the counting variant:
 *    13.1 vs 15.2 lanes a visit, bunny primary), so the order is kept.
 *  - Per lane, the single-ray HTR's arithmetic exactly (kd_trace_htr.h,
 *    tt_kd_htr_moving): the root interval with rounding bands (kd_ray.h),
 *    the per-axis band e_k, ts = (split - o_k) inv_k, lo / hi = ts -+ e_k,
 *    the near child on [ta, min(tb, hi)] unless hi < ta, the far child on
 *    [max(ta, lo), tb] unless lo > tb; a popped entry drops the lanes whose
 *    ta >= their closest hit so far. The packet visits a node when any of
 *    its lanes does, depth first and near first, so every lane meets its
 *    leaves in the single ray's order (the visits of the other lanes are
 *    invisible to it).
 *  - Leaves: each triangle in reference order against the active lanes,
 *    tt_intersect_triangle's float operations in its order (the unit is
 *    compiled without FMA contraction), a lane's best replaced only by a
 *    strictly nearer hit, a lane with a zero edge function recomputed by
 *    tt_intersect_triangle itself. That is the scalar leaf loop of
 *    kd_best.h lane by lane (and the gathered kernel gives the same), so
 *    with the same leaves in the same order every ray gets the single-ray
 *    triangle, t, u and v bit for bit.
 *  - The triangles come from the engine's leaf blocks (kd_blocks.h: the
 *    kernel walks the block view, whose leaves index blocks), the single
 *    ray kernels' copy, so both read the same lines; zero-area triangles
 *    are NaN there and fail every lane's t test.
 *  - Leaves with at most PK_L / 2 lanes left test several triangles at
 *    once (kp_multi): w >= the lanes a power of two, a vector holds PK_L / w
 *    triangles against the w lanes (one lane: PK_L triangles a test, as the
 *    single ray's block test); closest hits are merged lane by lane in
 *    triangle order, so the answers stay the single ray's. The lone and
 *    few-lane leaves of shadow walks (most leaf visits on the bunny) were
 *    a triangle a test over a mostly empty vector: bunny shadows 1.17x,
 *    primary 1.00-1.07x (AVX-512, Zen 5, 1 thread CPU time, interleaved).
 *  - Occlusion: a lane is retired at its first hit; the walk ends when no
 *    lane of it is left.
 *
 * The including unit defines PK_L, the vector macros PK_* (see
 * kd_packet_avx512.c), KD_FN (adds the ISA to a name), KD_SINGLE_INTERSECT
 * / KD_SINGLE_OCCLUDED (the unit's fast single-ray entry points). */
#include "accel/kdtree/trace/kd_ray.h"
#include "accel/kdtree/trace/kd_best.h"
#include "geometry/triangle.h"
#include "geometry/tri_block.h"

#ifndef KD_PACKET_TYPES
#define KD_PACKET_TYPES

#define KP_N TT_PACKET_MAX
#define KP_V (KP_N / PK_L) /* vectors of a whole packet */
/* Vectors per walk: two (16 rays for AVX2, 32 for AVX-512) measured best;
 * AVX-512 with one (16 rays) was 10-25% slower, with four (64) 5-25%
 * slower (bunny, sibenik, conference, 1 thread, CPU time). */
#ifndef KP_K
#define KP_K 2u
#endif
#define KP_RAYS (KP_K * PK_L) /* rays per walk */
_Static_assert(KP_K * PK_L <= 32, "a walk's lanes fit one 32-bit word (kp_walk)");
/* (Finishing a walk's subtree ray by ray once one ray is left in it, with
 * scalar steps, measured level with the vector steps; two or three rays
 * left measured 5-10% slower: not kept.) */
/* Leaves: pack a walk's active lanes into one vector when they fit. */
#ifndef KP_PACK
#define KP_PACK 1
#endif
/* Leaves with lanes in both vectors of a walk (too many to pack): both
 * vectors against each triangle in one loop (kp_tris2). */
#ifndef KP_TRIS2
#define KP_TRIS2 1
#endif
/* Groups with fewer rays go ray by ray. */
#ifndef KP_MIN_RAYS
#define KP_MIN_RAYS 4u
#endif
/* The 24 groups: octant * 3 + kz. */
#define KP_GROUPS 24u
/* a vector's lane bits all clear or all set */
#define KP_LANES ((uint32_t)((1ull << PK_L) - 1u))
#define KP_UNIFORM(bits) ((((bits) + 1u) & KP_LANES) <= 1u)

/* One group's rays, structure of arrays; lanes past n repeat its first ray
 * and are never live. */
typedef struct kp_rays {
    _Alignas(64) float o[3][KP_N];
    _Alignas(64) float inv[3][KP_N];
    _Alignas(64) float e[3][KP_N];
    _Alignas(64) float ta[KP_N];
    _Alignas(64) float tb[KP_N];
    _Alignas(64) float tmin[KP_N];
    _Alignas(64) float t[KP_N];
    _Alignas(64) float u[KP_N];
    _Alignas(64) float v[KP_N];
    _Alignas(64) float sx[KP_N];
    _Alignas(64) float sy[KP_N];
    _Alignas(64) float sz[KP_N];
    _Alignas(64) uint32_t prim[KP_N];
    uint16_t src[KP_N]; /* the lane's row in R                             */
    const tt_packet_rays *R;
    uint32_t live[KP_V]; /* lanes whose ray meets the scene box           */
    uint32_t done[KP_V]; /* occlusion: lanes answered                     */
    uint32_t n, vecs;
    int kx, ky, kz;
    int down[3]; /* the group's direction signs: dir_k < 0               */
} kp_rays;

#define KP_INLINE static inline __attribute__((always_inline))

static inline uint32_t kp_popcount(uint32_t x) { return (uint32_t)__builtin_popcount(x); }

/* tt_intersect_triangle for row j of R (the rare zero-edge lanes: the
 * ray's tt_wray is built only there) */
static inline int kp_tri_row(const tt_packet_rays *R, uint32_t j, const float *p, float tmax,
                             float *t, float *u, float *v)
{
    tt_wray w;
    tt_packet_ray_wray(R, j, &w);
    return tt_intersect_triangle(&w, p, p + 3, p + 6, tmax, t, u, v);
}

#endif

#ifndef KP_MULTI_TABLES
#define KP_MULTI_TABLES
/* kp_multi's slots for w = 2^lg lanes (PK_L <= 16 of them read): slot s
 * holds lane s % w against triangle s / w; rep has bit 0 of each
 * triangle's group of w slots. */
static _Alignas(64) const uint32_t kp_rsel[4][16] = {
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1},
    {0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3},
    {0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 2, 3, 4, 5, 6, 7}};
static _Alignas(64) const uint32_t kp_tsub[4][16] = {
    {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15},
    {0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7},
    {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3},
    {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1}};
static const uint32_t kp_rep[4] = {0xffffu, 0x5555u, 0x1111u, 0x0101u};
_Static_assert(PK_L <= 16, "kp_multi's tables");
#endif

/* A deferred far child with its lanes and their intervals. */
#ifndef KP_ENTRY_DEFINED
#define KP_ENTRY_DEFINED
typedef struct kp_entry {
    pk_v ta[KP_K], tb[KP_K];
    uint32_t m; /* the walk's lanes, vector j's at bit j * PK_L */
    uint32_t node;
} kp_entry;
#endif

/* Triangle i of a leaf's blocks (kd_blocks.h: lane i % 8 of block i / 8,
 * in reference order): coordinate c (a.x .. c.z), its id. */
#define KP_TRI(blk, i, c) ((blk)[(i) >> 3].v[c][(i) & 7u])
#define KP_TRI_ID(blk, i) ((blk)[(i) >> 3].prim[(i) & 7u])
_Static_assert(TT_TRI_BLOCK_W == 8, "KP_TRI: eight triangles a block");

/* tt_intersect_triangle's sheared edge functions U, V, W, in its order of
 * operations, for the vertex rows tv (a.x .. c.z) against origin (ox, oy,
 * oz) in the (kx, ky, kz) order and shear (sx, sy); the depths az, bz, cz
 * stay for t. Shared by kp_tri1 and kp_multi. */
KP_INLINE void TT_VARIANT(KD_FN(kp_edges))(const pk_v *tv, const int kx, const int ky,
                                             const int kz, const pk_v ox, const pk_v oy,
                                             const pk_v oz, const pk_v sx, const pk_v sy,
                                             pk_v *U, pk_v *V, pk_v *W, pk_v *az, pk_v *bz,
                                             pk_v *cz)
{
    const pk_v ax = PK_SUB(tv[kx], ox), ay = PK_SUB(tv[ky], oy);
    const pk_v bx = PK_SUB(tv[3 + kx], ox), by = PK_SUB(tv[3 + ky], oy);
    const pk_v cx = PK_SUB(tv[6 + kx], ox), cy = PK_SUB(tv[6 + ky], oy);
    *az = PK_SUB(tv[kz], oz);
    *bz = PK_SUB(tv[3 + kz], oz);
    *cz = PK_SUB(tv[6 + kz], oz);
    const pk_v Ax = PK_SUB(ax, PK_MUL(sx, *az)), Ay = PK_SUB(ay, PK_MUL(sy, *az));
    const pk_v Bx = PK_SUB(bx, PK_MUL(sx, *bz)), By = PK_SUB(by, PK_MUL(sy, *bz));
    const pk_v Cx = PK_SUB(cx, PK_MUL(sx, *cz)), Cy = PK_SUB(cy, PK_MUL(sy, *cz));
    *U = PK_SUB(PK_MUL(Cx, By), PK_MUL(Cy, Bx));
    *V = PK_SUB(PK_MUL(Ax, Cy), PK_MUL(Ay, Cx));
    *W = PK_SUB(PK_MUL(Bx, Ay), PK_MUL(By, Ax));
}

/* Triangle id's coordinates tv (a.x .. c.z, broadcast) against the lanes
 * *pmm of one vector of rays (kp_tris' arguments); hits (any = 1) leave
 * *pmm, and the lanes that hit or whose best changed are added to *pout. */
KP_INLINE void TT_VARIANT(KD_FN(kp_tri1))(const tt_kd_view *T, const pk_v *tv, uint32_t id,
                                            const int kx, const int ky, const int kz,
                                            const pk_v ox, const pk_v oy, const pk_v oz,
                                            const pk_v sx, const pk_v sy, const pk_v sz,
                                            const pk_v tmin, pk_v *pbt, float *bu, float *bv,
                                            uint32_t *bp, uint32_t *pmm, uint32_t *pout,
                                            const tt_packet_rays *R, const uint16_t *src,
                                            const int any)
{
    const pk_v zero = PK_SET1(0.0f), one = PK_SET1(1.0f);
    const uint32_t mm = *pmm;
    pk_v U, V, W, az, bz, cz;
    TT_VARIANT(KD_FN(kp_edges))(tv, kx, ky, kz, ox, oy, oz, sx, sy, &U, &V, &W, &az, &bz, &cz);
    uint32_t zl =
        PK_BITS(PK_MOR(PK_MOR(PK_CMP_EQ(U, zero), PK_CMP_EQ(V, zero)), PK_CMP_EQ(W, zero))) & mm;
    /* Inside: no edge function < 0 while another is > 0. Away from
     * the zero lanes (zl, handled below) that is U, V, W of one sign:
     * the sign bits of U ^ V and U ^ W clear. A NaN lane may come out
     * either way here, but its det and t are NaN and the t test below
     * refuses it as tt_intersect_triangle does. */
    const uint32_t inside = ~PK_SIGNS(PK_XOR_OR(U, V, W)) & mm & ~zl;
    /* most lanes miss most triangles on the edge functions: skip the
     * division when every active lane does */
    if (!(inside | zl)) return;
    const pk_v det = PK_ADD(PK_ADD(U, V), W);
    const pk_v Tv = PK_ADD(PK_ADD(PK_MUL(U, PK_MUL(sz, az)), PK_MUL(V, PK_MUL(sz, bz))),
                           PK_MUL(W, PK_MUL(sz, cz)));
    const pk_v inv_det = PK_DIV(one, det);
    const pk_v tt = PK_MUL(Tv, inv_det);
    pk_v bt = *pbt;
    const pk_m ok =
        PK_MAND(PK_MAND(PK_CMP_NEQ(det, zero), PK_CMP_GE(tt, tmin)), PK_CMP_LT(tt, bt));
    const uint32_t acc = PK_BITS(ok) & inside;
    if (!(acc | zl)) return;
    if (any) {
        *pout |= acc;
        *pmm = mm & ~acc;
    } else if (acc) {
        const pk_m am = PK_MASK(acc);
        bt = PK_BLEND(am, bt, tt);
        PK_STORE(bu, PK_BLEND(am, PK_LOAD(bu), PK_MUL(V, inv_det)));
        PK_STORE(bv, PK_BLEND(am, PK_LOAD(bv), PK_MUL(W, inv_det)));
        PK_STOREI(bp, PK_BLENDI(am, PK_LOADI(bp), id));
        *pout |= acc;
    }
    if (zl) {
        /* zero edge functions: tt_intersect_triangle's double-precision
         * recomputation, lane by lane (rare), on the scene's triangle */
        const float *p = T->tri + 9 * (size_t)id;
        _Alignas(64) float bts[PK_L];
        PK_STORE(bts, bt);
        for (; zl; zl &= zl - 1) {
            const uint32_t l = (uint32_t)__builtin_ctz(zl);
            float th, uh, vh;
            if (!kp_tri_row(R, src[l], p, bts[l], &th, &uh, &vh)) continue;
            *pout |= 1u << l;
            if (any) {
                *pmm &= ~(1u << l);
            } else {
                bts[l] = th;
                bu[l] = uh;
                bv[l] = vh;
                bp[l] = id;
            }
        }
        bt = PK_LOAD(bts);
    }
    *pbt = bt;
}

/* A leaf's triangles (count of them, blocks blk) against the lanes mm of
 * one vector of rays: origin (ox, oy, oz) in the group's (kx, ky, kz)
 * order, shear (sx, sy, sz), tmin, the best t so far *pbt; u, v, prim of
 * the lanes in the arrays bu, bv, bp (PK_L each, updated where a lane's
 * best changes); src[l] the lane's row in R (the zero-edge
 * recomputation). Returns the lanes that hit (any = 1: occluded) or whose
 * best changed (any = 0). Zero-area triangles are NaN in the blocks: every
 * lane fails their t test, as tt_intersect_triangle refuses them. */
KP_INLINE uint32_t TT_VARIANT(KD_FN(kp_tris))(const tt_kd_view *T, const tt_tri_block *blk,
                                              uint32_t count, const int kx, const int ky,
                                              const int kz, const pk_v ox, const pk_v oy,
                                              const pk_v oz, const pk_v sx, const pk_v sy,
                                              const pk_v sz, const pk_v tmin, pk_v *pbt,
                                              float *bu, float *bv, uint32_t *bp, uint32_t mm,
                                              const tt_packet_rays *R, const uint16_t *src,
                                              const int any)
{
    uint32_t out = 0;
    for (uint32_t i = 0; i < count && mm; i++) {
        pk_v tv[9];
        for (int k = 0; k < 9; k++) tv[k] = PK_SET1(KP_TRI(blk, i, k));
        TT_VARIANT(KD_FN(kp_tri1))(T, tv, KP_TRI_ID(blk, i), kx, ky, kz, ox, oy, oz, sx, sy, sz,
                                   tmin, pbt, bu, bv, bp, &mm, &out, R, src, any);
    }
    return out;
}

#if KP_K == 2
/* kp_tris for both vectors of a walk at once (base the first's lane): each
 * triangle's coordinates broadcast once for the two, each vector's lanes
 * tested with kp_tri1 exactly as kp_tris would (lanes are independent, so
 * every lane sees the same operations in the same triangle order).
 * Occlusion: answered lanes into P->done. */
KP_INLINE void TT_VARIANT(KD_FN(kp_tris2))(const tt_kd_view *T, kp_rays *P, uint32_t v0,
                                              const tt_tri_block *blk, uint32_t count,
                                              uint32_t *mm, const int any)
{
    const int kx = P->kx, ky = P->ky, kz = P->kz;
    const uint32_t b0 = v0 * PK_L, b1 = b0 + PK_L;
    const pk_v ox0 = PK_LOAD(P->o[kx] + b0), oy0 = PK_LOAD(P->o[ky] + b0),
               oz0 = PK_LOAD(P->o[kz] + b0);
    const pk_v sx0 = PK_LOAD(P->sx + b0), sy0 = PK_LOAD(P->sy + b0), sz0 = PK_LOAD(P->sz + b0);
    const pk_v tmin0 = PK_LOAD(P->tmin + b0);
    const pk_v ox1 = PK_LOAD(P->o[kx] + b1), oy1 = PK_LOAD(P->o[ky] + b1),
               oz1 = PK_LOAD(P->o[kz] + b1);
    const pk_v sx1 = PK_LOAD(P->sx + b1), sy1 = PK_LOAD(P->sy + b1), sz1 = PK_LOAD(P->sz + b1);
    const pk_v tmin1 = PK_LOAD(P->tmin + b1);
    pk_v bt0 = PK_LOAD(P->t + b0), bt1 = PK_LOAD(P->t + b1);
    uint32_t m0 = mm[0], m1 = mm[1], out0 = 0, out1 = 0;
    for (uint32_t i = 0; i < count && (m0 | m1); i++) {
        pk_v tv[9];
        for (int k = 0; k < 9; k++) tv[k] = PK_SET1(KP_TRI(blk, i, k));
        const uint32_t id = KP_TRI_ID(blk, i);
        if (m0)
            TT_VARIANT(KD_FN(kp_tri1))(T, tv, id, kx, ky, kz, ox0, oy0, oz0, sx0, sy0, sz0,
                                       tmin0, &bt0, P->u + b0, P->v + b0, P->prim + b0, &m0,
                                       &out0, P->R, P->src + b0, any);
        if (m1)
            TT_VARIANT(KD_FN(kp_tri1))(T, tv, id, kx, ky, kz, ox1, oy1, oz1, sx1, sy1, sz1,
                                       tmin1, &bt1, P->u + b1, P->v + b1, P->prim + b1, &m1,
                                       &out1, P->R, P->src + b1, any);
    }
    if (any) {
        P->done[v0] |= out0;
        P->done[v0 + 1] |= out1;
    } else {
        PK_STORE(P->t + b0, bt0);
        PK_STORE(P->t + b1, bt1);
    }
}
#endif

#if KP_K <= 2
/* A leaf against c <= PK_L / 2 lanes mm[] of the walk at v0, several
 * triangles a test: with w the power of two >= c, slot s of a vector holds
 * the walk's lane lanes[s % w] against triangle i + s / w, so one test
 * covers PK_L / w triangles (a lone lane: PK_L at once, as the single ray's
 * block test). The triangles come from the blocks' rows by a permute
 * (PK_PERMX; for PK_L / w = 16, two blocks' rows side by side). Each slot
 * is tt_intersect_triangle's float operations as in kp_tris.
 * Closest hits: every slot is tested against its lane's best before the
 * test, then the hits are taken slot by slot in order, which is triangle
 * order for each lane, a triangle replacing the best only when strictly
 * nearer, and a zero-edge slot recomputed against the best as it stands:
 * the order one triangle after the other gives. Occlusion: a lane is
 * answered at any hit. */
KP_INLINE void TT_VARIANT(KD_FN(kp_multi))(const tt_kd_view *T, kp_rays *P, uint32_t v0,
                                              const tt_tri_block *blk, uint32_t count,
                                              const uint32_t *mm, const uint32_t c,
                                              const int any)
{
    const int kx = P->kx, ky = P->ky, kz = P->kz;
    const uint32_t base = v0 * PK_L;
    const uint32_t lg = c <= 1u ? 0u : 32u - (uint32_t)__builtin_clz(c - 1u);
    const uint32_t w = 1u << lg, per = PK_L >> lg, rl = w - 1u;
    _Alignas(64) uint32_t lanes[PK_L];
    PK_STOREI(lanes, PK_SETI(0)); /* (the lanes past w are loaded, never picked) */
    {
        uint32_t k = 0;
        for (uint32_t j = 0; j < KP_K; j++)
            for (uint32_t b = mm[j]; b; b &= b - 1)
                lanes[k++] = j * PK_L + (uint32_t)__builtin_ctz(b);
        for (; k < w; k++) lanes[k] = lanes[0]; /* slots of r >= c: never active */
    }
    /* rep: bit 0 of each triangle's group of w slots */
    const uint32_t rep = kp_rep[lg] & KP_LANES;
    const pk_vi rs = PK_LOADI(kp_rsel[lg]), ts0 = PK_LOADI(kp_tsub[lg]);
    const pk_vi ix = PK_PERMXI(rs, PK_LOADI(lanes));
#if KP_K == 2
#define KP_G(a) PK_PERM2(ix, PK_LOAD((a) + base), PK_LOAD((a) + base + PK_L))
#else
#define KP_G(a) PK_PERMX(ix, PK_LOAD((a) + base))
#endif
    const pk_v ox = KP_G(P->o[kx]), oy = KP_G(P->o[ky]), oz = KP_G(P->o[kz]);
    const pk_v sx = KP_G(P->sx), sy = KP_G(P->sy), sz = KP_G(P->sz);
    const pk_v tmin = KP_G(P->tmin);
    pk_v bt = KP_G(P->t);
#undef KP_G
    /* closest hits: lane r's best so far (t, u, v, prim) */
    _Alignas(64) float best_t[PK_L];
    float best_u[PK_L / 2], best_v[PK_L / 2];
    uint32_t best_p[PK_L / 2], changed = 0;
    if (!any) {
        for (uint32_t r = 0; r < c; r++) {
            const uint32_t l = base + lanes[r];
            best_t[r] = P->t[l];
            best_u[r] = P->u[l];
            best_v[r] = P->v[l];
            best_p[r] = P->prim[l];
        }
        /* (the slots of lanes r >= c are never active) */
        for (uint32_t r = c; r < PK_L; r++) best_t[r] = best_t[0];
    }
    const pk_v zero = PK_SET1(0.0f), one = PK_SET1(1.0f);
    uint32_t open = (1u << c) - 1u; /* lanes r < c not yet occluded */
    for (uint32_t i0 = 0; i0 < count && open; i0 += per) {
        const tt_tri_block *b = blk + (i0 >> 3);
        pk_v tv[9];
#if PK_L > TT_TRI_BLOCK_W
        if (per > TT_TRI_BLOCK_W) {
            /* 16 triangles: this block's row and the next's (itself when
             * there is no next: those slots are past count) */
            const tt_tri_block *b1 = i0 + TT_TRI_BLOCK_W < count ? b + 1 : b;
            for (int k = 0; k < 9; k++) tv[k] = PK_ROW2(b->v[k], b1->v[k]);
        } else
#endif
        {
            const pk_vi tix = PK_ADDI(ts0, PK_SETI(i0 & 7u));
            for (int k = 0; k < 9; k++) tv[k] = PK_PERMX(tix, PK_ROW(b->v[k]));
        }
        const uint32_t nt = count - i0 < per ? count - i0 : per;
        const uint32_t act = ((nt << lg) >= 32u ? ~0u : (1u << (nt << lg)) - 1u) & (rep * open);
        pk_v U, V, W, az, bz, cz;
        TT_VARIANT(KD_FN(kp_edges))(tv, kx, ky, kz, ox, oy, oz, sx, sy, &U, &V, &W, &az, &bz,
                                    &cz);
        uint32_t zl =
            PK_BITS(PK_MOR(PK_MOR(PK_CMP_EQ(U, zero), PK_CMP_EQ(V, zero)), PK_CMP_EQ(W, zero))) &
            act;
        const uint32_t inside = ~PK_SIGNS(PK_XOR_OR(U, V, W)) & act & ~zl;
        if (!(inside | zl)) continue;
        const pk_v det = PK_ADD(PK_ADD(U, V), W);
        const pk_v Tv = PK_ADD(PK_ADD(PK_MUL(U, PK_MUL(sz, az)), PK_MUL(V, PK_MUL(sz, bz))),
                               PK_MUL(W, PK_MUL(sz, cz)));
        const pk_v inv_det = PK_DIV(one, det);
        const pk_v tt = PK_MUL(Tv, inv_det);
        const pk_m ok =
            PK_MAND(PK_MAND(PK_CMP_NEQ(det, zero), PK_CMP_GE(tt, tmin)), PK_CMP_LT(tt, bt));
        uint32_t acc = PK_BITS(ok) & inside;
        if (!(acc | zl)) continue;
        if (!any) {
            _Alignas(64) float ts[PK_L], us[PK_L], vs[PK_L];
            PK_STORE(ts, tt);
            PK_STORE(us, PK_MUL(V, inv_det));
            PK_STORE(vs, PK_MUL(W, inv_det));
            for (uint32_t sl = acc | zl; sl; sl &= sl - 1) {
                const uint32_t s = (uint32_t)__builtin_ctz(sl), r = s & rl;
                const uint32_t id = KP_TRI_ID(blk, i0 + (s >> lg));
                float th, uh, vh;
                if (zl >> s & 1u) {
                    if (!kp_tri_row(P->R, P->src[base + lanes[r]], T->tri + 9 * (size_t)id,
                                    best_t[r], &th, &uh, &vh))
                        continue;
                } else if (ts[s] < best_t[r]) {
                    th = ts[s], uh = us[s], vh = vs[s];
                } else {
                    continue;
                }
                best_t[r] = th;
                best_u[r] = uh;
                best_v[r] = vh;
                best_p[r] = id;
                changed |= 1u << r;
            }
            /* each slot's bound: its lane's best */
            bt = PK_PERMX(rs, PK_LOAD(best_t));
            continue;
        }
        /* zero edge functions: tt_intersect_triangle's double-precision
         * recomputation, slot by slot (rare) */
        for (; zl; zl &= zl - 1) {
            const uint32_t s = (uint32_t)__builtin_ctz(zl), r = s & rl;
            const uint32_t id = KP_TRI_ID(blk, i0 + (s >> lg));
            float th, uh, vh;
            if (kp_tri_row(P->R, P->src[base + lanes[r]], T->tri + 9 * (size_t)id,
                           P->t[base + lanes[r]], &th, &uh, &vh))
                acc |= 1u << s;
        }
        /* a lane's hits folded onto bits 0 .. w - 1 */
        for (uint32_t sh = PK_L >> 1; sh >= w; sh >>= 1) acc |= acc >> sh;
        open &= ~acc;
    }
    if (!any) {
        for (; changed; changed &= changed - 1) {
            const uint32_t r = (uint32_t)__builtin_ctz(changed), l = base + lanes[r];
            P->t[l] = best_t[r];
            P->u[l] = best_u[r];
            P->v[l] = best_v[r];
            P->prim[l] = best_p[r];
        }
        return;
    }
    for (uint32_t hit = ((1u << c) - 1u) & ~open; hit; hit &= hit - 1) {
        const uint32_t l = lanes[__builtin_ctz(hit)];
        P->done[v0 + l / PK_L] |= 1u << (l % PK_L);
    }
}
#endif

/* A leaf's triangles (its blocks) against lanes m[] of the walk at vector
 * v0. Few lanes (at most half a vector) take several triangles a test
 * (kp_multi); otherwise, when the walk's active lanes fit one vector, they
 * are packed into one (PK_PERM2) and the leaf is tested once instead of
 * once per vector. */
KP_INLINE void TT_VARIANT(KD_FN(kp_leaf))(const tt_kd_view *T, kp_rays *P, uint32_t v0,
                                             const uint32_t m, tt_kd_node leaf, const int any,
                                             tt_packet_stats *stats)
{
    const uint32_t count = tt_kd_leaf_count(leaf.bits);
    const tt_tri_block *blk = T->blocks + leaf.u.first;
    (void)stats;
#if TT_STATS
    {
        uint64_t act = 0;
        act += kp_popcount(m);
        TT_COUNT(stats, node_visits, 1);
        TT_COUNT(stats, active_lanes, act);
        TT_COUNT(stats, rays.nodes, act);
        TT_COUNT(stats, rays.leaves, act);
        TT_COUNT(stats, rays.triangles, act * count);
    }
#endif
    if (!count) return;
    const int kx = P->kx, ky = P->ky, kz = P->kz;
    uint32_t mm[KP_K], tot = 0, nz = 0;
    for (uint32_t j = 0; j < KP_K; j++) {
        mm[j] = m >> (j * PK_L) & KP_LANES;
        if (any) mm[j] &= ~P->done[v0 + j];
        tot += kp_popcount(mm[j]);
        nz += mm[j] != 0;
    }
    if (!tot) return;
#if KP_K <= 2
    if (tot <= PK_L / 2) {
        TT_VARIANT(KD_FN(kp_multi))(T, P, v0, blk, count, mm, tot, any);
        return;
    }
#endif
#if KP_PACK
    if (KP_K == 2 && nz == 2 && tot <= PK_L) {
        /* lane r of the packed vector is the walk's lane lanes[r] */
        const uint32_t base = v0 * PK_L;
        _Alignas(64) uint32_t lanes[PK_L];
        uint32_t c = 0;
        for (uint32_t j = 0; j < 2; j++)
            for (uint32_t b = mm[j]; b; b &= b - 1) lanes[c++] = j * PK_L + (uint32_t)__builtin_ctz(b);
        for (uint32_t r = c; r < PK_L; r++) lanes[r] = 0; /* never active */
        const pk_vi ix = PK_LOADI(lanes);
#define KP_G(a) PK_PERM2(ix, PK_LOAD((a) + base), PK_LOAD((a) + base + PK_L))
        const pk_v ox = KP_G(P->o[kx]), oy = KP_G(P->o[ky]), oz = KP_G(P->o[kz]);
        const pk_v sx = KP_G(P->sx), sy = KP_G(P->sy), sz = KP_G(P->sz);
        const pk_v tmin = KP_G(P->tmin);
        pk_v bt = KP_G(P->t);
#undef KP_G
        _Alignas(64) float bu[PK_L], bv[PK_L], ts[PK_L];
        _Alignas(64) uint32_t bp[PK_L];
        uint16_t src[PK_L];
        for (uint32_t r = 0; r < c; r++) src[r] = P->src[base + lanes[r]];
        uint32_t out = TT_VARIANT(KD_FN(kp_tris))(T, blk, count, kx, ky, kz, ox, oy, oz, sx, sy,
                                                  sz, tmin, &bt, bu, bv, bp,
                                                  c == 32 ? ~0u : (1u << c) - 1u, P->R, src, any);
        if (any) {
            for (; out; out &= out - 1) {
                const uint32_t l = lanes[__builtin_ctz(out)];
                P->done[v0 + l / PK_L] |= 1u << (l % PK_L);
            }
        } else if (out) {
            PK_STORE(ts, bt);
            for (; out; out &= out - 1) {
                const uint32_t r = (uint32_t)__builtin_ctz(out), l = base + lanes[r];
                P->t[l] = ts[r];
                P->u[l] = bu[r];
                P->v[l] = bv[r];
                P->prim[l] = bp[r];
            }
        }
        return;
    }
#endif
    (void)tot;
    (void)nz;
#if KP_K == 2 && KP_TRIS2
    if (nz == 2) {
        TT_VARIANT(KD_FN(kp_tris2))(T, P, v0, blk, count, mm, any);
        return;
    }
#endif
    for (uint32_t j = 0; j < KP_K; j++) {
        const uint32_t vi = v0 + j, base = vi * PK_L;
        if (!mm[j]) continue;
        const pk_v ox = PK_LOAD(P->o[kx] + base), oy = PK_LOAD(P->o[ky] + base),
                   oz = PK_LOAD(P->o[kz] + base);
        const pk_v sx = PK_LOAD(P->sx + base), sy = PK_LOAD(P->sy + base),
                   sz = PK_LOAD(P->sz + base);
        const pk_v tmin = PK_LOAD(P->tmin + base);
        pk_v bt = PK_LOAD(P->t + base);
        const uint32_t out = TT_VARIANT(KD_FN(kp_tris))(
            T, blk, count, kx, ky, kz, ox, oy, oz, sx, sy, sz, tmin, &bt, P->u + base,
            P->v + base, P->prim + base, mm[j], P->R, P->src + base, any);
        if (any) P->done[vi] |= out;
        else PK_STORE(P->t + base, bt);
    }
}

/* One walk: the vectors v0 .. v0 + KP_K - 1 of the group from the root.
 * Its lanes are one word, vector j's at bit j * PK_L (KP_K * PK_L <= 32):
 * a node's two child masks, a stack entry's and a pop's are then word
 * operations, not a loop over the vectors (callgrind: the per-vector mask
 * bookkeeping was about a third of a node's instructions). */
KP_INLINE void TT_VARIANT(KD_FN(kp_walk))(const tt_kd_view *T, kp_rays *P, uint32_t v0,
                                             const int any, tt_packet_stats *stats)
{
    kp_entry stack[TT_KD_STACK];
    int sp = 0;
    pk_v ta[KP_K], tb[KP_K];
    uint32_t m = 0;
    for (uint32_t j = 0; j < KP_K; j++) {
        m |= P->live[v0 + j] << (j * PK_L);
        ta[j] = PK_LOAD(P->ta + (v0 + j) * PK_L);
        tb[j] = PK_LOAD(P->tb + (v0 + j) * PK_L);
    }
    if (!m) return;
    /* the group's direction signs, bit k for axis k */
    const uint32_t down = (uint32_t)P->down[0] | (uint32_t)P->down[1] << 1 |
                          (uint32_t)P->down[2] << 2;
    uint32_t node = 0;
    (void)stats;
    for (;;) {
        tt_kd_node n = T->nodes[node];
        while (!tt_kd_is_leaf(n.bits)) {
#if TT_STATS
            {
                const uint64_t act = kp_popcount(m);
                TT_COUNT(stats, node_visits, 1);
                TT_COUNT(stats, active_lanes, act);
                TT_COUNT(stats, rays.nodes, act);
                TT_COUNT(stats, rays.interior, act);
            }
#endif
            const int k = tt_kd_axis(n.bits);
            const uint32_t left = tt_kd_left(node, n.bits), right = tt_kd_right(n.bits);
            const uint32_t dk = down >> k & 1u;
            const uint32_t first = dk ? right : left, second = dk ? left : right;
            const pk_v split = PK_SET1(n.u.split);
            uint32_t far_only = 0, near_only = 0;
            pk_v lo[KP_K], hi[KP_K];
            for (uint32_t j = 0; j < KP_K; j++) {
                const uint32_t base = (v0 + j) * PK_L;
                const pk_v ts = PK_MUL(PK_SUB(split, PK_LOAD(P->o[k] + base)),
                                       PK_LOAD(P->inv[k] + base));
                const pk_v e = PK_LOAD(P->e[k] + base);
                lo[j] = PK_SUB(ts, e);
                hi[j] = PK_ADD(ts, e);
                far_only |= PK_BITS(PK_CMP_LT(hi[j], ta[j])) << (j * PK_L);
                near_only |= PK_BITS(PK_CMP_GT(lo[j], tb[j])) << (j * PK_L);
            }
            /* HTR's branches: hi < ta the far child alone, else lo > tb
             * the near child alone, else both */
            const uint32_t fm = m & ~far_only, sm = m & (far_only | ~near_only);
            if (fm && sm) {
                kp_entry *e = &stack[sp++];
                e->node = second;
                e->m = sm;
                for (uint32_t j = 0; j < KP_K; j++) {
                    e->ta[j] = PK_MAX(ta[j], lo[j]);
                    e->tb[j] = tb[j];
                    tb[j] = PK_MIN(tb[j], hi[j]);
                }
                m = fm;
                node = first;
            } else if (fm) {
                /* (lanes going near only keep tb: lo > tb there, so hi > tb) */
                for (uint32_t j = 0; j < KP_K; j++) tb[j] = PK_MIN(tb[j], hi[j]);
                m = fm;
                node = first;
            } else if (sm) {
                for (uint32_t j = 0; j < KP_K; j++) ta[j] = PK_MAX(ta[j], lo[j]);
                m = sm;
                node = second;
            } else {
                goto pop;
            }
            n = T->nodes[node];
        }
        TT_VARIANT(KD_FN(kp_leaf))(T, P, v0, m, n, any, stats);
    pop:
        for (;;) {
            if (!sp) return;
            const kp_entry *e = &stack[--sp];
            /* tt_kd_htr_pop: entries beginning at or past the lane's
             * closest hit so far are dropped (occlusion: answered lanes) */
            uint32_t drop = 0;
            for (uint32_t j = 0; j < KP_K; j++) {
                const uint32_t base = (v0 + j) * PK_L;
                drop |= PK_BITS(PK_CMP_GE(e->ta[j], PK_LOAD(P->t + base))) << (j * PK_L);
                if (any) drop |= P->done[v0 + j] << (j * PK_L);
            }
            m = e->m & ~drop;
            if (m) {
                node = e->node;
                for (uint32_t j = 0; j < KP_K; j++) {
                    ta[j] = e->ta[j];
                    tb[j] = e->tb[j];
                }
                break;
            }
        }
    }
}

/* Loads the group's rays idx[0..n) into P, in the caller's order: a
 * scalar copy into structure of arrays, then the root interval and the
 * bands a vector at a time (the per-ray scalar form, tt_kd_band_init +
 * tt_kd_root_interval, took about 9% of the primary packet time, perf).
 * Every lane does tt_kd_box_interval's float operations in its order: the
 * group's signs fix each axis's near and far face (no ray here has a zero
 * direction component), so the faces are the same for all its lanes. */
KP_INLINE void TT_VARIANT(KD_FN(kp_load))(const tt_kd_view *T, kp_rays *P,
                                             const tt_packet_rays *R, const uint16_t *idx,
                                             uint32_t n, uint32_t group)
{
    const uint32_t i0 = idx[0];
    P->n = n;
    P->R = R;
    /* whole walks: lanes past n repeat the first ray, never live */
    P->vecs = (n + KP_RAYS - 1) / KP_RAYS * KP_K;
    /* the group (octant * 3 + kz) fixes tt_wray_init's permutation */
    const int kz = (int)(group % 3u);
    for (int k = 0; k < 3; k++) P->down[k] = (int)(group / 3u >> k & 1u);
    {
        const int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
        P->kx = P->down[kz] ? ky : kx;
        P->ky = P->down[kz] ? kx : ky;
        P->kz = kz;
    }
    const uint32_t lanes = P->vecs * PK_L;
    _Alignas(64) float d[3][KP_N];
    uint32_t i = 0;
    /* whole vectors of consecutive rows (the usual case: kp_group appends
     * a tile's vectors whole) by vector loads; the scalar copy was about
     * 27 instructions a ray (callgrind, sibenik shadows) */
    for (; i + PK_L <= n && idx[i + PK_L - 1] - idx[i] == PK_L - 1; i += PK_L) {
        const uint32_t j = idx[i];
        for (uint32_t l = 0; l < PK_L; l++) P->src[i + l] = (uint16_t)(j + l);
        for (int k = 0; k < 3; k++) {
            PK_STORE(P->o[k] + i, PK_LOADU(R->org[k] + j));
            PK_STORE(d[k] + i, PK_LOADU(R->dir[k] + j));
        }
        PK_STORE(P->tmin + i, PK_LOADU(R->tmin + j));
        PK_STORE(P->t + i, PK_LOADU(R->tmax + j));
    }
    for (; i < lanes; i++) {
        const uint32_t j = i < n ? idx[i] : i0;
        P->src[i] = (uint16_t)j;
        for (int k = 0; k < 3; k++) {
            P->o[k][i] = R->org[k][j];
            d[k][i] = R->dir[k][j];
        }
        P->tmin[i] = R->tmin[j];
        P->t[i] = R->tmax[j];
    }
    /* tt_wray_init's inv (tt_safe_inv: no component is zero here) and
     * shear, a vector at a time with its IEEE operations */
    {
        const pk_v one = PK_SET1(1.0f), zero = PK_SET1(0.0f), tiny = PK_SET1(1e-30f);
        const pk_v big = PK_SET1(1e30f), nbig = PK_SET1(-1e30f);
        for (uint32_t base = 0; base < lanes; base += PK_L) {
            for (int k = 0; k < 3; k++) {
                const pk_v x = PK_LOAD(d[k] + base);
                const pk_v huge = PK_BLEND(PK_CMP_LT(x, zero), big, nbig);
                PK_STORE(P->inv[k] + base,
                         PK_BLEND(PK_CMP_LT(PK_ANDNOT(PK_SET1(-0.0f), x), tiny), PK_DIV(one, x),
                                  huge));
            }
            const pk_v dz = PK_LOAD(d[kz] + base);
            PK_STORE(P->sx + base, PK_DIV(PK_LOAD(d[P->kx] + base), dz));
            PK_STORE(P->sy + base, PK_DIV(PK_LOAD(d[P->ky] + base), dz));
            PK_STORE(P->sz + base, PK_DIV(one, dz));
        }
    }
    const int empty = T->empty;
    float m[3], fn[3], ff[3];
    for (int k = 0; k < 3; k++) {
        const float lo = TT_LDG(&T->aug[0].lo[k]), hi = TT_LDG(&T->aug[0].hi[k]);
        m[k] = tt_kd_max(fabsf(lo), fabsf(hi));
        fn[k] = P->down[k] ? hi : lo;
        ff[k] = P->down[k] ? lo : hi;
    }
    const pk_v band = PK_SET1(TT_KD_BAND), zero = PK_SET1(0.0f), sign = PK_SET1(-0.0f);
    for (uint32_t v = 0; v < P->vecs; v++) {
        const uint32_t base = v * PK_L;
        const pk_v tmax = PK_LOAD(P->t + base);
        pk_v t0 = PK_LOAD(P->tmin + base), t1 = PK_SET1(TT_INF);
        for (int k = 0; k < 3; k++) {
            const pk_v o = PK_LOAD(P->o[k] + base), inv = PK_LOAD(P->inv[k] + base);
            /* tt_kd_band_init */
            const pk_v bi = PK_MUL(band, PK_ANDNOT(sign, inv));
            const pk_v bo = PK_MUL(bi, PK_ANDNOT(sign, o));
            /* tt_kd_htr_moving's per-axis band */
            PK_STORE(P->e[k] + base, PK_ADD(PK_MUL(PK_SET1(m[k]), bi), bo));
            /* tt_kd_box_interval with the band */
            pk_v tn = PK_MUL(PK_SUB(PK_SET1(fn[k]), o), inv);
            pk_v tf = PK_MUL(PK_SUB(PK_SET1(ff[k]), o), inv);
            tn = PK_SUB(tn, PK_ADD(PK_MUL(PK_SET1(fabsf(fn[k])), bi), bo));
            tf = PK_ADD(tf, PK_ADD(PK_MUL(PK_SET1(fabsf(ff[k])), bi), bo));
            t0 = PK_MAX(t0, tn);
            t1 = PK_MIN(t1, tf);
        }
        uint32_t hit = PK_BITS(PK_MAND(PK_CMP_LE(t0, t1), PK_CMP_LT(t0, tmax)));
        if (empty) hit = 0;
        if (base + PK_L > n) hit &= base >= n ? 0u : (1u << (n - base)) - 1u;
        P->live[v] = hit;
        P->done[v] = 0;
        /* missing lanes: [0, 0] as before (never live) */
        const pk_m hm = PK_MASK(hit);
        PK_STORE(P->ta + base, PK_BLEND(hm, zero, t0));
        PK_STORE(P->tb + base, PK_BLEND(hm, zero, PK_MIN(t1, tmax)));
        PK_STORE(P->u + base, zero);
        PK_STORE(P->v + base, zero);
        PK_STOREI(P->prim + base, PK_SETI(TT_INVALID_ID));
    }
}

/* One ray through the single-ray kernel (small groups, rays with a zero
 * direction component). */
KP_INLINE void TT_VARIANT(KD_FN(kp_single))(const tt_kd_view *T, const tt_kd_view *V,
                                               const tt_wray *r, int any, tt_hit *hit,
                                               uint8_t *occ, tt_packet_stats *stats)
{
    uint32_t end;
    (void)stats;
    (void)V;
#if TT_STATS
    /* the counting kernel tests leaves through refs[]: the tree's own view */
    T = V;
    const uint64_t before = stats->rays.rays;
    if (any) *occ = (uint8_t)(tt_kd_cpu_occluded_stats(T, TT_KD_HTR, r, TT_INVALID_ID,
                                                       TT_INVALID_ID, &end, &stats->rays) != 0);
    else tt_kd_cpu_intersect_stats(T, TT_KD_HTR, r, TT_INVALID_ID, hit, &end, &stats->rays);
    stats->rays.rays = before; /* counted once by the packet */
    TT_COUNT(stats, fallback_rays, 1);
#else
    if (any) *occ = (uint8_t)(KD_SINGLE_OCCLUDED(T, TT_KD_HTR, r, TT_INVALID_ID, TT_INVALID_ID,
                                                 &end) != 0);
    else KD_SINGLE_INTERSECT(T, TT_KD_HTR, r, TT_INVALID_ID, hit, &end);
#endif
}

/* The entry point: rays[0..n) (n <= TT_PACKET_MAX) grouped by octant and
 * dominant axis, each group traced in walks of KP_RAYS rays (small groups
 * ray by ray); closest hits into hits (any = 0) or occlusion bytes into
 * occ (any = 1). */
void TT_VARIANT(KD_FN(tt_kd_packet))(const tt_kd_view *T, const tt_kd_view *V,
                                     const tt_packet_rays *R, int any, tt_hit *hits, uint8_t *occ,
                                     tt_packet_stats *stats)
{
    const uint32_t n = R->n;
    uint16_t idx[KP_GROUPS][KP_N];
    uint32_t cnt[KP_GROUPS] = {0};
    TT_COUNT(stats, rays.rays, n);
    /* each ray's group, its compares a vector at a time (a scalar compare
     * and branch per component was about 30 instructions a ray): the
     * octant, and tt_wray_init's dominant axis (x wins ties, then y) */
    const pk_v zero = PK_SET1(0.0f);
    for (uint32_t o = 0; o < n; o += PK_L) {
        /* (lanes past n read rows the packet does not use: their bits are
         * dropped) */
        const pk_v x = PK_LOAD(R->dir[0] + o), y = PK_LOAD(R->dir[1] + o),
                   z = PK_LOAD(R->dir[2] + o);
        const pk_v ax = PK_ANDNOT(PK_SET1(-0.0f), x), ay = PK_ANDNOT(PK_SET1(-0.0f), y),
                   az = PK_ANDNOT(PK_SET1(-0.0f), z);
        const pk_m m0 = PK_MAND(PK_CMP_GE(ax, ay), PK_CMP_GE(ax, az));
        const uint32_t lanes = n - o < PK_L ? n - o : PK_L;
        const uint32_t zb =
            PK_BITS(PK_MOR(PK_MOR(PK_CMP_EQ(x, zero), PK_CMP_EQ(y, zero)), PK_CMP_EQ(z, zero)));
        const uint32_t nx = PK_BITS(PK_CMP_LT(x, zero)), ny = PK_BITS(PK_CMP_LT(y, zero)),
                       nz = PK_BITS(PK_CMP_LT(z, zero));
        const uint32_t b0 = PK_BITS(m0), b1 = PK_BITS(PK_MANDNOT(m0, PK_CMP_GE(ay, az)));
        /* a whole vector of one group (a tile's neighbours mostly are): its
         * rows appended at once (the lane by lane group arithmetic below
         * was about 35 instructions a ray, callgrind, sibenik shadows) */
        if (lanes == PK_L && !zb && KP_UNIFORM(nx) && KP_UNIFORM(ny) && KP_UNIFORM(nz) &&
            KP_UNIFORM(b0) && KP_UNIFORM(b1)) {
            const uint32_t g = ((nx & 1u) | (ny & 1u) << 1 | (nz & 1u) << 2) * 3u + 2u -
                               2u * (b0 & 1u) - (b1 & 1u);
            uint16_t *to = idx[g] + cnt[g];
            for (uint32_t l = 0; l < PK_L; l++) to[l] = (uint16_t)(o + l);
            cnt[g] += PK_L;
            continue;
        }
        for (uint32_t l = 0; l < lanes; l++) {
            const uint32_t i = o + l;
            if (zb >> l & 1u) {
                tt_wray w;
                tt_packet_ray_wray(R, i, &w);
                TT_VARIANT(KD_FN(kp_single))(T, V, &w, any, any ? NULL : hits + i,
                                             any ? occ + i : NULL, stats);
                continue;
            }
            const uint32_t g = ((nx >> l & 1u) | (ny >> l & 1u) << 1 | (nz >> l & 1u) << 2) * 3u +
                               2u - 2u * (b0 >> l & 1u) - (b1 >> l & 1u);
            idx[g][cnt[g]++] = (uint16_t)i;
        }
    }
    _Alignas(64) kp_rays P;
    for (uint32_t g = 0; g < KP_GROUPS; g++) {
        const uint32_t c = cnt[g];
        if (!c) continue;
        if (c < KP_MIN_RAYS) {
            for (uint32_t j = 0; j < c; j++) {
                const uint32_t i = idx[g][j];
                tt_wray w;
                tt_packet_ray_wray(R, i, &w);
                TT_VARIANT(KD_FN(kp_single))(T, V, &w, any, any ? NULL : hits + i,
                                             any ? occ + i : NULL, stats);
            }
            continue;
        }
        TT_COUNT(stats, packets, 1);
        TT_COUNT(stats, rays.boxes, c);
        TT_VARIANT(KD_FN(kp_load))(T, &P, R, idx[g], c, g);
        /* a walk inlined for each mode: the occlusion tests fold away */
        if (any)
            for (uint32_t v0 = 0; v0 < P.vecs; v0 += KP_K)
                TT_VARIANT(KD_FN(kp_walk))(T, &P, v0, 1, stats);
        else
            for (uint32_t v0 = 0; v0 < P.vecs; v0 += KP_K)
                TT_VARIANT(KD_FN(kp_walk))(T, &P, v0, 0, stats);
        uint32_t j = 0;
        if (any)
            /* a vector of consecutive rows: its answer bits four at a time
             * into bytes (bit q of a nibble lands alone on bit 8 q of the
             * product) */
            for (; j + PK_L <= c && idx[g][j + PK_L - 1] - idx[g][j] == PK_L - 1; j += PK_L) {
                uint8_t *out = occ + idx[g][j];
                for (uint32_t q = 0; q < PK_L; q += 4) {
                    const uint32_t b = ((P.done[j / PK_L] >> q & 15u) * 0x00204081u) & 0x01010101u;
                    out[q] = (uint8_t)b;
                    out[q + 1] = (uint8_t)(b >> 8);
                    out[q + 2] = (uint8_t)(b >> 16);
                    out[q + 3] = (uint8_t)(b >> 24);
                }
            }
        for (; j < c; j++) {
            const uint32_t i = idx[g][j];
            if (any) {
                occ[i] = (uint8_t)(P.done[j / PK_L] >> (j % PK_L) & 1u);
            } else {
                tt_hit *h = &hits[i];
                h->prim = P.prim[j];
                h->t = P.prim[j] == TT_INVALID_ID ? TT_INF : P.t[j];
                h->u = P.u[j];
                h->v = P.v[j];
            }
        }
    }
}
