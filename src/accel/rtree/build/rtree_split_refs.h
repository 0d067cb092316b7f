/* Early split clipping (in the spirit of Ernst & Greiner 2007) for the SAH
 * loader: before the build, a long thin triangle, whose box is mostly empty
 * space, is cut into pieces whose boxes are the boxes of its clipped parts;
 * every piece is a reference to the same triangle. The loader then builds
 * over the references, and references of one triangle that land in the
 * same leaf are merged again (rt_bulk_levels_merge_refs), so a leaf stores
 * a triangle once; a triangle may still sit in several leaves.
 *
 * Which pieces are cut: of the triangles whose box is not flat (an
 * axis-plane triangle's pieces would widen every subtree they land in),
 * greedily the piece whose cut saves the most box surface area (the SAH's measure of how often rays enter it), cut at the
 * midpoint of whichever of its three axes saves most, until the reference
 * budget is spent or no cut saves area. The order is fixed by (saving,
 * piece number), so the references do not depend on the thread count.
 *
 * Piece boxes are conservative: every point of the triangle lies in some
 * piece box of it. A cut plane is exact (both sides end on it); bounds that
 * come from clipped vertices are widened by a few ulps of the coordinates'
 * magnitude and clamped to the parent piece's box, so they never shrink
 * below the exact clipped part by rounding. */
#ifndef TT_ACCEL_RTREE_SPLIT_REFS_H
#define TT_ACCEL_RTREE_SPLIT_REFS_H

#include <stdint.h>

#include "accel/rtree/build/rtree_bulk.h"

typedef struct rt_refs {
    float *box;    /* 6 floats a reference                                  */
    uint32_t *tri; /* its triangle                                           */
    uint32_t count;
} rt_refs;

/* The references of triangles 0 .. T-1 (vertices tri, 9 floats each; boxes
 * tri_box): at most T + floor(budget T). The first T are the triangles
 * themselves in order (some with cut boxes); pieces cut off follow. */
tt_status rt_split_refs(tt_context *ctx, const float *tri, const float *tri_box, uint32_t T,
                        float budget, rt_refs *out);
void rt_refs_free(tt_context *ctx, rt_refs *r);

/* Rewrites a level form built over references into one over triangles:
 * every leaf's references become their triangles, each once (a leaf may
 * end with fewer than m entries); the leaf boxes stay the references'
 * (tighter than the triangles'). lv->triangles becomes T. */
void rt_bulk_levels_merge_refs(rt_bulk_levels *lv, const uint32_t *ref_tri, uint32_t T);

#endif
