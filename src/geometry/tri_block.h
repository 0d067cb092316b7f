/* Triangles in blocks of TT_TRI_BLOCK_W for SIMD intersection, shared by the
 * engines' leaves (R-tree compact layout, kd-tree leaves): the block's
 * vertices in structure-of-arrays form, one lane a triangle, so a kernel
 * loads each coordinate of all lanes with one vector load.
 *
 * The test is the project's watertight one (geometry/triangle.h) evaluated
 * lane by lane with the same operations in the same order, so every ISA path
 * returns bit for bit the hits tt_intersect_triangle returns:
 *  - the shear needs the ray, so nothing ray-dependent can be precomputed;
 *    a block holds plain vertices (36 bytes a triangle) and its ids;
 *  - a lane with a zero edge function is re-tested by tt_intersect_triangle
 *    itself (its double-precision recomputation), as rarely happens;
 *  - zero-area triangles never hit (tt_intersect_triangle refuses them after
 *    the t test); tt_tri_block_pack gives them NaN vertices instead, so no
 *    kernel needs that test, and unused lanes are NaN too (prim =
 *    TT_INVALID_ID): a NaN lane fails the t test in every kernel;
 *  - ties at equal t go to the smaller triangle id (tt_tri_better), so the
 *    closest hit does not depend on the order blocks are visited in: a
 *    packet traversal (rtree/trace/rtc_packet.h) visits them in another
 *    order than a single ray, and must give the same answer bit for bit;
 *    bruteforce (ids in order, strict <) gives exactly this answer too.
 *
 * Per-ISA kernels (tri_block_sse42.h, _avx2.h, _avx512.h) are static inline
 * functions with the signatures of the scalar ones below, for inclusion in a
 * structure's own *_sse42.c / *_avx2.c / *_avx512.c units. */
#ifndef TT_GEOMETRY_TRI_BLOCK_H
#define TT_GEOMETRY_TRI_BLOCK_H

#include <stdint.h>
#include <string.h>

#include "geometry/hd.h"
#include "geometry/ray.h"
#include "geometry/triangle.h"
#include "treetrace/treetrace.h" /* tt_hit, TT_INVALID_ID */

#define TT_TRI_BLOCK_W 8

/* The per-ISA block kernels are always inlined into the traversals that
 * include them: left to itself the compiler made them calls, and each call
 * from a node loop spilled and reloaded a dozen vector registers and
 * cleared the upper halves (vzeroupper) around a kernel of a few dozen
 * instructions. */
#define TT_TRI_KERNEL static inline __attribute__((always_inline))

typedef struct tt_tri_block {
    float v[9][TT_TRI_BLOCK_W]; /* a.x a.y a.z b.x b.y b.z c.x c.y c.z, lanes */
    uint32_t prim[TT_TRI_BLOCK_W]; /* load-order id; TT_INVALID_ID: unused    */
} tt_tri_block; /* 320 bytes; arrays of blocks are allocated 64-byte aligned */

/* Blocks needed for n triangles. */
TT_HD uint32_t tt_tri_block_count(uint32_t n) { return (n + TT_TRI_BLOCK_W - 1) / TT_TRI_BLOCK_W; }

/* Fills tt_tri_block_count(n) blocks with triangles ids[0..n) of the scene's
 * flat array tri (9 floats a triangle): lane i of block j holds ids[8j + i].
 * Zero-area triangles and unused lanes get NaN vertices (see above). */
void tt_tri_block_pack(const float *tri, const uint32_t *ids, uint32_t n, tt_tri_block *out);

/* 1 when triangle (a, b, c) can never be hit by tt_intersect_triangle
 * (its unsheared normal is exactly zero in float). */
static inline int tt_tri_is_degenerate(const float *a, const float *b, const float *c)
{
    /* The very expression tt_intersect_triangle refuses a hit with;
     * inline for the R-tree update's lane writers (a call there clobbered
     * the deformation's leaf union kept in vector registers). Every unit
     * is compiled without contraction (-ffp-contract=off where FMA is
     * allowed), so every caller gets the same answer. */
    const float e1x = b[0] - a[0], e1y = b[1] - a[1], e1z = b[2] - a[2];
    const float e2x = c[0] - a[0], e2y = c[1] - a[1], e2z = c[2] - a[2];
    return e1y * e2z - e1z * e2y == 0.0f && e1z * e2x - e1x * e2z == 0.0f &&
           e1x * e2y - e1y * e2x == 0.0f;
}

/* The tie rule of every closest-hit block kernel: a candidate replaces the
 * hit so far when nearer, or at equal t when its id is smaller; with no hit
 * yet (prim TT_INVALID_ID) hit->t is the ray's tmax, an open bound. A
 * kernel tests its lanes on [tmin, tt_tri_tie_limit(hit)) (t <= hit->t when
 * there is a hit) and then keeps the candidates tt_tri_better accepts. */
