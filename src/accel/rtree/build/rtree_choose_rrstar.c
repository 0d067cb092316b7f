/* The RR*-tree's choice of subtree (Beckmann & Seeger 2009, "A revised
 * R*-tree in comparison with related index structures", ChooseSubtree), in
 * 3D, for TT_RTREE_RRSTAR:
 *  1. entries that already contain the new box: the one of least volume
 *     (least perimeter where volumes are zero);
 *  2. otherwise the entries in ascending order of perimeter enlargement;
 *     if enlarging the first adds no overlap with the others (overlap
 *     measured by the perimeter of the intersection), it is the choice;
 *  3. otherwise the candidates are the entries up to the last one whose
 *     overlap with the enlarged first entry grows; among them, the one
 *     whose enlargement adds the least overlap with the other candidates,
 *     measured by volume, or by perimeter when an enlarged candidate is
 *     flat (zero volume). Ties keep the perimeter-enlargement order.
 * The paper's depth-first pruning of step 3 only saves work on large nodes;
 * with M <= 16 every candidate is evaluated, which gives its best result.
 * Perimeters are taken as the sum of the three extents (half the box's
 * edge length, which changes no order). */
#include "accel/rtree/build/rtree_build.h"
#include "accel/rtree/rtree_box.h"

static float margin(const float b[6]) { return (b[3] - b[0]) + (b[4] - b[1]) + (b[5] - b[2]); }

static void unite(const float a[6], const float e[6], float out[6])
{
    for (int k = 0; k < 3; k++) {
        out[k] = rt_min(a[k], e[k]);
        out[k + 3] = rt_max(a[k + 3], e[k + 3]);
    }
}

/* The overlap of a and b by the chosen measure: the intersection's volume,
 * or its perimeter (0 where they do not meet). */
static float overlap(const float a[6], const float b[6], int by_volume)
{
    float d[3];
    for (int k = 0; k < 3; k++) {
        d[k] = rt_min(a[k + 3], b[k + 3]) - rt_max(a[k], b[k]);
        if (d[k] < 0.0f) return 0.0f;
    }
    return by_volume ? d[0] * d[1] * d[2] : d[0] + d[1] + d[2];
}

int rt_choose_rrstar(const rt_builder *b, uint32_t n, const float e[6])
{
    const int cnt = b->hdr[n].count, cap = b->cap;
    if (cnt <= 1) return 0;
    const float *s = rt_node_box(b, n);
    /* 1: covering entries, straight from the rows (when one covers, and
     * high in the tree one mostly does, nothing else is computed) */
    int best = -1;
    float bv = 0.0f, bm = 0.0f;
    for (int i = 0; i < cnt; i++) {
        if (!(s[i] <= e[0] && s[cap + i] <= e[1] && s[2 * cap + i] <= e[2] &&
              s[3 * cap + i] >= e[3] && s[4 * cap + i] >= e[4] && s[5 * cap + i] >= e[5]))
            continue;
        float c[6];
        rt_soa_get(s, cap, i, c);
        const float vi = rt_box_volume(c), mi = margin(c);
        if (best < 0 || vi < bv || (vi == bv && mi < bm)) {
            best = i;
            bv = vi;
            bm = mi;
        }
    }
    if (best >= 0) return best;
    float ent[TT_RT_CAP][6], grown[TT_RT_CAP][6];
    for (int i = 0; i < cnt; i++) {
        rt_soa_get(s, cap, i, ent[i]);
        unite(ent[i], e, grown[i]);
    }
    /* 2: ascending perimeter enlargement (insertion sort, stable) */
    int order[TT_RT_CAP];
    float dm[TT_RT_CAP];
    for (int i = 0; i < cnt; i++) {
        dm[i] = margin(grown[i]) - margin(ent[i]);
        int j = i;
        while (j > 0 && dm[order[j - 1]] > dm[i]) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = i;
    }
    const int first = order[0];
    float grow1 = 0.0f;
    int p = 0; /* candidates: order[0 .. p] */
    for (int j = 1; j < cnt; j++) {
        const int o = order[j];
        const float g = overlap(grown[first], ent[o], 0) - overlap(ent[first], ent[o], 0);
        grow1 += g;
        if (g > 0.0f) p = j;
    }
    if (grow1 <= 0.0f) return first;
    /* 3: the candidate adding the least overlap with the other candidates */
    int by_volume = 1;
    for (int j = 0; j <= p; j++) by_volume &= rt_box_volume(grown[order[j]]) > 0.0f;
    float best_add = 0.0f;
    best = -1;
    for (int j = 0; j <= p; j++) {
        const int t = order[j];
        float add = 0.0f;
        for (int q = 0; q <= p; q++) {
            if (q == j) continue;
            const int o = order[q];
            add += overlap(grown[t], ent[o], by_volume) - overlap(ent[t], ent[o], by_volume);
        }
        if (best < 0 || add < best_add) {
            best = t;
            best_add = add;
            if (add <= 0.0f) break;
        }
    }
    return best;
}
