/* Out-of-line avx512 triangle-block kernels for tt_tri_block_kernels_for
 * (structures inline tri_block_avx512.h in their own units instead). */
#include "geometry/tri_block_avx512.h"

int tt_tri_blocks_intersect_avx512_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                      tt_hit *hit)
{
    return tt_tri_blocks_intersect_avx512(r, b, count, hit);
}

int tt_tri_blocks_occluded_avx512_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                     float tmax)
{
    return tt_tri_blocks_occluded_avx512(r, b, count, tmax);
}
