/* tt_accel_check for the kd-tree: the layout, the sparse boxes, and that
 * every triangle is exactly in the leaves its clipped part overlaps.
 *
 * Triangle placement is checked with the exact (double) clipper, in two
 * directions:
 *  - complete: a descent per triangle with its part inside the current cell.
 *    Where that part reaches strictly into a child's half-space the child
 *    must hold the triangle in every leaf it reaches there. A part that only
 *    touches the plane from one side (a vertex or an edge on it) may be in
 *    either child. A part lying in the plane must be complete in at least one
 *    of the two children (the builder puts it on one side).
 *  - sound: every reference in a leaf touches the leaf's closed cell,
 *    widened by a few float rounding units, as the builder's clipped bounds
 *    are rounded outwards (the triangle's bounding box does, for the binned
 *    builder's trees: tt_kdtree.loose_refs). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "accel/kdtree/build/kd_clip.h"
#include "accel/kdtree/kd_tree.h"
#include "io/scene.h"

typedef struct check {
    tt_context *ctx;
    const tt_scene *scene;
    const tt_kdtree *t;
    uint32_t next_slot; /* depth-first layout: where the next node must be */
    size_t next_ref;
    uint8_t *aug_seen;
    uint32_t aug_refs;
    double tol[3]; /* the soundness widening per axis                      */
} check;

typedef struct cell {
    double lo[3], hi[3];
} cell;

static tt_status broken(check *c, uint32_t node, const char *fmt, ...) TT_PRINTF(3, 4);

static tt_status broken(check *c, uint32_t node, const char *fmt, ...)
{
    char what[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return tt_error(c->ctx, TT_ERR_INVARIANT, "kdtree check: node %u: %s", node, what);
}

static int leaf_holds(const tt_kdtree *t, tt_kd_node leaf, uint32_t tri)
{
    const uint32_t *r = t->refs + leaf.u.first;
    uint32_t lo = 0, hi = tt_kd_leaf_count(leaf.bits);
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (r[mid] < tri) lo = mid + 1;
        else hi = mid;
    }
    return lo < tt_kd_leaf_count(leaf.bits) && r[lo] == tri;
}

/* Whether the triangle's bounding box touches the closed box [lo, hi]:
 * soundness for a builder that cuts boxes instead of clipping triangles
 * (tt_kdtree.loose_refs). */
static int box_touches(const float *v, const double lo[3], const double hi[3])
{
    for (int k = 0; k < 3; k++) {
        const double a = fmin(fmin(v[k], v[3 + k]), v[6 + k]), b = fmax(fmax(v[k], v[3 + k]), v[6 + k]);
        if (b < lo[k] || a > hi[k]) return 0;
    }
    return 1;
}

static tt_status walk_leaf(check *c, uint32_t node, tt_kd_node n, const cell *box)
{
    const tt_kdtree *t = c->t;
    uint32_t count = tt_kd_leaf_count(n.bits);
    if (n.u.first != c->next_ref)
        return broken(c, node, "leaf starts at reference %u, expected %zu", n.u.first, c->next_ref);
    if ((size_t)n.u.first + count > t->ref_count)
        return broken(c, node, "leaf runs past the %zu references (%u + %u)", t->ref_count, n.u.first,
                      count);
    c->next_ref += count;
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = box->lo[k] - c->tol[k];
        hi[k] = box->hi[k] + c->tol[k];
    }
    for (uint32_t i = 0; i < count; i++) {
        uint32_t tri = t->refs[n.u.first + i];
        if (tri >= c->scene->triangle_count)
            return broken(c, node, "leaf references triangle %u of %zu", tri,
                          c->scene->triangle_count);
        if (i > 0 && t->refs[n.u.first + i - 1] >= tri)
            return broken(c, node, "leaf references are not strictly ascending at triangle %u", tri);
        if (t->loose_refs) {
            if (!box_touches(c->scene->tri + 9 * (size_t)tri, lo, hi))
                return broken(c, node, "leaf holds triangle %u, whose box does not touch its cell",
                              tri);
            continue;
        }
        double poly[KD_CLIP_MAX][3];
        if (!kd_clip_polygon(c->scene->tri + 9 * (size_t)tri, lo, hi, poly))
            return broken(c, node, "leaf holds triangle %u, which does not touch its cell", tri);
    }
    return TT_OK;
}

static int augmented_here(const tt_kdtree *t, int depth, int aug_dist, int interior)
{
    if (depth == 0) return interior;
    return interior && t->dmin > 0 && aug_dist >= t->dmin;
}

