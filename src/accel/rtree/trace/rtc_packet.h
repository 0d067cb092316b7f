/* Packet traversal of the compact R-tree (rtc_layout.h): up to
 * TT_PACKET_MAX rays (a batch's 16 x 16 tile) walk the tree together, SIMD
 * across rays (PK_L = 8 lanes for AVX2, 16 for AVX-512), a template
 * compiled once per ISA unit (rtc_packet_avx2.c, _avx512.c) and once per
 * statistics variant (accel/stats_variant.h).
 *
 * Method: large packets over a wide tree with whole-node culling (Wald,
 * Boulos & Shirley 2007, "Ray tracing deformable scenes using dynamic
 * bounding volume hierarchies", and Overbeck, Ramamoorthi & Mark 2008,
 * "Large ray packets for real-time Whitted ray tracing": the packet's
 * active rays are kept as per-group lane masks with a first..last range of
 * groups, so a node costs only the groups that still have active rays).
 *  - The packet is split by direction octant first (rays of one octant share
 *    the near/far planes of every box, as the single-ray kernel picks them
 *    per ray, so the packet's box test is straight-line code; a mixed tile
 *    becomes up to 8 smaller packets). An octant with fewer than
 *    PK_MIN_RAYS rays is traced ray by ray (the single-ray kernel).
 *  - Per node, an interval-arithmetic test (Boulos et al. 2006; Wald et al.
 *    2007 §4) of all S child boxes at once against the bounds of the
 *    packet's origins and reciprocal directions culls children no ray can
 *    hit; it is conservative to the rounding (float subtraction and
 *    multiplication round monotonically), so it drops only boxes that every
 *    ray's own test misses.
 *  - The surviving children are tested ray by ray, SIMD across the rays of
 *    each active group, with exactly the single-ray kernel's operations in
 *    its order (rtc_box_x86.h / tt_rt_box_test_at), against each ray's own
 *    closest hit so far. The hit children are entered near to far by their
 *    nearest ray's entry distance.
 *  - Leaves: a block of 8 triangles is tested against the rays of a group
 *    SIMD across rays, triangle by triangle in lane order (only the
 *    triangles of the leaves hit on it, rtc_pk_block), with
 *    tt_intersect_triangle's float operations in its order; a lane with a
 *    zero edge function is recomputed by tt_intersect_triangle itself, and
 *    a group whose rays do not share the shear's axis permutation is tested
 *    ray by ray with the single-ray block kernel. So every ray's candidate
 *    triangles give the single-ray kernel's t, u, v bit for bit, and its
 *    closest hit is the single-ray answer (ties at equal t go to the
 *    smaller id in both: rtc_pk_block). A group with few active lanes
 *    (PK_LEAF_SINGLE) takes the single-ray block kernel too: it tests the
 *    block's 8 triangles at once, where the packet's test pays a pass per
 *    triangle whatever the lanes; an occlusion packet's such lanes go two
 *    at a time where the unit defines RTC_OCC_PAIR (AVX-512: a ray a
 *    256-bit half, each half the single-ray kernel's operations).
 *  - Occlusion packets are runs of at most PK_OCC_CHUNK consecutive rays of
 *    an octant: shadow rays come in image order, and a shorter run's
 *    origins bound more tightly, so the interval test culls more; their
 *    active rays fit one 32-bit mask (rtc_pk_walk_occ).
 *
 * The including unit defines PK_L, the vector macros PK_* (see
 * rtc_packet_avx512.c), RTC_ISA, RTC_BLOCKS_INTERSECT / _OCCLUDED (the
 * single-ray block kernels) and RTC_SINGLE (the unit's single-ray stack
 * traversal, for small octants); optionally RTC_OCC_PAIR (two rays'
 * occlusion of one block, bit h for ray h, each as RTC_BLOCKS_OCCLUDED). */
#include <string.h>

#include "accel/rtree/layout/rtc_layout.h"

#ifndef RTC_PACKET_TYPES
#define RTC_PACKET_TYPES

#define PK_N TT_PACKET_MAX
#define PK_G (PK_N / PK_L)
/* Octants with fewer rays go ray by ray: below this the packet's per-node
 * work (interval test, sorting) costs more than it shares. */
#ifndef PK_MIN_RAYS
#define PK_MIN_RAYS 4u
#endif
/* A leaf block meets a group's rays one by one (the single-ray block
 * kernel: its 8 triangles at once) when at most this many of the group's
 * lanes are active: the packet's block test costs a pass per triangle
 * whatever the number of lanes. 6 of 16 lanes measured best (4 and 8 were
 * a few % slower; 2026-12-02, sibenik and bunny, rpacket note). With fewer
 * triangles to test (the hit leaves' share of the block) the limit shrinks
 * in proportion: lanes * 8 <= triangles * PK_LEAF_SINGLE. */
#ifndef PK_LEAF_SINGLE
#define PK_LEAF_SINGLE (PK_L * 3u / 8u)
#endif
/* Occlusion packets take at most this many consecutive rays of an octant:
 * shadow rays in image order (a run of hit points along rows) diverge in
 * their origins, and the interval test of 256 of them culls little;
 * runs of 32 were 4-29% faster than 256 (64: 0-8%, 16: worse on sibenik).
 * Camera tiles stay whole (their 256 rays share the eye). */
#ifndef PK_OCC_CHUNK
#define PK_OCC_CHUNK 32u
#endif
#define PK_CHUNK (any ? PK_OCC_CHUNK : PK_N)

/* One packet of rays of one octant, structure of arrays, PK_G groups of
 * PK_L lanes; lanes past n repeat ray 0 and are never active. */
typedef struct pk_rays {
    _Alignas(64) float ox[PK_N];
    _Alignas(64) float oy[PK_N];
    _Alignas(64) float oz[PK_N];
    _Alignas(64) float rx[PK_N];
    _Alignas(64) float ry[PK_N];
    _Alignas(64) float rz[PK_N];
    _Alignas(64) float tmin[PK_N];
    _Alignas(64) float t[PK_N];
    _Alignas(64) float tcut[PK_N]; /* occlusion: t widened by 2^-15, see rtc_pk_walk */
    /* occlusion with tmin >= 0 (rtc_pk_widen): rx, ry, rz and tcut
     * widened by 2^-20, so the far bound needs no margin of its own */
    _Alignas(64) float fx[PK_N];
    _Alignas(64) float fy[PK_N];
    _Alignas(64) float fz[PK_N];
    _Alignas(64) float tcf[PK_N];
    /* an absolute margin a lane's box test adds to its far and takes off
     * its near distances, 2^-20 max_k |org_k rcp_k| over the axes where
     * that is finite: the single-ray FMA kernels' pad (rtc_box_x86.h),
     * doubled. The watertight triangle test's t errs by roughly the
     * vertices' distance from the origin times 2^-24 (its translated
     * coordinates), not by a fraction of t: a short ray (a shadow ray
     * ending on a triangle far wider than it is long) finds its hit up
     * to ~2^-22 of the scene's size before the plane of a flat box, and
     * the relative margins alone culled that box where the single ray
     * kept it (test_packets' shadow rays ending on occluders, Sibenik). */
    _Alignas(64) float pad[PK_N];
    _Alignas(64) float u[PK_N];
    _Alignas(64) float v[PK_N];
    _Alignas(64) float sx[PK_N];
    _Alignas(64) float sy[PK_N];
    _Alignas(64) float sz[PK_N];
    _Alignas(64) uint32_t prim[PK_N];
    uint16_t src[PK_N];  /* the lane's row in R                            */
    const tt_packet_rays *R;
    uint32_t made[PK_G]; /* lanes whose w[] is built                       */
    uint32_t done[PK_G];  /* occlusion: rays answered                      */
    uint32_t valid[PK_G]; /* lanes holding rays                            */
    int8_t perm[PK_G];    /* the group's shared kx*9+ky*3+kz, or -1         */
    uint8_t kxyz[PK_G][3]; /* perm's kx, ky, kz (decoded once a packet)    */
    uint32_t n, groups;
    uint32_t nrow[3], frow[3]; /* the octant's near / far bound rows (0..5) */
    int ia;                    /* interval test usable (finite reciprocals) */
    float omin[3], omax[3], rmin[3], rmax[3], tmin_min;
    float tcut_max; /* no ray's test keeps a box entered beyond it */
    float pad_max;  /* the largest pad: the interval test's far margin */
    /* lane l's ray for the single-ray triangle tests, built on first use
     * (pk_wray): only the fallbacks want it (a group's few lanes or mixed
     * shears at a leaf, zero edge functions) */
    tt_wray w[PK_N];
} pk_rays;

