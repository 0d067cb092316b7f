/* Ray-versus-cell arithmetic shared by every kd-tree traversal (CPU and GPU).
 *
 * Robustness rests on one rule: the distance at which a ray crosses a plane
 * x_k = c is always computed the same way, (c - org_k) * inv_k, whether c is
 * a split position met while descending or the face of a sparse box met
 * while climbing back up. A box face IS the split position of an ancestor
 * (the same float), so both give bit-identical distances and the cells a
 * traversal visits tile the ray without gaps or overlaps, with no epsilon.
 *
 * Axes along which the ray does not move (dir_k == 0, possibly -0) never
 * produce a distance: the ray is simply on one side of such a plane for its
 * whole length, or lies in it, which each traversal handles explicitly. */
#ifndef TT_ACCEL_KDTREE_KD_RAY_H
#define TT_ACCEL_KDTREE_KD_RAY_H

#include "accel/kdtree/kd_layout.h"
#include "geometry/ray.h"

/* min / max as plain comparisons: fminf / fmaxf must honour NaN, which
 * keeps compilers from using the single min / max instruction and makes
 * them library calls in the traversal's inner loop. */
TT_HD float tt_kd_min(float a, float b) { return a < b ? a : b; }
TT_HD float tt_kd_max(float a, float b) { return a > b ? a : b; }

/* The stack traversals widen every plane crossing by this much relative
 * uncertainty (see tt_kd_band): 2^-19, some 30 float rounding units. */
#define TT_KD_BAND 1.9073486e-6f

/* A ray's crossing distance ts of a plane x_k = p is uncertain: (p - o) and
 * 1 / d are rounded, and the watertight triangle test sees the ray through
 * its own rounding. When two planes are crossed at nearly the same distance
 * (a ray through an edge of the tree, or aimed at a vertex, which lies on
 * split planes), the computed order of the crossings may differ from where
 * the triangle test finds the ray, so the triangle it hits at the corner
 * may lie in a cell the computed order skips. The stack traversals
 * therefore visit a child when its interval widened by
 * e = band * (|p| + |o_k|) / |d_k| (an upper bound of the rounding error,
 * with a wide margin) touches the ray's. Visiting a cell too many only costs
 * time; hits stay exact (closest so far, see kd_trace_common.h). Per ray:
 * bi[k] = band |inv_k|, bo[k] = band |o_k inv_k|, so e = |p| bi[k] + bo[k]. */
typedef struct tt_kd_band {
    float bi[3], bo[3];
} tt_kd_band;

TT_HD void tt_kd_band_init(tt_kd_band *b, const tt_wray *r)
{
    for (int k = 0; k < 3; k++) {
        b->bi[k] = TT_KD_BAND * fabsf(r->inv[k]);
        b->bo[k] = b->bi[k] * fabsf(r->org[k]);
    }
}

/* The ray's interval [*ta, *tb] inside a box, clipped to its [tmin, tmax).
 * Returns 0 if the ray misses it. A zero-length interval (a ray grazing an
 * edge or corner) counts as a hit of the box. With a band (the stack
 * traversals), each face crossing is widened by its rounding band, so a ray
 * through an edge of the scene box is not lost to rounding either. */
TT_HD int tt_kd_box_interval(const tt_kd_aug *a, const tt_wray *r, const tt_kd_band *band,
                             float *ta, float *tb)
{
    float t0 = r->tmin, t1 = TT_INF;
    for (int k = 0; k < 3; k++) {
        const float lo = TT_LDG(&a->lo[k]), hi = TT_LDG(&a->hi[k]), o = r->org[k];
        if (r->dir[k] == 0.0f) {
            if (!(o >= lo && o <= hi)) return 0;
            continue;
        }
        const int neg = r->dir[k] < 0.0f;
        const float fnear = neg ? hi : lo, ffar = neg ? lo : hi;
        float tn = (fnear - o) * r->inv[k], tf = (ffar - o) * r->inv[k];
        if (band) {
            tn -= fabsf(fnear) * band->bi[k] + band->bo[k];
            tf += fabsf(ffar) * band->bi[k] + band->bo[k];
        }
        t0 = tt_kd_max(t0, tn);
        t1 = tt_kd_min(t1, tf);
    }
    if (!(t0 <= t1 && t0 < r->tmax)) return 0;
    *ta = t0;
    *tb = t1;
    return 1;
}

