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

/* The ray's broadcasts for the any-hit tests below, made once a ray instead
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

/* The 8-lane blocks (kd_blocks.h): kd_edges8, kd_block8_edges, kd_block8
 * (closest hit) and kd_block8_any (occlusion). */
#define KDW 8
#define KDW_BLOCK tt_tri_block
#define KDW_V __m256
#define KDW_OP(op) _mm256_##op
#define KDW_RAY(x) (x)
#include "accel/kdtree/trace/kd_leaf_block_w.h"

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
 * line walks: kd_edges4, kd_block4_edges, kd_block4 and kd_block4_any, the
 * same text in 128-bit vectors. */
#define KDW 4
#define KDW_BLOCK tt_kd_block4
#define KDW_V __m128
#define KDW_OP(op) _mm_##op
#define KDW_RAY(x) _mm256_castps256_ps128(x)
#include "accel/kdtree/trace/kd_leaf_block_w.h"

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