/* The layout, the augmentation and soundness, depth first. */
static tt_status walk(check *c, uint32_t node, const cell *box, int depth, int aug_dist,
                      uint32_t parent_aug)
{
    const tt_kdtree *t = c->t;
    if (node != c->next_slot)
        return broken(c, node, "node is at slot %u, the depth-first layout puts it at %u", node,
                      c->next_slot);
    if (node >= t->node_slots)
        return broken(c, node, "index beyond the %u node slots", t->node_slots);
    if (depth > t->max_depth)
        return broken(c, node, "depth %d exceeds the limit %d", depth, t->max_depth);
    tt_kd_node n = t->nodes[node];
    int interior = !tt_kd_is_leaf(n.bits);
    int aug = interior && tt_kd_is_aug(n.bits);
    if (aug != augmented_here(t, depth, aug_dist, interior))
        return broken(c, node, "augmented flag %d, but the d_min rule (distance %d, d_min %d) says otherwise",
                      aug, aug_dist, t->dmin);
    c->next_slot = node + 1 + (uint32_t)aug;
    if (!interior) return walk_leaf(c, node, n, box);
    uint32_t rec = parent_aug;
    if (aug) {
        if (node + 1 >= t->node_slots) return broken(c, node, "extension slot missing");
        rec = t->nodes[node + 1].u.first;
        if (rec >= t->aug_count || (depth == 0) != (rec == 0))
            return broken(c, node, "box record %u is not valid here (%u records)", rec,
                          t->aug_count);
        if (c->aug_seen[rec]++)
            return broken(c, node, "box record %u is used by two nodes", rec);
        c->aug_refs++;
        const tt_kd_aug *a = &t->aug[rec];
        if (a->node != node)
            return broken(c, node, "box record %u names node %u", rec, a->node);
        if (a->parent != parent_aug)
            return broken(c, node, "box parent link %u, nearest augmented ancestor is %u",
                          a->parent, parent_aug);
        for (int k = 0; k < 3; k++)
            if ((double)a->lo[k] != box->lo[k] || (double)a->hi[k] != box->hi[k])
                return broken(c, node, "box differs from the node's cell on axis %d", k);
    }
    int axis = tt_kd_axis(n.bits);
    double p = n.u.split;
    if (!(p > box->lo[axis] && p < box->hi[axis]))
        return broken(c, node, "split %.9g is not strictly inside the cell on axis %d", p,
                      axis);
    uint32_t left = tt_kd_left(node, n.bits), right = tt_kd_right(n.bits);
    cell l = *box, r = *box;
    l.hi[axis] = r.lo[axis] = p;
    int dist = aug ? 1 : aug_dist + 1;
    tt_status st = walk(c, left, &l, depth + 1, dist, rec);
    if (st != TT_OK) return st;
    if (right != c->next_slot)
        return broken(c, node, "right child %u, the depth-first layout puts it at %u", right,
                      c->next_slot);
    return walk(c, right, &r, depth + 1, dist, rec);
}

/* Whether the part of the triangle in this cell lies in the plane. */
static int in_plane(double poly[][3], int n, int axis, double p)
{
    for (int i = 0; i < n; i++)
        if (poly[i][axis] != p) return 0;
    return 1;
}

/* Whether the part reaches strictly into the half-space beyond the plane.
 * The check's own clipping runs the planes in another order than the
 * builder's, so a vertex the builder found exactly on the plane may come
 * out here a double rounding error (around 2^-52 relative) beyond it: only
 * reaching further than 2^-36 relative (to the plane's and the scene's
 * coordinates) counts. (The builder rounds its
 * float bounds outwards, so anything truly crossing by more than a float
 * rounding error, 2^-24, is always placed on both sides.) */
static int reaches(const check *c, double poly[][3], int n, int axis, double p, double sign)
{
    const double tol = ldexp(fabs(p), -36) + ldexp(c->tol[axis], -15);
    for (int i = 0; i < n; i++)
        if (sign * (poly[i][axis] - p) > tol) return 1;
    return 0;
}

/* Completeness (see the top): 1 if the triangle, whose part in this node's
 * cell is poly, is in every leaf below that requires it. *bad: the first
 * leaf missing it. */