TT_HD float tt_tri_tie_limit(const tt_hit *hit)
{
    if (hit->prim == TT_INVALID_ID) return hit->t;
#ifdef __CUDA_ARCH__
    return nextafterf(hit->t, INFINITY);
#else
    /* nextafterf(t, +inf) for a hit's t (finite, >= tmin >= 0) by its bits:
     * glibc's is a call through the PLT, and the AVX2 walk spilled six
     * vector registers around it at every block test after a first hit
     * (callgrind, conference: 1% of the kernel's instructions). The same
     * float for every t the call would get: NaN and +inf stay, +-0 give
     * the least denormal, a positive t the next bit pattern up, a negative
     * one the next down. */
    const float t = hit->t;
    if (!(t < TT_INF)) return t;
    if (t == 0.0f) return __FLT_DENORM_MIN__;
    uint32_t u;
    memcpy(&u, &t, sizeof u);
    u = t > 0.0f ? u + 1u : u - 1u;
    float n;
    memcpy(&n, &u, sizeof n);
    return n;
#endif
}
TT_HD int tt_tri_better(float t, uint32_t prim, const tt_hit *hit)
{
    return t < hit->t || (t == hit->t && prim < hit->prim);
}

/* Closest hit among `count` blocks on [r->tmin, hit->t): updates *hit (t,
 * u, v, prim) when a lane is nearer than hit->t (or as near, with a smaller
 * id); returns 1 if it did. */
TT_HD int tt_tri_blocks_intersect_scalar(const tt_wray *r, const tt_tri_block *b,
                                         uint32_t count, tt_hit *hit)
{
    int found = 0;
    for (uint32_t j = 0; j < count; j++)
        for (int i = 0; i < TT_TRI_BLOCK_W; i++) {
            const float a[3] = {b[j].v[0][i], b[j].v[1][i], b[j].v[2][i]};
            const float bb[3] = {b[j].v[3][i], b[j].v[4][i], b[j].v[5][i]};
            const float c[3] = {b[j].v[6][i], b[j].v[7][i], b[j].v[8][i]};
            float t, u, v;
            if (tt_intersect_triangle(r, a, bb, c, tt_tri_tie_limit(hit), &t, &u, &v) &&
                tt_tri_better(t, b[j].prim[i], hit)) {
                hit->t = t;
                hit->u = u;
                hit->v = v;
                hit->prim = b[j].prim[i];
                found = 1;
            }
        }
    return found;
}

/* Any hit among `count` blocks on [r->tmin, tmax): 1 or 0. */
TT_HD int tt_tri_blocks_occluded_scalar(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                        float tmax)
{
    for (uint32_t j = 0; j < count; j++)
        for (int i = 0; i < TT_TRI_BLOCK_W; i++) {
            const float a[3] = {b[j].v[0][i], b[j].v[1][i], b[j].v[2][i]};
            const float bb[3] = {b[j].v[3][i], b[j].v[4][i], b[j].v[5][i]};
            const float c[3] = {b[j].v[6][i], b[j].v[7][i], b[j].v[8][i]};
            float t, u, v;
            if (tt_intersect_triangle(r, a, bb, c, tmax, &t, &u, &v)) return 1;
        }
    return 0;
}

/* The kernels of one ISA, for tests and simple users; structures include the
 * per-ISA headers in their own *_<isa>.c units instead, so the kernel is
 * inlined into their traversal. Host code only. */
#ifndef __CUDACC__

typedef struct tt_tri_block_kernels {
    int (*intersect)(const tt_wray *r, const tt_tri_block *b, uint32_t count, tt_hit *hit);
    int (*occluded)(const tt_wray *r, const tt_tri_block *b, uint32_t count, float tmax);
} tt_tri_block_kernels;

/* The kernels of `isa` (the caller checks tt_isa_supported); the scalar
 * ones for TT_ISA_SCALAR, TT_ISA_AUTO, unknown values and in builds without
 * x86 kernels. */
tt_tri_block_kernels tt_tri_block_kernels_for(tt_isa isa);

#ifdef TT_HAVE_X86_KERNELS
/* Out-of-line copies of the per-ISA kernels (tri_block_<isa>.c). */
int tt_tri_blocks_intersect_sse42_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                     tt_hit *hit);
int tt_tri_blocks_occluded_sse42_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                    float tmax);
int tt_tri_blocks_intersect_avx2_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                    tt_hit *hit);
int tt_tri_blocks_occluded_avx2_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                   float tmax);
int tt_tri_blocks_intersect_avx512_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                      tt_hit *hit);
int tt_tri_blocks_occluded_avx512_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                     float tmax);
#endif
#endif

#endif