/* The same for the scene box (aug[0]); an empty tree is never hit. */
TT_HD int tt_kd_root_interval(const tt_kd_view *T, const tt_wray *r, const tt_kd_band *band,
                              float *ta, float *tb)
{
    return !T->empty && tt_kd_box_interval(&T->aug[0], r, band, ta, tb);
}

/* Where the ray leaves a sparse box (the ray is known to be in it). */
TT_HD float tt_kd_box_exit(const tt_kd_aug *a, const tt_wray *r)
{
    float t = TT_INF;
    for (int k = 0; k < 3; k++) {
        if (r->dir[k] == 0.0f) continue;
        const float face = r->dir[k] < 0.0f ? TT_LDG(&a->lo[k]) : TT_LDG(&a->hi[k]);
        t = tt_kd_min(t, (face - r->org[k]) * r->inv[k]);
    }
    return t;
}

/* Whether a traversal may start in this box: the origin lies strictly
 * inside it. An origin on a face also lies in the neighbouring cell behind
 * that face (a triangle through the origin may be there alone, hit at
 * t = 0), and a ray lying in a face runs along the neighbour for its whole
 * length; a traversal started inside the box would see neither, so such a
 * ray starts higher up, where that face is an interior split plane. */
TT_HD int tt_kd_box_holds_origin(const tt_kd_aug *a, const tt_wray *r)
{
    for (int k = 0; k < 3; k++) {
        const float o = r->org[k];
        if (!(o > TT_LDG(&a->lo[k]) && o < TT_LDG(&a->hi[k]))) return 0;
    }
    return 1;
}

/* The start node (an aug[] index) for a ray whose root interval is
 * [*ta, *tb]: the hinted augmented node, or the nearest augmented ancestor
 * of it that holds the ray origin, with the interval narrowed to that box;
 * the root when the hint is TT_INVALID_ID or out of range, when no box on
 * the way up holds the origin, or when tmin != 0 (the hint describes the
 * origin, not the point at tmin). *tests counts the boxes tested. */
TT_HD uint32_t tt_kd_start_node(const tt_kd_view *T, const tt_wray *r, uint32_t hint, float *ta,
                                float *tb, unsigned *tests)
{
    if (hint == 0 || hint >= T->aug_count || r->tmin != 0.0f) return 0;
    for (uint32_t h = hint; h != 0 && h != TT_KD_NO_PARENT; h = TT_LDG(&T->aug[h].parent)) {
        ++*tests;
        if (tt_kd_box_holds_origin(&T->aug[h], r)) {
            *ta = r->tmin;
            *tb = tt_kd_box_exit(&T->aug[h], r);
            return h;
        }
    }
    return 0;
}

/* Whether the ray leaves box a near one of its edges or corners: a face
 * other than the exit face at t_exit is crossed within the rounding band,
 * or the ray runs within the band of a face it is parallel to. */
TT_HD int tt_kd_exit_near_edge(const tt_kd_aug *a, const tt_wray *r, const tt_kd_band *band,
                               float t_exit)
{
    int at_exit = 0;
    for (int k = 0; k < 3; k++) {
        const float lo = TT_LDG(&a->lo[k]), hi = TT_LDG(&a->hi[k]), o = r->org[k];
        if (r->dir[k] == 0.0f) {
            const float e = TT_KD_BAND * (fabsf(o) + tt_kd_max(fabsf(lo), fabsf(hi)));
            if (o - lo <= e || hi - o <= e) return 1;
            continue;
        }
        const float face = r->dir[k] < 0.0f ? lo : hi;
        const float t = (face - r->org[k]) * r->inv[k];
        const float e = 2.0f * (fabsf(face) * band->bi[k] + band->bo[k]);
        if (t == t_exit && !at_exit) at_exit = 1; /* the exit face itself */
        else if (t - t_exit <= e) return 1;
    }
    return 0;
}

#endif