/* Lane l's ray for the single-ray triangle tests (the block kernels of
 * geometry/tri_block_*.h, tt_intersect_triangle): the fields they read,
 * org, tmin, kx, ky, kz, sx, sy, sz, as tt_wray_init sets them, from the
 * packet's rows (no division); dir, inv, rcp and tmax are left unset, and
 * nothing else may take this ray. A shadow packet's few-lane groups take
 * this path at many leaves (a whole tt_wray was 92 instructions a lane). */
static inline const tt_wray *pk_wray(pk_rays *P, uint32_t l)
{
    const uint32_t g = l / PK_L, bit = 1u << (l % PK_L);
    tt_wray *w = &P->w[l];
    if (P->made[g] & bit) return w;
    P->made[g] |= bit;
    const tt_packet_rays *R = P->R;
    const uint32_t j = P->src[l];
    const float dir[3] = {R->dir[0][j], R->dir[1][j], R->dir[2][j]};
    w->org[0] = P->ox[l];
    w->org[1] = P->oy[l];
    w->org[2] = P->oz[l];
    w->tmin = P->tmin[l];
    const float ax = fabsf(dir[0]), ay = fabsf(dir[1]), az = fabsf(dir[2]);
    const int kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    const int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
    const int neg = dir[kz] < 0.0f;
    w->kx = neg ? ky : kx;
    w->ky = neg ? kx : ky;
    w->kz = kz;
    w->sx = P->sx[l];
    w->sy = P->sy[l];
    w->sz = P->sz[l];
    return w;
}

/* 1 for a negative float, -0 included (the octant of a direction: its
 * reciprocal's sign, as the single-ray kernels pick near planes by it) */
static inline uint32_t pk_sign(float x)
{
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return b >> 31;
}

/* A node waiting on the stack with its active rays. */
typedef struct pk_entry {
    uint32_t node, level, g0, g1;
    uint32_t m[PK_G];
} pk_entry;

#define PK_STACK (TT_RTC_STACK_SIZE)

static inline uint32_t pk_popcount(uint32_t x) { return (uint32_t)__builtin_popcount(x); }

/* An occlusion packet (rtc_pk_walk_occ): groups, a group's lane bits, a
 * waiting node with its rays. */
#define PK_OG (32u / PK_L)
#define PK_LANES ((uint32_t)((1ull << PK_L) - 1u))
_Static_assert(PK_OCC_CHUNK <= 32u, "an occlusion packet's rays fit a 32-bit mask");
typedef struct pk_oentry {
    uint32_t node, level, m;
} pk_oentry;

/* A child's box broadcast to every lane: its near planes n[k] and far
 * planes f[k] by the octant's rows (offsets nr, fr: rtc_pk_consts), which
 * both walks test against one group of rays after another. */
typedef struct pk_cbox {
    pk_v n[3], f[3];
} pk_cbox;

TT_RT_INLINE pk_cbox pk_child_box(const float *box, const uint32_t nr[3], const uint32_t fr[3],
                                   uint32_t c)
{
    pk_cbox b;
    for (int k = 0; k < 3; k++) {
        b.n[k] = PK_SET1(box[nr[k] + c]);
        b.f[k] = PK_SET1(box[fr[k] + c]);
    }
    return b;
}

/* The slab distances of child box cb for the rays of the group at offset o:
 * the entry (the largest near plane, at least tmin) and the three far
 * planes, which each walk closes with its own far bound. */
TT_RT_INLINE pk_v pk_child_slabs(const pk_cbox *cb, const pk_rays *P, uint32_t o, pk_v far[3])
{
    const pk_v ox = PK_LOAD(P->ox + o), oy = PK_LOAD(P->oy + o), oz = PK_LOAD(P->oz + o);
    const pk_v ix = PK_LOAD(P->rx + o), iy = PK_LOAD(P->ry + o), iz = PK_LOAD(P->rz + o);
    const pk_v tnx = PK_MUL(PK_SUB(cb->n[0], ox), ix);
    const pk_v tny = PK_MUL(PK_SUB(cb->n[1], oy), iy);
    const pk_v tnz = PK_MUL(PK_SUB(cb->n[2], oz), iz);
    far[0] = PK_MUL(PK_SUB(cb->f[0], ox), ix);
    far[1] = PK_MUL(PK_SUB(cb->f[1], oy), iy);
    far[2] = PK_MUL(PK_SUB(cb->f[2], oz), iz);
    return PK_MAX(tnz, PK_MAX(tny, PK_MAX(tnx, PK_LOAD(P->tmin + o))));
}

/* The occlusion walk's overlap test of child box cb for the group at
 * offset o, with rtc_pk_widen's rows: the lanes where the entry is at most
 * the far bound. The lean test closes the far bound tc = min(far planes,
 * tcut) with tc + |tc| 2^-22; here the far planes use reciprocals and tcut
 * widened by 2^-20 instead, which for tc >= 0 is never below that (a
 * product with a factor at least 1 + 2^-20 - 2^-24 against at most
 * 1 + 2^-22 + 2^-23 in all), and for tc < 0 both miss, the entry being at
 * least tmin >= 0. Three vector operations fewer a test. */
TT_RT_INLINE uint32_t pk_child_occ_wide(const pk_cbox *cb, const pk_rays *P, uint32_t o)
{
    const pk_v ox = PK_LOAD(P->ox + o), oy = PK_LOAD(P->oy + o), oz = PK_LOAD(P->oz + o);
    const pk_v tnx = PK_MUL(PK_SUB(cb->n[0], ox), PK_LOAD(P->rx + o));
    const pk_v tny = PK_MUL(PK_SUB(cb->n[1], oy), PK_LOAD(P->ry + o));
    const pk_v tnz = PK_MUL(PK_SUB(cb->n[2], oz), PK_LOAD(P->rz + o));
    const pk_v tfx = PK_MUL(PK_SUB(cb->f[0], ox), PK_LOAD(P->fx + o));
    const pk_v tfy = PK_MUL(PK_SUB(cb->f[1], oy), PK_LOAD(P->fy + o));
    const pk_v tfz = PK_MUL(PK_SUB(cb->f[2], oz), PK_LOAD(P->fz + o));
    const pk_v tn = PK_MAX(tnz, PK_MAX(tny, PK_MAX(tnx, PK_LOAD(P->tmin + o))));
    const pk_v tc = PK_MIN(tfz, PK_MIN(tfy, PK_MIN(tfx, PK_LOAD(P->tcf + o))));
    return PK_BITS(PK_CMP_LE(tn, PK_ADD(tc, PK_LOAD(P->pad + o))));
}

/* rtc_pk_load's reciprocals and tcut times 1 + 2^-20 into fx, fy, fz, tcf
 * (rounded: at least r (1 + 2^-20 - 2^-24) in magnitude, and never below
 * r, both being normal or the product rounding up from r) for
 * pk_child_occ_wide. */
TT_RT_INLINE void pk_widen(pk_rays *P)
{
    const pk_v w = PK_SET1(1.0f + 1.0f / 1048576.0f);
    for (uint32_t o = 0; o < P->groups * PK_L; o += PK_L) {
        PK_STORE(P->fx + o, PK_MUL(PK_LOAD(P->rx + o), w));
        PK_STORE(P->fy + o, PK_MUL(PK_LOAD(P->ry + o), w));
        PK_STORE(P->fz + o, PK_MUL(PK_LOAD(P->rz + o), w));
        PK_STORE(P->tcf + o, PK_MUL(PK_LOAD(P->tcut + o), w));
    }
}

#endif

