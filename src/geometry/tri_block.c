/* Packing triangles into SIMD blocks (see geometry/tri_block.h). */
#include "geometry/tri_block.h"

#include <math.h>

void tt_tri_block_pack(const float *tri, const uint32_t *ids, uint32_t n, tt_tri_block *out)
{
    const uint32_t blocks = tt_tri_block_count(n);
    for (uint32_t j = 0; j < blocks; j++) {
        tt_tri_block *b = &out[j];
        for (uint32_t i = 0; i < TT_TRI_BLOCK_W; i++) {
            const uint32_t k = j * TT_TRI_BLOCK_W + i;
            if (k < n) {
                const float *v = tri + 9 * (size_t)ids[k];
                const int dead = tt_tri_is_degenerate(v, v + 3, v + 6);
                for (int c = 0; c < 9; c++) b->v[c][i] = dead ? NAN : v[c];
                b->prim[i] = ids[k];
            } else {
                for (int c = 0; c < 9; c++) b->v[c][i] = NAN;
                b->prim[i] = TT_INVALID_ID;
            }
        }
    }
}

static int intersect_scalar(const tt_wray *r, const tt_tri_block *b, uint32_t count, tt_hit *hit)
{
    return tt_tri_blocks_intersect_scalar(r, b, count, hit);
}

static int occluded_scalar(const tt_wray *r, const tt_tri_block *b, uint32_t count, float tmax)
{
    return tt_tri_blocks_occluded_scalar(r, b, count, tmax);
}

tt_tri_block_kernels tt_tri_block_kernels_for(tt_isa isa)
{
    tt_tri_block_kernels k = {intersect_scalar, occluded_scalar};
#ifdef TT_HAVE_X86_KERNELS
    switch (isa) {
    case TT_ISA_SSE42:
        k.intersect = tt_tri_blocks_intersect_sse42_fn;
        k.occluded = tt_tri_blocks_occluded_sse42_fn;
        break;
    case TT_ISA_AVX2:
        k.intersect = tt_tri_blocks_intersect_avx2_fn;
        k.occluded = tt_tri_blocks_occluded_avx2_fn;
        break;
    case TT_ISA_AVX512:
        k.intersect = tt_tri_blocks_intersect_avx512_fn;
        k.occluded = tt_tri_blocks_occluded_avx512_fn;
        break;
    default: break;
    }
#else
    (void)isa;
#endif
    return k;
}