static int complete(const check *c, uint32_t tri, uint32_t node, const cell *box, double poly[][3],
                    int n, uint32_t *bad)
{
    const tt_kdtree *t = c->t;
    tt_kd_node nd = t->nodes[node];
    if (tt_kd_is_leaf(nd.bits)) {
        if (leaf_holds(t, nd, tri)) return 1;
        *bad = node;
        return 0;
    }
    int axis = tt_kd_axis(nd.bits);
    double p = nd.u.split;
    cell l = *box, r = *box;
    l.hi[axis] = r.lo[axis] = p;
    const float *v = c->scene->tri + 9 * (size_t)tri;
    double pl[KD_CLIP_MAX][3], pr[KD_CLIP_MAX][3];
    int nl = kd_clip_polygon(v, l.lo, l.hi, pl), nr = kd_clip_polygon(v, r.lo, r.hi, pr);
    uint32_t left = tt_kd_left(node, nd.bits), right = tt_kd_right(nd.bits);
    if (in_plane(poly, n, axis, p))
        return complete(c, tri, left, &l, pl, nl, bad) || complete(c, tri, right, &r, pr, nr, bad);
    if (nl && reaches(c, pl, nl, axis, p, -1.0) && !complete(c, tri, left, &l, pl, nl, bad)) return 0;
    if (nr && reaches(c, pr, nr, axis, p, 1.0) && !complete(c, tri, right, &r, pr, nr, bad)) return 0;
    return 1;
}

tt_status tt_kdtree_check(tt_context *ctx, const tt_scene *scene, const tt_kdtree *t)
{
    check c;
    memset(&c, 0, sizeof c);
    c.ctx = ctx;
    c.scene = scene;
    c.t = t;
    if (t->max_depth > TT_KD_MAX_DEPTH)
        return tt_error(ctx, TT_ERR_INVARIANT, "kdtree check: depth limit %d above the stack bound %d",
                        t->max_depth, TT_KD_MAX_DEPTH);
    if (t->aug_count == 0 || t->aug[0].node != 0 || t->aug[0].parent != TT_KD_NO_PARENT)
        return tt_error(ctx, TT_ERR_INVARIANT, "kdtree check: node 0: box record 0 is not the root's");
    cell root;
    for (int k = 0; k < 3; k++) {
        root.lo[k] = scene->bounds.lo[k];
        root.hi[k] = scene->bounds.hi[k];
        if (scene->triangle_count &&
            (t->aug[0].lo[k] != scene->bounds.lo[k] || t->aug[0].hi[k] != scene->bounds.hi[k]))
            return tt_error(ctx, TT_ERR_INVARIANT,
                            "kdtree check: node 0: root box differs from the scene box on axis %d", k);
        /* Eight float rounding units of the coordinates involved. */
        double m = fmax(fabs(root.lo[k]), fabs(root.hi[k]));
        c.tol[k] = (scene->triangle_count ? m : 0.0) * ldexp(1.0, -21);
    }
    if (scene->triangle_count == 0) {
        tt_kd_node n = t->nodes[0];
        if (t->node_slots != 1 || !tt_kd_is_leaf(n.bits) || tt_kd_leaf_count(n.bits) != 0 || !t->view.empty)
            return tt_error(ctx, TT_ERR_INVARIANT, "kdtree check: node 0: an empty scene needs one empty leaf");
        return TT_OK;
    }
    c.aug_seen = tt_calloc(ctx, t->aug_count, 1);
    if (!c.aug_seen) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree check: out of memory");
    tt_status st = walk(&c, 0, &root, 0, 0, TT_KD_NO_PARENT);
    if (st == TT_OK && c.next_slot != t->node_slots)
        st = tt_error(ctx, TT_ERR_INVARIANT, "kdtree check: %u node slots, the tree uses %u",
                      t->node_slots, c.next_slot);
    if (st == TT_OK && c.next_ref != t->ref_count)
        st = tt_error(ctx, TT_ERR_INVARIANT, "kdtree check: %zu references, the leaves use %zu",
                      t->ref_count, c.next_ref);
    /* A root leaf keeps record 0 for the scene box without the flag. */
    uint32_t expect = tt_kd_is_leaf(t->nodes[0].bits) ? t->aug_count - 1 : t->aug_count;
    if (st == TT_OK && c.aug_refs != expect)
        st = tt_error(ctx, TT_ERR_INVARIANT, "kdtree check: %u box records, %u augmented nodes",
                      t->aug_count, c.aug_refs);
    tt_free(ctx, c.aug_seen);
    for (uint32_t tri = 0; st == TT_OK && tri < scene->triangle_count; tri++) {
        double poly[KD_CLIP_MAX][3];
        int n = kd_clip_polygon(scene->tri + 9 * (size_t)tri, root.lo, root.hi, poly);
        uint32_t bad = 0;
        if (!complete(&c, tri, 0, &root, poly, n, &bad))
            st = tt_error(ctx, TT_ERR_INVARIANT,
                          "kdtree check: node %u: leaf lacks triangle %u, whose clipped part "
                          "overlaps its cell",
                          bad, tri);
    }
    return st;
}