/* Block b's triangles against the rays of group g in lanes m (nonzero).
 * A lane's hit is replaced by a nearer triangle, or at equal t by one with
 * a smaller id (tt_tri_better, geometry/tri_block.h): the single-ray block
 * kernels' rule, which makes the closest hit independent of the order in
 * which blocks are visited. Ids are below 2^31, and TT_INVALID_ID is -1 as
 * a signed integer, so "id < the lane's id" as a signed compare is false
 * while the lane has no hit (its t is then tmax, an open bound). */
TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_block))(pk_rays *P, const int any, uint32_t g,
                                                   uint32_t m, const tt_tri_block *b,
                                                   uint32_t tm)
{
    const uint32_t base = g * PK_L;
        if (P->perm[g] < 0 || pk_popcount(m) * TT_TRI_BLOCK_W <= pk_popcount(tm) * PK_LEAF_SINGLE) {
        /* the rays of this group shear differently: one by one with the
         * single-ray kernel */
#ifdef RTC_OCC_PAIR
        if (any) {
            /* occlusion: two rays a call where the unit has a pair kernel
             * (AVX-512: 5-8% faster shadow packets on the shared views,
             * the few-lane groups' leaf tests being a quarter of them) */
            while (m) {
                const uint32_t l0 = base + (uint32_t)__builtin_ctz(m);
                m &= m - 1;
                if (!m) {
                    if (RTC_BLOCKS_OCCLUDED(pk_wray(P, l0), b, 1, P->t[l0]))
                        P->done[g] |= 1u << (l0 - base);
                    break;
                }
                const uint32_t l1 = base + (uint32_t)__builtin_ctz(m);
                m &= m - 1;
                const uint32_t o = RTC_OCC_PAIR(pk_wray(P, l0), pk_wray(P, l1), b, P->t[l0], P->t[l1]);
                P->done[g] |= (o & 1u) << (l0 - base) | (o >> 1) << (l1 - base);
            }
            return;
        }
#endif
        while (m) {
            const uint32_t l = base + (uint32_t)__builtin_ctz(m);
            m &= m - 1;
            if (any) {
                if (RTC_BLOCKS_OCCLUDED(pk_wray(P, l), b, 1, P->t[l])) P->done[g] |= 1u << (l - base);
            } else {
                tt_hit h = {P->t[l], P->u[l], P->v[l], P->prim[l]};
                if (RTC_BLOCKS_INTERSECT(pk_wray(P, l), b, 1, &h)) {
                    P->t[l] = h.t;
                    P->u[l] = h.u;
                    P->v[l] = h.v;
                    P->prim[l] = h.prim;
                }
            }
        }
        return;
    }
    const int kx = P->kxyz[g][0], ky = P->kxyz[g][1], kz = P->kxyz[g][2];
    const float *const orow[3] = {P->ox + base, P->oy + base, P->oz + base};
    const pk_v ox = PK_LOAD(orow[kx]), oy = PK_LOAD(orow[ky]), oz = PK_LOAD(orow[kz]);
    const pk_v sx = PK_LOAD(P->sx + base), sy = PK_LOAD(P->sy + base), sz = PK_LOAD(P->sz + base);
    const pk_v tmin = PK_LOAD(P->tmin + base);
    const pk_v zero = PK_SET1(0.0f), one = PK_SET1(1.0f);
    /* only the triangles of the leaves hit here (tm: lanes of real
     * triangles; a pass costs the same for any number of lanes). The
     * single-ray kernel tests the whole block, its neighbours' triangles
     * too, at no cost; the answers agree: a ray's closest hit (and any hit
     * in range) lies in a leaf whose box the ray's conservative test
     * keeps, where both test it. */
    for (int i = 0; i < TT_TRI_BLOCK_W && m; i++) {
        if (!(tm >> i & 1u)) continue;
        const pk_v ax = PK_SUB(PK_SET1(b->v[kx][i]), ox), ay = PK_SUB(PK_SET1(b->v[ky][i]), oy),
                   az = PK_SUB(PK_SET1(b->v[kz][i]), oz);
        const pk_v bx = PK_SUB(PK_SET1(b->v[3 + kx][i]), ox),
                   by = PK_SUB(PK_SET1(b->v[3 + ky][i]), oy),
                   bz = PK_SUB(PK_SET1(b->v[3 + kz][i]), oz);
        const pk_v cx = PK_SUB(PK_SET1(b->v[6 + kx][i]), ox),
                   cy = PK_SUB(PK_SET1(b->v[6 + ky][i]), oy),
                   cz = PK_SUB(PK_SET1(b->v[6 + kz][i]), oz);
        const pk_v Ax = PK_SUB(ax, PK_MUL(sx, az)), Ay = PK_SUB(ay, PK_MUL(sy, az));
        const pk_v Bx = PK_SUB(bx, PK_MUL(sx, bz)), By = PK_SUB(by, PK_MUL(sy, bz));
        const pk_v Cx = PK_SUB(cx, PK_MUL(sx, cz)), Cy = PK_SUB(cy, PK_MUL(sy, cz));
        const pk_v U = PK_SUB(PK_MUL(Cx, By), PK_MUL(Cy, Bx));
        const pk_v V = PK_SUB(PK_MUL(Ax, Cy), PK_MUL(Ay, Cx));
        const pk_v W = PK_SUB(PK_MUL(Bx, Ay), PK_MUL(By, Ax));
        const uint32_t zl =
            PK_BITS(PK_MOR(PK_MOR(PK_CMP_EQ(U, zero), PK_CMP_EQ(V, zero)), PK_CMP_EQ(W, zero))) &
            m;
        const pk_m neg = PK_MOR(PK_MOR(PK_CMP_LT(U, zero), PK_CMP_LT(V, zero)), PK_CMP_LT(W, zero));
        const pk_m pos = PK_MOR(PK_MOR(PK_CMP_GT(U, zero), PK_CMP_GT(V, zero)), PK_CMP_GT(W, zero));
        /* no lane inside all three edges: no division (16 lanes' worth a
         * triangle), as the single-ray block kernel skips a block */
        const uint32_t in = ~PK_BITS(PK_MAND(neg, pos)) & m & ~zl;
        if (in) {
            const pk_v det = PK_ADD(PK_ADD(U, V), W);
            const pk_v T = PK_ADD(PK_ADD(PK_MUL(U, PK_MUL(sz, az)), PK_MUL(V, PK_MUL(sz, bz))),
                                  PK_MUL(W, PK_MUL(sz, cz)));
            const pk_v inv_det = PK_DIV(one, det);
            const pk_v tt = PK_MUL(T, inv_det);
            const pk_v tcur = PK_LOAD(P->t + base);
            const pk_m nearer = PK_MOR(PK_CMP_LT(tt, tcur),
                                       PK_MAND(PK_CMP_EQ(tt, tcur),
                                               PK_IDGT(PK_LOADI(P->prim + base), b->prim[i])));
            const pk_m ok = PK_MAND(PK_MAND(PK_CMP_NEQ(det, zero), PK_CMP_GE(tt, tmin)),
                                    any ? PK_CMP_LT(tt, tcur) : nearer);
            const uint32_t acc = PK_BITS(ok) & in;
            if (any) {
                m &= ~acc;
                P->done[g] |= acc;
            } else if (acc) {
                const pk_m am = PK_MASK(acc);
                PK_STORE(P->t + base, PK_BLEND(am, tcur, tt));
                PK_STORE(P->u + base, PK_BLEND(am, PK_LOAD(P->u + base), PK_MUL(V, inv_det)));
                PK_STORE(P->v + base, PK_BLEND(am, PK_LOAD(P->v + base), PK_MUL(W, inv_det)));
                PK_STOREI(P->prim + base, PK_BLENDI(am, PK_LOADI(P->prim + base), b->prim[i]));
            }
        }
        /* zero edge functions: tt_intersect_triangle's double-precision
         * recomputation, lane by lane (rare) */
        for (uint32_t z = zl; z; z &= z - 1) {
            const uint32_t l = base + (uint32_t)__builtin_ctz(z);
            const float va[3] = {b->v[0][i], b->v[1][i], b->v[2][i]};
            const float vb[3] = {b->v[3][i], b->v[4][i], b->v[5][i]};
            const float vc[3] = {b->v[6][i], b->v[7][i], b->v[8][i]};
            float th, uh, vh;
            const tt_hit cur = {P->t[l], P->u[l], P->v[l], P->prim[l]};
            if (tt_intersect_triangle(pk_wray(P, l), va, vb, vc, any ? cur.t : tt_tri_tie_limit(&cur),
                                      &th, &uh, &vh) &&
                (any || tt_tri_better(th, b->prim[i], &cur))) {
                if (any) {
                    P->done[g] |= 1u << (l - base);
                    m &= ~(1u << (l - base));
                } else {
                    P->t[l] = th;
                    P->u[l] = uh;
                    P->v[l] = vh;
                    P->prim[l] = b->prim[i];
                }
            }
        }
    }
}

