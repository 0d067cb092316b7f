/* The triangle-block kernels for AVX-512 units: the AVX2 kernels
 * (tri_block_avx2.h, one 256-bit vector a block), compiled with the AVX-512
 * flags (EVEX encoding, 32 vector registers). Include only from a
 * *_avx512.c unit (see core/isa.h). Results are bit for bit those of
 * tt_tri_blocks_intersect_scalar / _occluded_scalar (geometry/tri_block.h).
 *
 * Why not wider: measured on this project's Xeon (random blocks of 8
 * triangles in L1, 4 blocks a call, min of 25 rounds), two blocks per
 * 512-bit vector took 1.13-1.15 ns a triangle and 256-bit operations with
 * mask registers (512-bit broadcast constants) 1.11-1.15 ns, against
 * 0.91-0.93 ns for this code (0.93-0.99 ns in the AVX2 unit); at 1 block a
 * call 1.68, 1.71 and 1.56-1.58 ns. The 512-bit division costs twice the
 * 256-bit one, merging two blocks' rows costs a shuffle per row, and
 * 512-bit instructions take a vector port away from the rest of the loop. */
#ifndef TT_GEOMETRY_TRI_BLOCK_AVX512_H
#define TT_GEOMETRY_TRI_BLOCK_AVX512_H

#include "geometry/tri_block_avx2.h"

TT_TRI_KERNEL int tt_tri_blocks_intersect_avx512(const tt_wray *r, const tt_tri_block *b,
                                                 uint32_t count, tt_hit *hit)
{
    return tt_tri_blocks_intersect_avx2(r, b, count, hit);
}

TT_TRI_KERNEL int tt_tri_blocks_occluded_avx512(const tt_wray *r, const tt_tri_block *b,
                                                uint32_t count, float tmax)
{
    return tt_tri_blocks_occluded_avx2(r, b, count, tmax);
}

#endif
