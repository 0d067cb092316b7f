/* The binned SAH split (after Wald 2007 and Shevtsov et al. 2007, here on
 * the triangles' clipped bounds): each axis of the cell is cut into BINS
 * equal bins; one pass counts in which bin each triangle's part starts and
 * ends, and the SAH is evaluated at the BINS - 1 inner bin boundaries only.
 * O(n) per node instead of a sort; the tree is close to the exact one at
 * the big nodes near the root, where a few candidates more or less change
 * little, and the builder switches to the exact sweep below kd_binned_min
 * triangles, where the leaves are decided. */
#include "accel/kdtree/kd_build.h"

#include <math.h>

#define BINS 64

uint32_t kd_binned_min = 32;

/* The SAH cost of the split at pos with nl and nr triangles (kd_sweep's). */
static double split_cost(const kd_builder *b, const tt_aabb *cell, int axis, double pos, uint32_t nl,
                         uint32_t nr)
{
    double ext[3];
    for (int k = 0; k < 3; k++) ext[k] = (double)cell->hi[k] - (double)cell->lo[k];
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double area = ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0];
    const double cap = ext[u] * ext[v] / area, side = (ext[u] + ext[v]) / area;
    const double pl = cap + (pos - cell->lo[axis]) * side, pr = cap + (cell->hi[axis] - pos) * side;
    double c = b->ct + b->ci * (pl * nl + pr * nr);
    if (nl == 0 || nr == 0) c *= b->empty_factor;
    return c;
}

kd_split kd_binned_split(const kd_builder *b, const kd_item *items, uint32_t n, const tt_aabb *cell)
{
    kd_split best = {-1, 0.0f, 0, INFINITY, 0, 0};
    double ext[3];
    for (int k = 0; k < 3; k++) ext[k] = (double)cell->hi[k] - (double)cell->lo[k];
    if (!(ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0] > 0.0)) return best;
    /* In which bin each triangle's part starts and ends, all axes in one
     * pass. The bin index is an estimate in float (the counts of the plane
     * chosen are taken exactly below); clamped, so that bounds on the
     * cell's faces land in the first and last bin. */
    uint32_t start[3][BINS] = {{0}}, end[3][BINS] = {{0}};
    float lo[3], scale[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = cell->lo[k];
        scale[k] = ext[k] > 0.0 ? (float)(BINS / ext[k]) : 0.0f;
    }
    /* The clamp is done in float, before the conversion (min/max
     * instructions, no branches): the same bins as clamping the integer,
     * since (int) truncates and BINS - 1 is exact in float. */
    const float top = (float)(BINS - 1);
    for (uint32_t i = 0; i < n; i++) {
        const tt_aabb *box = &items[i].box;
        for (int k = 0; k < 3; k++) {
            float f = (box->lo[k] - lo[k]) * scale[k];
            float g = (box->hi[k] - lo[k]) * scale[k];
            f = f > 0.0f ? f : 0.0f;
            g = g > 0.0f ? g : 0.0f;
            f = f < top ? f : top;
            g = g < top ? g : top;
            start[k][(int)f]++;
            end[k][(int)g]++;
        }
    }
    for (int axis = 0; axis < 3; axis++) {
        if (!(ext[axis] > 0.0)) continue;
        /* The boundary j lies between bins j - 1 and j: a triangle starting
         * in a bin below it counts left, one ending in bin j or above
         * counts right. */
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const double area = ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0];
        const double cap = ext[u] * ext[v] / area, side = (ext[u] + ext[v]) / area;
        uint32_t nl = 0, nr = n;
        for (int j = 1; j < BINS; j++) {
            nl += start[axis][j - 1];
            nr -= end[axis][j - 1];
            const float pos = (float)(cell->lo[axis] + ext[axis] * j / BINS);
            if (!(pos > cell->lo[axis] && pos < cell->hi[axis])) continue;
            const double pl = cap + ((double)pos - cell->lo[axis]) * side;
            const double pr = cap + ((double)cell->hi[axis] - pos) * side;
            double c = b->ct + b->ci * (pl * nl + pr * nr);
            if (nl == 0 || nr == 0) c *= b->empty_factor;
            if (c < best.cost) {
                best.cost = c;
                best.axis = axis;
                best.pos = pos;
            }
        }
    }
    if (best.axis < 0) return best;
    /* The exact counts of the plane (straddlers in both), as kd_sweep
     * reports them: the cost compared with a leaf's and the references
     * the budget counts. Triangles lying in the plane go right. */
    uint32_t nl = 0, nr = 0;
    for (uint32_t i = 0; i < n; i++) {
        const int side = kd_classify(items[i].box.lo[best.axis], items[i].box.hi[best.axis], &best);
        nl += (side & KD_SIDE_LEFT) != 0;
        nr += (side & KD_SIDE_RIGHT) != 0;
    }
    best.n_left = nl;
    best.n_right = nr;
    best.cost = split_cost(b, cell, best.axis, best.pos, nl, nr);
    return best;
}