/* The packet's constants of a walk, in locals: the rows' offsets of each
 * axis's near and far planes, and the interval test's broadcast bounds
 * (read through P at every node they were reloaded and re-selected: P's
 * uint32_t fields may alias the walk's masks, 174 instructions a node). */
typedef struct TT_VARIANT(RTC_FN(pk_consts)) {
    uint32_t nr[3], fr[3];
    pk_v on[3], of[3], rlo[3], rhi[3], tn, tf, pad;
} TT_VARIANT(RTC_FN(pk_consts));

TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_consts))(const pk_rays *P, uint32_t S,
                                                    TT_VARIANT(RTC_FN(pk_consts)) *A)
{
    for (int k = 0; k < 3; k++) {
        const int neg = P->nrow[k] != (uint32_t)k;
        A->nr[k] = P->nrow[k] * S;
        A->fr[k] = P->frow[k] * S;
        A->on[k] = PK_SET1(neg ? P->omin[k] : P->omax[k]);
        A->of[k] = PK_SET1(neg ? P->omax[k] : P->omin[k]);
        A->rlo[k] = PK_SET1(P->rmin[k]);
        A->rhi[k] = PK_SET1(P->rmax[k]);
    }
    A->tn = PK_SET1(P->tmin_min);
    A->tf = PK_SET1(P->tcut_max);
    A->pad = PK_SET1(P->pad_max);
}

/* The interval test of all S children of node record rec against the
 * packet's bounds: bit i clear where no ray of the packet can hit child i. */
TT_RT_INLINE uint32_t TT_VARIANT(RTC_FN(rtc_pk_interval))(const TT_VARIANT(RTC_FN(pk_consts)) *A,
                                                         const float *rec, uint32_t S,
                                                         float *tn_out)
{
    uint32_t keep = 0;
    const float c1 = 1.0f / 4194304.0f;
    for (uint32_t i = 0; i < S; i += PK_L) {
        pk_v tn = A->tn, tf = A->tf;
        for (int k = 0; k < 3; k++) {
            const pk_v dn = PK_SUB(PK_LOADU(tt_rtc_boxes(rec) + A->nr[k] + i), A->on[k]);
            const pk_v df = PK_SUB(PK_LOADU(tt_rtc_boxes(rec) + A->fr[k] + i), A->of[k]);
            tn = PK_MAX(PK_MIN(PK_MUL(dn, A->rlo[k]), PK_MUL(dn, A->rhi[k])), tn);
            tf = PK_MIN(PK_MAX(PK_MUL(df, A->rlo[k]), PK_MUL(df, A->rhi[k])), tf);
        }
        /* each ray's far bound is padded too (pk_rays.pad) */
        tf = PK_ADD(PK_ADD(tf, PK_MUL(PK_ABS(tf), PK_SET1(c1))), A->pad);
        PK_STOREU(tn_out + i, tn);
        keep |= (PK_BITS(PK_CMP_GT(tn, tf)) ^ ((1u << PK_L) - 1u)) << i;
    }
    return keep;
}

