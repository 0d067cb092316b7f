/* Out-of-line avx2 triangle-block kernels for tt_tri_block_kernels_for
 * (structures inline tri_block_avx2.h in their own units instead). */
#include "geometry/tri_block_avx2.h"

int tt_tri_blocks_intersect_avx2_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                    tt_hit *hit)
{
    return tt_tri_blocks_intersect_avx2(r, b, count, hit);
}

int tt_tri_blocks_occluded_avx2_fn(const tt_wray *r, const tt_tri_block *b, uint32_t count,
                                   float tmax)
{
    return tt_tri_blocks_occluded_avx2(r, b, count, tmax);
}
