/* "Perfect splits" (Havran; Wald & Havran 2006): split candidates come from
 * the bounds of the part of each triangle inside the node's cell, not from
 * the triangle's own bounds. */
#ifndef TT_ACCEL_KDTREE_KD_CLIP_H
#define TT_ACCEL_KDTREE_KD_CLIP_H

#include "geometry/aabb.h"

/* Bounds of triangle tri (9 floats) clipped to the closed box. Returns 0 if
 * nothing of the triangle is inside. The result is conservative: computed in
 * double and rounded outward to float, then clamped to the box, so it always
 * contains the exact clipped part and never leaves the box. A triangle that
 * lies inside the box gets its exact vertex bounds. */
int kd_clip_triangle(const float *tri, const tt_aabb *box, tt_aabb *out);

/* kd_clip_triangle of the triangle to both children of cell split at pos
 * on axis (left: hi[axis] = pos, right: lo[axis] = pos), with the same
 * results bit for bit, the clipping by the planes they share made once.
 * Returns bit 0 set if something is inside the left child (its bounds in
 * *left), bit 1 for the right. */
int kd_clip_triangle_split(const float *tri, const tt_aabb *cell, int axis, float pos,
                           tt_aabb *left, tt_aabb *right);

/* The part of triangle tri inside the closed box [lo, hi], as a convex
 * polygon in double (at most KD_CLIP_MAX vertices; vertices created on a
 * face get that face's coordinate exactly). Returns the vertex count, 0 if
 * nothing is inside. Used by the builder above and by tt_accel_check. */
#define KD_CLIP_MAX 9
int kd_clip_polygon(const float *tri, const double lo[3], const double hi[3],
                    double out[KD_CLIP_MAX][3]);

#endif