/* The packet's walk: near to far, like the single-ray stack traversal. */
TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_walk))(const tt_rtc *TT_RESTRICT t, const uint32_t S,
                                                  const int any, pk_rays *P,
                                                  tt_packet_stats *stats)
{
    pk_entry stack[PK_STACK]; /* as the single-ray stack: S - 1 a level */
    uint32_t sp = 0;
    pk_entry cur;
    cur.node = 0;
    cur.level = t->height;
    cur.g0 = 0;
    cur.g1 = P->groups - 1;
    for (uint32_t g = 0; g < P->groups; g++) cur.m[g] = P->valid[g];
    for (uint32_t g = P->groups; g < PK_G; g++) cur.m[g] = 0;
    const float c1 = 1.0f / 4194304.0f, c2 = 1.0f / 65536.0f;
    const pk_v inf = PK_SET1(TT_INF);
    TT_VARIANT(RTC_FN(pk_consts)) A;
    TT_VARIANT(RTC_FN(rtc_pk_consts))(P, S, &A);
    (void)stats;
    for (;;) {
        const float *rec = tt_rtc_node(t, cur.node);
        const float *box = tt_rtc_boxes(rec); /* SoA rows, stride S */
        const uint32_t *child = tt_rtc_child(t, rec);
        if (any) {
            /* rays answered since this entry was pushed drop out; with
             * none left the entry is skipped (the walk ends when the
             * packet has none: checked after the leaves, which answer) */
            uint32_t live = 0;
            for (uint32_t g = cur.g0; g <= cur.g1; g++) live |= cur.m[g] &= ~P->done[g];
            if (!live) goto pop;
        }
#if TT_STATS
        {
            const uint32_t count = tt_rtc_count(t, rec);
            uint64_t act = 0;
            for (uint32_t g = cur.g0; g <= cur.g1; g++) act += pk_popcount(cur.m[g]);
            TT_COUNT(stats, node_visits, 1);
            TT_COUNT(stats, active_lanes, act);
            TT_COUNT(stats, rays.nodes, act);
            TT_COUNT(stats, rays.interior, act);
            TT_COUNT(stats, rays.boxes, act * count);
        }
#endif
        uint32_t cand = tt_rtc_used(t, rec);
        /* the interval test's entry distance of each child, for the packet */
        float tpk[TT_RT_MAX_M];
        const int itest = P->ia && S % PK_L == 0;
        if (itest) cand &= TT_VARIANT(RTC_FN(rtc_pk_interval))(&A, rec, S, tpk);
        if (itest && cur.level >= 2 && !(cand & (cand - 1))) {
            /* one child left by the interval test: the active rays go to
             * it untested (as rtc_pk_walk_occ; a ray missing it is dropped
             * by its own tests below, the children's boxes lying inside) */
            if (!cand) goto pop;
            cur.node = child[__builtin_ctz(cand)];
            cur.level--;
            continue;
        }
        /* Occlusion asks any hit, not the nearest: a child's rays need only
         * the overlap test, and the children go near to far by the
         * packet's interval entry (as good an order, and free), not by a
         * per-ray entry reduced across lanes. A ray's t is its tmax for
         * the whole walk (answered rays leave the masks instead), so
         * "entry < t" folds into the far bound as tcut (rtc_pk_load):
         * every child the full test keeps, this one keeps. */
        const int lean = any && itest;
        /* the hit children, their rays and nearest entry */
        uint32_t nh = 0, ord[TT_RT_MAX_M];
        float ot[TT_RT_MAX_M];
        uint32_t cm[TT_RT_MAX_M][PK_G], cg0[TT_RT_MAX_M], cg1[TT_RT_MAX_M];
        while (cand) {
            const uint32_t c = (uint32_t)__builtin_ctz(cand);
            cand &= cand - 1;
            const pk_cbox cb = pk_child_box(box, A.nr, A.fr, c);
            pk_v vmin = inf;
            uint32_t g0 = PK_G, g1 = 0;
            uint32_t *mk = cm[nh];
            for (uint32_t g = cur.g0; g <= cur.g1; g++) {
                const uint32_t m = cur.m[g];
                mk[g] = 0;
                if (!m) continue;
                const uint32_t o = g * PK_L;
                pk_v tf3[3];
                const pk_v tn = pk_child_slabs(&cb, P, o, tf3);
                const pk_v tfx = tf3[0], tfy = tf3[1], tfz = tf3[2];
                const pk_v pad = PK_LOAD(P->pad + o);
                if (lean) {
                    const pk_v tc = PK_MIN(tfz, PK_MIN(tfy, PK_MIN(tfx, PK_LOAD(P->tcut + o))));
                    const pk_v tfc = PK_ADD(PK_ADD(tc, PK_MUL(PK_ABS(tc), PK_SET1(c1))), pad);
                    const uint32_t h = PK_BITS(PK_CMP_LE(tn, tfc)) & m;
                    if (!h) continue;
                    mk[g] = h;
                    if (g < g0) g0 = g;
                    g1 = g;
                    continue;
                }
                const pk_v tf0 = PK_MIN(tfz, PK_MIN(tfy, PK_MIN(tfx, inf)));
                const pk_v tf = PK_ADD(PK_ADD(tf0, PK_MUL(PK_ABS(tf0), PK_SET1(c1))), pad);
                const pk_v entry = PK_SUB(PK_SUB(tn, PK_MUL(PK_ABS(tn), PK_SET1(c2))), pad);
                const pk_m hm = PK_MAND(PK_CMP_LE(tn, tf), PK_CMP_LT(entry, PK_LOAD(P->t + o)));
                const uint32_t h = PK_BITS(hm) & m;
                if (!h) continue;
                mk[g] = h;
                vmin = PK_MIN(PK_BLEND(PK_MASK(h), inf, entry), vmin);
                if (g < g0) g0 = g;
                g1 = g;
            }
            if (g0 == PK_G) continue;
            const float te = lean ? tpk[c] : PK_HMIN(vmin);
            cg0[nh] = g0;
            cg1[nh] = g1;
            uint32_t j = nh++;
            /* insertion by nearest entry; ord holds slots of cm */
            while (j > 0 && ot[j - 1] > te) {
                ot[j] = ot[j - 1];
                ord[j] = ord[j - 1];
                j--;
            }
            ot[j] = te;
            ord[j] = nh - 1;
            /* remember which child slot nh - 1 is */
            cg0[nh - 1] |= c << 16;
        }
        if (nh) {
            if (cur.level == 1) {
                /* Leaves share blocks (rtc_layout.h): each block of this
                 * node is tested once, for every ray of every hit leaf on
                 * it, in the order the nearest leaves first reach it. */
                const uint32_t base = tt_rtc_leaf_block(child[0]);
                uint32_t blist[64], nb_list = 0; /* offsets < 64, as in the single-ray kernel */
                uint32_t bm[64][PK_G];
                uint32_t bg0[64], bg1[64], btm[64];
                uint64_t seen = 0;
                for (uint32_t j = 0; j < nh; j++) {
                    const uint32_t s = ord[j];
                    const uint32_t c = cg0[s] >> 16, g0 = cg0[s] & 0xffffu, g1 = cg1[s];
                    const uint32_t ref = child[c];
                    uint32_t nb;
                    (void)tt_rtc_leaf_blocks(t, ref, &nb);
                    const uint32_t off = tt_rtc_leaf_block(ref) - base;
                    /* the leaf's triangle lanes from its first block on */
                    const uint32_t lanes = ((1u << tt_rtc_leaf_count(ref)) - 1u)
                                           << tt_rtc_leaf_lane(ref);
#if TT_STATS
                    {
                        uint64_t act = 0;
                        for (uint32_t g = g0; g <= g1; g++) act += pk_popcount(cm[s][g]);
                        TT_COUNT(stats, rays.nodes, act);
                        TT_COUNT(stats, rays.leaves, act);
                    }
#endif
                    for (uint32_t q = 0; q < nb; q++) {
                        const uint32_t k = off + q;
                        if (!(seen >> k & 1u)) {
                            seen |= (uint64_t)1 << k;
                            blist[nb_list++] = k;
                            for (uint32_t g = g0; g <= g1; g++) bm[k][g] = cm[s][g];
                            bg0[k] = g0;
                            bg1[k] = g1;
                            btm[k] = lanes >> (q * TT_TRI_BLOCK_W) & 0xffu;
                            continue;
                        }
                        btm[k] |= lanes >> (q * TT_TRI_BLOCK_W) & 0xffu;
                        /* widen the block's group range, zeroing what it
                         * gains, then add this leaf's rays */
                        for (uint32_t g = g0; g < bg0[k]; g++) bm[k][g] = 0;
                        for (uint32_t g = bg1[k] + 1; g <= g1; g++) bm[k][g] = 0;
                        if (g0 < bg0[k]) bg0[k] = g0;
                        if (g1 > bg1[k]) bg1[k] = g1;
                        for (uint32_t g = g0; g <= g1; g++) bm[k][g] |= cm[s][g];
                    }
                }
                for (uint32_t j = 0; j < nb_list; j++) {
                    const uint32_t k = blist[j];
                    const tt_tri_block *b = t->block + base + k;
                    for (uint32_t g = bg0[k]; g <= bg1[k]; g++) {
                        uint32_t m = bm[k][g];
                        if (any) m &= ~P->done[g];
                        if (!m) continue;
                        TT_COUNT(stats, rays.triangles, (uint64_t)TT_TRI_BLOCK_W * pk_popcount(m));
                        TT_VARIANT(RTC_FN(rtc_pk_block))(P, any, g, m, b, btm[k]);
                    }
                }
                if (any) {
                    uint32_t left = 0;
                    for (uint32_t g = 0; g < P->groups; g++) left |= P->valid[g] & ~P->done[g];
                    if (!left) return;
                }
            } else {
                for (uint32_t j = nh - 1; j > 0; j--) {
                    const uint32_t s = ord[j];
                    pk_entry *e = &stack[sp++];
                    e->node = child[cg0[s] >> 16];
                    e->level = cur.level - 1;
                    e->g0 = cg0[s] & 0xffffu;
                    e->g1 = cg1[s];
                    for (uint32_t g = e->g0; g <= e->g1; g++) e->m[g] = cm[s][g];
                }
                const uint32_t s = ord[0];
                cur.node = child[cg0[s] >> 16];
                cur.level--;
                cur.g0 = cg0[s] & 0xffffu;
                cur.g1 = cg1[s];
                for (uint32_t g = cur.g0; g <= cur.g1; g++) cur.m[g] = cm[s][g];
                continue;
            }
        }
    pop:
        if (!sp) return;
        /* the entry's mask words in use only (a whole pk_entry is 144
         * bytes: a memcpy a pop) */
        {
            const pk_entry *e = &stack[--sp];
            cur.node = e->node;
            cur.level = e->level;
            cur.g0 = e->g0;
            cur.g1 = e->g1;
            for (uint32_t g = e->g0; g <= e->g1; g++) cur.m[g] = e->m[g];
        }
    }
}

/* Occlusion packets are at most 32 rays (PK_OCC_CHUNK): their active rays
 * fit one 32-bit mask, bit l for lane l (group g's lanes at g * PK_L), so
 * the walk's bookkeeping is word operations: a node's live rays, a
 * child's hit rays, a stack entry, a block's rays. The per-group arrays of
 * rtc_pk_walk (copied, cleared and scanned a group at a time, with their
 * first..last ranges) were as many instructions as the box tests. The
 * tests themselves are rtc_pk_walk's lean ones (interval test, overlap
 * against tcut, children by interval entry), so the same children are
 * entered with the same rays. Needs finite reciprocals and S a multiple of
 * PK_L (the interval test); rtc_pk_trace checks. */
TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_walk_occ))(const tt_rtc *TT_RESTRICT t,
                                                      const uint32_t S, const int wide,
                                                      pk_rays *P, tt_packet_stats *stats)
{
    pk_oentry stack[PK_STACK];
    uint32_t sp = 0;
    uint32_t node = 0, level = t->height, valid = 0;
    for (uint32_t g = 0; g < P->groups; g++) valid |= P->valid[g] << (g * PK_L);
    uint32_t m = valid, done = 0;
    TT_VARIANT(RTC_FN(pk_consts)) A;
    TT_VARIANT(RTC_FN(rtc_pk_consts))(P, S, &A);
    const pk_v c1 = PK_SET1(1.0f / 4194304.0f);
    (void)stats;
    for (;;) {
        /* rays answered since this entry was pushed drop out */
        m &= ~done;
        if (!m) goto pop;
        {
            const float *rec = tt_rtc_node(t, node);
            const float *box = tt_rtc_boxes(rec); /* SoA rows, stride S */
            const uint32_t *child = tt_rtc_child(t, rec);
#if TT_STATS
            {
                const uint64_t act = pk_popcount(m);
                TT_COUNT(stats, node_visits, 1);
                TT_COUNT(stats, active_lanes, act);
                TT_COUNT(stats, rays.nodes, act);
                TT_COUNT(stats, rays.interior, act);
                TT_COUNT(stats, rays.boxes, act * tt_rtc_count(t, rec));
            }
#endif
            /* the groups with active rays, found once a node (the child
             * loop below scanned all PK_OG groups of every candidate) */
            uint32_t gm = 0;
            for (uint32_t g = 0; g < PK_OG; g++) gm |= (uint32_t)((m >> (g * PK_L) & PK_LANES) != 0) << g;
            float tpk[TT_RT_MAX_M];
            uint32_t cand =
                tt_rtc_used(t, rec) & TT_VARIANT(RTC_FN(rtc_pk_interval))(&A, rec, S, tpk);
            if (level >= 2 && !(cand & (cand - 1))) {
                /* one child left by the interval test (two thirds of a
                 * shadow packet's interior visits, conference and sibenik;
                 * the rays' own tests then keep all active rays 97-98% of
                 * the time): it takes the active rays untested. A ray that
                 * misses it is dropped by its own tests below (the
                 * children's boxes lie inside), and at worst is tested
                 * against more leaves, whose triangle tests answer it. */
                if (!cand) goto pop;
                node = child[__builtin_ctz(cand)];
                level--;
                continue;
            }
            /* the hit children near to far by interval entry, their rays */
            uint32_t nh = 0, hc[TT_RT_MAX_M], hm[TT_RT_MAX_M];
            float ht[TT_RT_MAX_M];
            while (cand) {
                const uint32_t c = (uint32_t)__builtin_ctz(cand);
                cand &= cand - 1;
                const pk_cbox cb = pk_child_box(box, A.nr, A.fr, c);
                uint32_t h = 0;
                for (uint32_t gb = gm; gb; gb &= gb - 1) {
                    const uint32_t o = (uint32_t)__builtin_ctz(gb) * PK_L;
                    const uint32_t mg = m >> o & PK_LANES;
                    if (wide) {
                        /* inactive lanes go with h &= m below */
                        h |= pk_child_occ_wide(&cb, P, o) << o;
                        continue;
                    }
                    pk_v tf3[3];
                    const pk_v tn = pk_child_slabs(&cb, P, o, tf3);
                    const pk_v tc =
                        PK_MIN(tf3[2], PK_MIN(tf3[1], PK_MIN(tf3[0], PK_LOAD(P->tcut + o))));
                    const pk_v tfc = PK_ADD(PK_ADD(tc, PK_MUL(PK_ABS(tc), c1)), PK_LOAD(P->pad + o));
                    h |= (PK_BITS(PK_CMP_LE(tn, tfc)) & mg) << o;
                }
                h &= m;
                if (!h) continue;
                const float te = tpk[c];
                uint32_t j = nh++;
                while (j > 0 && ht[j - 1] > te) {
                    ht[j] = ht[j - 1];
                    hc[j] = hc[j - 1];
                    hm[j] = hm[j - 1];
                    j--;
                }
                ht[j] = te;
                hc[j] = c;
                hm[j] = h;
            }
            if (!nh) goto pop;
            if (level == 1) {
                /* each block of this node's hit leaves once, for all their
                 * rays, with the triangles of those leaves (as rtc_pk_walk) */
                const uint32_t base = tt_rtc_leaf_block(child[0]);
                uint32_t blist[64], nbl = 0, bmk[64], btm[64];
                uint64_t seen = 0;
                for (uint32_t j = 0; j < nh; j++) {
                    const uint32_t ref = child[hc[j]];
                    uint32_t nb;
                    (void)tt_rtc_leaf_blocks(t, ref, &nb);
                    const uint32_t off = tt_rtc_leaf_block(ref) - base;
                    const uint32_t lanes = ((1u << tt_rtc_leaf_count(ref)) - 1u)
                                           << tt_rtc_leaf_lane(ref);
                    TT_COUNT(stats, rays.nodes, pk_popcount(hm[j]));
                    TT_COUNT(stats, rays.leaves, pk_popcount(hm[j]));
                    for (uint32_t q = 0; q < nb; q++) {
                        const uint32_t k = off + q;
                        const uint32_t tl = lanes >> (q * TT_TRI_BLOCK_W) & 0xffu;
                        if (!(seen >> k & 1u)) {
                            seen |= (uint64_t)1 << k;
                            blist[nbl++] = k;
                            bmk[k] = hm[j];
                            btm[k] = tl;
                        } else {
                            bmk[k] |= hm[j];
                            btm[k] |= tl;
                        }
                    }
                }
                for (uint32_t j = 0; j < nbl; j++) {
                    const uint32_t k = blist[j];
                    const tt_tri_block *b = t->block + base + k;
                    const uint32_t bm = bmk[k] & ~done;
                    for (uint32_t g = 0; g < PK_OG; g++) {
                        const uint32_t mg = bm >> (g * PK_L) & PK_LANES;
                        if (!mg) continue;
                        TT_COUNT(stats, rays.triangles, (uint64_t)TT_TRI_BLOCK_W * pk_popcount(mg));
                        TT_VARIANT(RTC_FN(rtc_pk_block))(P, 1, g, mg, b, btm[k]);
                        done |= P->done[g] << (g * PK_L);
                    }
                }
                if (!(valid & ~done)) return;
                goto pop;
            }
            for (uint32_t j = nh - 1; j > 0; j--) {
                pk_oentry *e = &stack[sp++];
                e->node = child[hc[j]];
                e->level = level - 1;
                e->m = hm[j];
            }
            node = child[hc[0]];
            level--;
            m = hm[0];
            continue;
        }
    pop:
        if (!sp) return;
        sp--;
        node = stack[sp].node;
        level = stack[sp].level;
        m = stack[sp].m;
    }
}

/* Loads the rows idx[0..n) of R (one octant) into P and prepares them a
 * group at a time: reciprocals, the watertight test's shear (tt_wray_init's
 * fields from its IEEE operations: 1 / d, d[kx] / d[kz], so bit for bit)
 * and the packet's bounds. The batch used to build a tt_wray per ray for
 * this (scalar selects, AoS stores) and this load copied them back into
 * rows: about a third of a shadow ray's instructions. */
TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_load))(pk_rays *P, const tt_packet_rays *R,
                                                  const uint32_t *idx, uint32_t n)
{
    P->n = n;
    P->groups = (n + PK_L - 1) / PK_L;
    P->R = R;
    const uint32_t lanes = P->groups * PK_L;
    const uint32_t i0 = idx[0];
    for (uint32_t k = 0; k < 3; k++) {
        const int neg = pk_sign(R->dir[k][i0]) != 0;
        P->nrow[k] = neg ? k + 3 : k;
        P->frow[k] = neg ? k : k + 3;
    }
    _Alignas(64) float d[3][PK_N];
    if (idx[n - 1] - i0 == n - 1) {
        /* consecutive rows (a tile of one octant, a run of shadow rays):
         * straight copies */
        const float *const from[8] = {R->org[0] + i0, R->org[1] + i0, R->org[2] + i0,
                                      R->dir[0] + i0, R->dir[1] + i0, R->dir[2] + i0,
                                      R->tmin + i0,   R->tmax + i0};
        float *const to[8] = {P->ox, P->oy, P->oz, d[0], d[1], d[2], P->tmin, P->t};
        /* whole vectors while they stay inside R's rows (lanes past n are
         * overwritten below); memcpy was a libc call a row */
        uint32_t i = 0;
        for (; i < n && i0 + i + PK_L <= PK_N; i += PK_L)
            for (int r = 0; r < 8; r++) PK_STORE(to[r] + i, PK_LOADU(from[r] + i));
        for (; i < n; i++)
            for (int r = 0; r < 8; r++) to[r][i] = from[r][i];
        for (i = 0; i < n; i++) P->src[i] = (uint16_t)(i0 + i);
    } else {
        for (uint32_t i = 0; i < n; i++) {
            const uint32_t j = idx[i];
            P->src[i] = (uint16_t)j;
            P->ox[i] = R->org[0][j];
            P->oy[i] = R->org[1][j];
            P->oz[i] = R->org[2][j];
            d[0][i] = R->dir[0][j];
            d[1][i] = R->dir[1][j];
            d[2][i] = R->dir[2][j];
            P->tmin[i] = R->tmin[j];
            P->t[i] = R->tmax[j];
        }
    }
    /* lanes past n repeat the first ray (inside every bound, never active) */
    for (uint32_t i = n; i < lanes; i++) {
        P->src[i] = (uint16_t)i0;
        P->ox[i] = P->ox[0];
        P->oy[i] = P->oy[0];
        P->oz[i] = P->oz[0];
        d[0][i] = d[0][0];
        d[1][i] = d[1][0];
        d[2][i] = d[2][0];
        P->tmin[i] = P->tmin[0];
        P->t[i] = P->t[0];
    }
    memset(P->prim, 0xff, lanes * sizeof(uint32_t)); /* TT_INVALID_ID */
    const pk_v zero = PK_SET1(0.0f), one = PK_SET1(1.0f);
    const pk_v inf = PK_SET1(TT_INF), ninf = PK_SET1(-TT_INF);
    pk_v mag = zero, tlo = inf, thi = zero, pmax = zero;
    pk_v olo[3] = {inf, inf, inf}, ohi[3] = {ninf, ninf, ninf};
    pk_v rlo[3] = {inf, inf, inf}, rhi[3] = {ninf, ninf, ninf};
    float *const orow[3] = {P->ox, P->oy, P->oz}, *const rrow[3] = {P->rx, P->ry, P->rz};
    for (uint32_t g = 0; g < P->groups; g++) {
        const uint32_t o = g * PK_L;
        const pk_v x = PK_LOAD(d[0] + o), y = PK_LOAD(d[1] + o), z = PK_LOAD(d[2] + o);
        const pk_v dv[3] = {x, y, z};
        pk_v pad = zero;
        for (uint32_t k = 0; k < 3; k++) {
            const pk_v r = PK_DIV(one, dv[k]), ov = PK_LOAD(orow[k] + o);
            PK_STORE(rrow[k] + o, r);
            /* |org rcp| where finite (a zero direction component: that
             * axis does not cull, as in the FMA kernels) */
            const pk_v axr = PK_ABS(PK_MUL(ov, r));
            pad = PK_MAX(PK_BLEND(PK_CMP_LT(axr, inf), zero, axr), pad);
            olo[k] = PK_MIN(ov, olo[k]);
            ohi[k] = PK_MAX(ov, ohi[k]);
            rlo[k] = PK_MIN(r, rlo[k]);
            rhi[k] = PK_MAX(r, rhi[k]);
            mag = PK_MAX(PK_ABS(r), mag);
        }
        pad = PK_MUL(pad, PK_SET1(1.0f / 1048576.0f));
        PK_STORE(P->pad + o, pad);
        pmax = PK_MAX(pad, pmax);
        const pk_v tmax = PK_LOAD(P->t + o);
        /* "tn - |tn| 2^-16 - pad < t" (the full test's entry) implies
         * tn <= tcut, for t >= 0: tn < (t + pad) (1 + 2^-16 + ...), and
         * 2^-15 and pad (1 + 2^-14) leave room for the roundings */
        const pk_v tcut = PK_ADD(PK_ADD(tmax, PK_MUL(PK_ABS(tmax), PK_SET1(1.0f / 32768.0f))),
                                 PK_MUL(pad, PK_SET1(1.0f + 1.0f / 16384.0f)));
        PK_STORE(P->tcut + o, tcut);
        tlo = PK_MIN(PK_LOAD(P->tmin + o), tlo);
        thi = PK_MAX(tcut, thi);
        PK_STORE(P->u + o, zero);
        PK_STORE(P->v + o, zero);
        /* tt_wray_init's shear, lane by lane with selects: kz the dominant
         * axis (x wins ties, then y), kx, ky the next ones cyclically,
         * swapped where d[kz] < 0 */
        const pk_v ax = PK_ABS(x), ay = PK_ABS(y), az = PK_ABS(z);
        const pk_m m0 = PK_MAND(PK_CMP_GE(ax, ay), PK_CMP_GE(ax, az));
        const pk_m m1 = PK_MANDNOT(m0, PK_CMP_GE(ay, az));
        const pk_v dkz = PK_BLEND(m0, PK_BLEND(m1, z, y), x);
        const pk_v dkx = PK_BLEND(m0, PK_BLEND(m1, x, z), y);
        const pk_v dky = PK_BLEND(m0, PK_BLEND(m1, y, x), z);
        const pk_m neg = PK_CMP_LT(dkz, zero);
        PK_STORE(P->sx + o, PK_DIV(PK_BLEND(neg, dkx, dky), dkz));
        PK_STORE(P->sy + o, PK_DIV(PK_BLEND(neg, dky, dkx), dkz));
        PK_STORE(P->sz + o, PK_DIV(one, dkz));
        const uint32_t left = n - o;
        const uint32_t valid = left >= PK_L ? (1u << PK_L) - 1u : (1u << left) - 1u;
        P->valid[g] = valid;
        P->done[g] = 0;
        P->made[g] = 0;
        /* the group's shared permutation, or -1 */
        const uint32_t b0 = PK_BITS(m0) & valid, b1 = PK_BITS(m1) & valid,
                       bn = PK_BITS(neg) & valid;
        if ((b0 && b0 != valid) || (b1 && b1 != valid) || (bn && bn != valid)) {
            P->perm[g] = -1;
        } else {
            const int kz = b0 ? 0 : b1 ? 1 : 2;
            const int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
            P->perm[g] = (int8_t)(bn ? ky * 9 + kx * 3 + kz : kx * 9 + ky * 3 + kz);
            P->kxyz[g][0] = (uint8_t)(bn ? ky : kx);
            P->kxyz[g][1] = (uint8_t)(bn ? kx : ky);
            P->kxyz[g][2] = (uint8_t)kz;
        }
    }
    for (uint32_t k = 0; k < 3; k++) {
        P->omin[k] = PK_HMIN(olo[k]);
        P->omax[k] = PK_HMAX(ohi[k]);
        P->rmin[k] = PK_HMIN(rlo[k]);
        P->rmax[k] = PK_HMAX(rhi[k]);
    }
    P->tmin_min = PK_HMIN(tlo);
    /* a ray's own test keeps a box only where tn - |tn| 2^-16 < t <= tmax
     * (or, occlusion, tn <= tcut): so tn <= tcut of some ray, and the
     * packet's far bound starts at the largest tcut, not infinity (shadow
     * rays: boxes past the light go) */
    P->tcut_max = PK_HMAX(thi);
    P->pad_max = PK_HMAX(pmax);
    /* finite reciprocals (the batch's rays have no NaN) */
    P->ia = PK_HMAX(mag) < TT_INF;
}

