/* The binned SAH split (after Wald 2007 and Shevtsov et al. 2007, here on
 * the triangles' clipped bounds): each axis of the cell is cut into BINS
 * equal bins; one pass counts in which bin each triangle's part starts and
 * ends, and the SAH is evaluated at the BINS - 1 inner bin boundaries only.
 * O(n) per node instead of a sort; the tree is close to the exact one at
 * the big nodes near the root, where a few candidates more or less change
 * little, and the builder switches to the exact sweep below KD_BINNED_MIN
 * triangles, where the leaves are decided. */
#include "accel/kdtree/kd_build.h"

#include <math.h>

#define BINS 64

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

static int bin_of(float x, double lo, double scale)
{
    const double f = ((double)x - lo) * scale;
    const int i = f > 0.0 ? (int)f : 0;
    return i < BINS ? i : BINS - 1;
}

kd_split kd_binned_split(const kd_builder *b, const kd_item *items, uint32_t n, const tt_aabb *cell)
{
    kd_split best = {-1, 0.0f, 0, INFINITY, 0, 0};
    double ext[3];
    for (int k = 0; k < 3; k++) ext[k] = (double)cell->hi[k] - (double)cell->lo[k];
    if (!(ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0] > 0.0)) return best;
    for (int axis = 0; axis < 3; axis++) {
        if (!(ext[axis] > 0.0)) continue;
        const double lo = cell->lo[axis], scale = BINS / ext[axis];
        uint32_t start[BINS] = {0}, end[BINS] = {0};
        for (uint32_t i = 0; i < n; i++) {
            start[bin_of(items[i].box.lo[axis], lo, scale)]++;
            end[bin_of(items[i].box.hi[axis], lo, scale)]++;
        }
        /* The boundary j lies between bins j - 1 and j: a triangle starting
         * in a bin below it counts left, one ending in bin j or above
         * counts right (the estimate; the counts of the plane chosen are
         * taken exactly below). */
        uint32_t nl = 0, nr = n;
        for (int j = 1; j < BINS; j++) {
            nl += start[j - 1];
            nr -= end[j - 1];
            const float pos = (float)(lo + ext[axis] * j / BINS);
            if (!(pos > cell->lo[axis] && pos < cell->hi[axis])) continue;
            const double c = split_cost(b, cell, axis, pos, nl, nr);
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