/* One packet: the rays ix[0..c) of one octant loaded, walked, answered. */
TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_trace))(const tt_rtc *t, const tt_packet_rays *rays,
                                                   const uint32_t *ix, uint32_t c, int any,
                                                   tt_hit *hits, uint8_t *occ, pk_rays *P,
                                                   tt_packet_stats *stats)
{
    TT_COUNT(stats, packets, 1);
    TT_VARIANT(RTC_FN(rtc_pk_load))(P, rays, ix, c);
    if (any && P->ia && t->S % PK_L == 0 && c <= 32u) {
        /* shadow rays (tmin >= 0): the test with widened rows */
        const int wide = P->tmin_min >= 0.0f;
        if (wide) pk_widen(P);
        switch (t->S) {
        case 16:
            if (wide) TT_VARIANT(RTC_FN(rtc_pk_walk_occ))(t, 16, 1, P, stats);
            else TT_VARIANT(RTC_FN(rtc_pk_walk_occ))(t, 16, 0, P, stats);
            break;
        default: TT_VARIANT(RTC_FN(rtc_pk_walk_occ))(t, t->S, wide, P, stats); break;
        }
    } else switch (t->S) {
    case 16:
        if (any) TT_VARIANT(RTC_FN(rtc_pk_walk))(t, 16, 1, P, stats);
        else TT_VARIANT(RTC_FN(rtc_pk_walk))(t, 16, 0, P, stats);
        break;
    case 8:
        if (any) TT_VARIANT(RTC_FN(rtc_pk_walk))(t, 8, 1, P, stats);
        else TT_VARIANT(RTC_FN(rtc_pk_walk))(t, 8, 0, P, stats);
        break;
    default:
        if (any) TT_VARIANT(RTC_FN(rtc_pk_walk))(t, t->S, 1, P, stats);
        else TT_VARIANT(RTC_FN(rtc_pk_walk))(t, t->S, 0, P, stats);
        break;
    }
    if (any && ix[c - 1] - ix[0] == c - 1) {
        /* consecutive rows: the answer bits 4 at a time into bytes (each
         * bit i of a nibble lands alone on bit 8 i of the product) */
        uint8_t *out = occ + ix[0];
        uint32_t j = 0;
        for (; j + 4 <= c; j += 4) {
            const uint32_t q = P->done[j / PK_L] >> (j % PK_L) & 15u;
            const uint32_t bytes = (q * 0x00204081u) & 0x01010101u;
            out[j] = (uint8_t)bytes;
            out[j + 1] = (uint8_t)(bytes >> 8);
            out[j + 2] = (uint8_t)(bytes >> 16);
            out[j + 3] = (uint8_t)(bytes >> 24);
        }
        for (; j < c; j++) out[j] = (uint8_t)(P->done[j / PK_L] >> (j % PK_L) & 1u);
        return;
    }
    for (uint32_t j = 0; j < c; j++) {
        const uint32_t i = ix[j];
        if (any) {
            occ[i] = (uint8_t)(P->done[j / PK_L] >> (j % PK_L) & 1u);
        } else {
            tt_hit *h = &hits[i];
            h->prim = P->prim[j];
            h->t = P->prim[j] == TT_INVALID_ID ? TT_INF : P->t[j];
            h->u = P->u[j];
            h->v = P->v[j];
        }
    }
}

/* Ray i of R by the unit's single-ray traversal (an octant of too few rays,
 * a ray the packet cannot match: see tt_rtc_packet). */
TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_single))(const tt_rtc *t, const tt_packet_rays *R,
                                                    uint32_t i, int any, tt_hit *hits,
                                                    uint8_t *occ, tt_packet_stats *stats)
{
    tt_hit h;
    tt_wray w;
    tt_packet_ray_wray(R, i, &w);
#if TT_STATS
    const uint64_t before = stats->rays.rays;
    const int r = RTC_SINGLE_STATS(t, &w, any, &h, &stats->rays);
    stats->rays.rays = before; /* counted once by the caller */
    TT_COUNT(stats, fallback_rays, 1);
#else
    (void)stats;
    const int r = RTC_SINGLE(t, &w, any, &h, NULL);
#endif
    if (any) occ[i] = (uint8_t)(r != 0);
    else hits[i] = h;
}

/* Ray i of R to its octant's rows (by sign bit, -0 negative), or ray by
 * ray when a component is huge (see tt_rtc_packet). */
TT_RT_INLINE void TT_VARIANT(RTC_FN(rtc_pk_octant_one))(const tt_rtc *t, const tt_packet_rays *R,
                                                        uint32_t i, int any, tt_hit *hits,
                                                        uint8_t *occ, tt_packet_stats *stats,
                                                        uint32_t (*idx)[PK_N], uint32_t *cnt)
{
    const float dx = R->dir[0][i], dy = R->dir[1][i], dz = R->dir[2][i];
    if ((fabsf(dx) >= 0x1p126f) | (fabsf(dy) >= 0x1p126f) | (fabsf(dz) >= 0x1p126f)) {
        TT_VARIANT(RTC_FN(rtc_pk_single))(t, R, i, any, hits, occ, stats);
        return;
    }
    const uint32_t o = pk_sign(dx) | pk_sign(dy) << 1 | pk_sign(dz) << 2;
    idx[o][cnt[o]++] = i;
}

/* The entry point: the rows of R (R->n <= TT_PACKET_MAX) split by octant,
 * each octant's rays a packet (or ray by ray when few); closest hits into
 * hits (any = 0) or occlusion bytes into occ (any = 1), by row.
 * A ray with a direction component of magnitude 2^126 or more goes ray by
 * ray: its reciprocal and shear are subnormal, its triangle tests' t
 * underflow (to 0 for many triangles at once) and its box entries lose
 * their relative margin, so the box test stops being conservative and the
 * answer depends on the order in which its boxes are visited, which the
 * packet (near to far for the packet) cannot share with the single ray
 * (near to far for the ray). Found with components of +-3e38 on bunny. */
void TT_VARIANT(RTC_FN(tt_rtc_packet))(const tt_rtc *t, const tt_packet_rays *R, int any,
                                       tt_hit *hits, uint8_t *occ, tt_packet_stats *stats)
{
    const uint32_t n = R->n;
    uint32_t idx[8][PK_N], cnt[8] = {0};
    TT_COUNT(stats, rays.rays, n);
    /* a vector of rays at a time: one octant, no zero component, nothing
     * huge (the usual case) appends its rows whole */
    const pk_v zero = PK_SET1(0.0f), huge = PK_SET1(0x1p126f);
    uint32_t i = 0;
    for (;;) {
        for (; i + PK_L <= n; i += PK_L) {
            const pk_v dx = PK_LOAD(R->dir[0] + i), dy = PK_LOAD(R->dir[1] + i),
                       dz = PK_LOAD(R->dir[2] + i);
            const uint32_t nx = PK_BITS(PK_CMP_LT(dx, zero)), ny = PK_BITS(PK_CMP_LT(dy, zero)),
                           nz = PK_BITS(PK_CMP_LT(dz, zero));
            const uint32_t odd =
                PK_BITS(PK_MOR(PK_MOR(PK_CMP_EQ(dx, zero), PK_CMP_EQ(dy, zero)),
                               PK_MOR(PK_MOR(PK_CMP_EQ(dz, zero), PK_CMP_GE(PK_ABS(dx), huge)),
                                      PK_MOR(PK_CMP_GE(PK_ABS(dy), huge),
                                             PK_CMP_GE(PK_ABS(dz), huge)))));
            if (odd || ((nx + 1u) & PK_LANES) > 1u || ((ny + 1u) & PK_LANES) > 1u ||
                ((nz + 1u) & PK_LANES) > 1u)
                break;
            const uint32_t o = (nx & 1u) | (ny & 1u) << 1 | (nz & 1u) << 2;
            for (uint32_t l = 0; l < PK_L; l++) idx[o][cnt[o] + l] = i + l;
            cnt[o] += PK_L;
        }
        if (i + PK_L > n) break;
        /* a vector of mixed octants (a shadow item around a light inside
         * the scene) goes ray by ray, then whole vectors again: the rest of
         * the item went ray by ray */
        for (const uint32_t e = i + PK_L; i < e; i++)
            TT_VARIANT(RTC_FN(rtc_pk_octant_one))(t, R, i, any, hits, occ, stats, idx, cnt);
    }
    for (; i < n; i++)
        TT_VARIANT(RTC_FN(rtc_pk_octant_one))(t, R, i, any, hits, occ, stats, idx, cnt);
    _Alignas(64) pk_rays P;
    for (uint32_t o = 0; o < 8; o++) {
        const uint32_t c = cnt[o];
        if (!c) continue;
        if (c < PK_MIN_RAYS) {
            for (uint32_t j = 0; j < c; j++)
                TT_VARIANT(RTC_FN(rtc_pk_single))(t, R, idx[o][j], any, hits, occ, stats);
            continue;
        }
        /* an octant of more than PK_CHUNK rays goes in equal runs */
        const uint32_t runs = (cnt[o] + PK_CHUNK - 1) / PK_CHUNK;
        const uint32_t per = (cnt[o] + runs - 1) / runs;
        for (uint32_t c0 = 0; c0 < cnt[o]; c0 += per) {
            const uint32_t k = cnt[o] - c0 < per ? cnt[o] - c0 : per;
            TT_VARIANT(RTC_FN(rtc_pk_trace))(t, R, idx[o] + c0, k, any, hits, occ, &P, stats);
        }
    }
}
