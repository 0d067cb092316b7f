/* Building a kd-tree from a scene: option validation, the builder run, and
 * the shape statistics counted once afterwards. */
#include <math.h>
#include <string.h>

#include "accel/kdtree/build/kd_build.h"
#include "accel/kdtree/kd_blocks.h"
#include "io/scene.h"

static tt_status validate(tt_context *ctx, const tt_kdtree_options *o)
{
    if (o->builder != TT_KD_NLOGN && o->builder != TT_KD_NLOG2N && o->builder != TT_KD_BINNED)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "kdtree: builder %d is not TT_KD_NLOGN (0), TT_KD_NLOG2N (1) or "
                        "TT_KD_BINNED (2)",
                        (int)o->builder);
    if (o->dmin == 0) /* tt_accel_build resolves auto before this */
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "kdtree: dmin 0 (auto) was not resolved (>= 1: a box every dmin levels; "
                        "< 0: no boxes)");
    if (!(isfinite(o->cost_traversal) && o->cost_traversal > 0.0f))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "kdtree: cost_traversal %g must be finite and > 0",
                        (double)o->cost_traversal);
    if (!(isfinite(o->cost_intersect) && o->cost_intersect > 0.0f))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "kdtree: cost_intersect %g must be finite and > 0",
                        (double)o->cost_intersect);
    if (!(o->empty_bonus >= 0.0f && o->empty_bonus < 1.0f))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "kdtree: empty_bonus %g must be in [0, 1)",
                        (double)o->empty_bonus);
    if (o->max_depth < 0 || o->max_depth > TT_KD_MAX_DEPTH)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "kdtree: max_depth %d must be 0 (automatic) or 1..%d", o->max_depth,
                        TT_KD_MAX_DEPTH);
    if ((int)o->traversal < TT_KD_HTR || (int)o->traversal > TT_KD_SEQ)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "kdtree: traversal %d is not one of htr (0), btr (1), sltr (2), seq (3)",
                        (int)o->traversal);
    if (o->shadow_caster_hint != 0 && o->shadow_caster_hint != 1)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "kdtree: shadow_caster_hint %d must be 0 or 1",
                        o->shadow_caster_hint);
    if (o->shadow_caster_hint && o->traversal == TT_KD_HTR)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "kdtree: shadow_caster_hint needs the btr, sltr or seq traversal (htr "
                        "uses no boxes)");
    return TT_OK;
}

/* Havran's rule of thumb for the depth limit: 8 + 1.3 log2 N. */
static int auto_depth(size_t n)
{
    double d = 8.0 + 1.3 * log2(n > 1 ? (double)n : 1.0);
    int r = (int)lround(d);
    return r > TT_KD_MAX_DEPTH ? TT_KD_MAX_DEPTH : r;
}

static double half_area(const tt_aabb *b)
{
    double x = (double)b->hi[0] - b->lo[0], y = (double)b->hi[1] - b->lo[1],
           z = (double)b->hi[2] - b->lo[2];
    return x * y + y * z + z * x;
}

/* Depth-first walk counting the shape and summing the tree's SAH cost. */
static void measure(tt_kdtree *t, uint32_t node, const tt_aabb *cell, int depth, double *sum_depth)
{
    const tt_kd_node *n = &t->nodes[node];
    double area = half_area(cell);
    t->nodes_total++;
    if (depth > t->depth_max) t->depth_max = depth;
    if (tt_kd_is_leaf(n->bits)) {
        uint32_t c = tt_kd_leaf_count(n->bits);
        t->leaves++;
        t->empty_leaves += c == 0;
        *sum_depth += depth;
        t->sah_cost += t->cost_intersect * c * area;
        return;
    }
    t->interior++;
    t->sah_cost += t->cost_traversal * area;
    tt_aabb l = *cell, r = *cell;
    int axis = tt_kd_axis(n->bits);
    l.hi[axis] = r.lo[axis] = n->u.split;
    measure(t, tt_kd_left(node, n->bits), &l, depth + 1, sum_depth);
    measure(t, tt_kd_right(n->bits), &r, depth + 1, sum_depth);
}

tt_status tt_kdtree_build(tt_context *ctx, const tt_scene *scene, const tt_kdtree_options *opt,
                          tt_kdtree **out)
{
    *out = NULL;
    tt_status st = validate(ctx, opt);
    if (st != TT_OK) return st;
    if (scene->triangle_count > KD_MAX_TRIANGLES)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "kdtree: %zu triangles, at most %u supported",
                        scene->triangle_count, KD_MAX_TRIANGLES);
    kd_builder b;
    memset(&b, 0, sizeof b);
    b.ctx = ctx;
    b.tri = scene->tri;
    b.tri_count = (uint32_t)scene->triangle_count;
    b.ct = opt->cost_traversal;
    b.ci = opt->cost_intersect;
    b.empty_factor = 1.0 - (double)opt->empty_bonus;
    b.max_depth = opt->max_depth ? opt->max_depth : auto_depth(scene->triangle_count);
    b.dmin = opt->dmin;
    b.ref_budget = kd_ref_budget(b.tri_count);
    tt_aabb root = scene->bounds;
    /* Record 0: the root's box, which every traversal clips against. */
    b.aug = tt_alloc_array(ctx, 256, sizeof *b.aug);
    if (!b.aug) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree: out of memory");
    b.aug_cap = 256;
    b.aug_count = 1;
    memcpy(b.aug[0].lo, root.lo, sizeof root.lo);
    memcpy(b.aug[0].hi, root.hi, sizeof root.hi);
    b.aug[0].parent = TT_KD_NO_PARENT;
    b.aug[0].node = 0;
    if (b.tri_count == 0) st = kd_emit_leaf(&b, NULL, 0);
    else if (opt->builder == TT_KD_NLOGN) st = kd_build_nlogn(&b, &root);
    else if (opt->builder == TT_KD_NLOG2N) st = kd_build_nlog2n(&b, &root);
    else st = kd_build_binned(&b, &root);
    tt_kdtree *t = NULL;
    if (st == TT_OK) {
        t = tt_calloc(ctx, 1, sizeof *t);
        if (!t) st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "kdtree: out of memory");
    }
    if (st != TT_OK) {
        tt_free(ctx, b.nodes);
        tt_free(ctx, b.refs);
        tt_free(ctx, b.aug);
        return st;
    }
    t->nodes = b.nodes;
    t->node_slots = b.node_count;
    t->refs = b.refs;
    t->ref_count = b.ref_count;
    t->aug = b.aug;
    t->aug_count = b.aug_count;
    t->dmin = opt->dmin;
    t->max_depth = b.max_depth;
    t->ref_budget_hit = b.budget_hit;
    t->loose_refs = opt->builder == TT_KD_BINNED;
    t->cost_traversal = b.ct;
    t->cost_intersect = b.ci;
    t->empty_factor = b.empty_factor;
    t->view.nodes = t->nodes;
    t->view.refs = t->refs;
    t->view.tri = scene->tri;
    t->view.aug = t->aug;
    t->view.aug_count = t->aug_count;
    t->view.empty = b.tri_count == 0;
    t->fast = tt_kd_cpu_kernels(TT_ISA_SCALAR, scene->triangle_count);
    t->fast_view = t->view;
    double sum_depth = 0.0, root_area = half_area(&root);
    measure(t, 0, &root, 0, &sum_depth);
    t->depth_mean = t->leaves ? sum_depth / t->leaves : 0.0;
    t->sah_cost = root_area > 0.0 ? t->sah_cost / root_area : 0.0;
    *out = t;
    return TT_OK;
}

void tt_kdtree_destroy(tt_context *ctx, tt_kdtree *t)
{
    if (!t) return;
    tt_kdtree_blocks_free(ctx, t);
    tt_free(ctx, t->nodes);
    tt_free(ctx, t->refs);
    tt_free(ctx, t->aug);
    tt_free(ctx, t);
}

size_t tt_kdtree_memory(const tt_kdtree *t)
{
    return (size_t)t->node_slots * sizeof(tt_kd_node) + t->ref_count * sizeof(uint32_t) +
           (size_t)t->aug_count * sizeof(tt_kd_aug);
}

uint32_t tt_kdtree_locate(const tt_kdtree *t, const float *p)
{
    const tt_kd_aug *root = &t->aug[0];
    if (t->view.empty) return TT_INVALID_ID;
    for (int k = 0; k < 3; k++)
        if (!(p[k] >= root->lo[k] && p[k] <= root->hi[k])) return TT_INVALID_ID;
    uint32_t node = 0, found = 0;
    for (;;) {
        const tt_kd_node *n = &t->nodes[node];
        if (tt_kd_is_leaf(n->bits)) return found;
        if (tt_kd_is_aug(n->bits)) found = tt_kd_aug_index(t->nodes, node);
        /* A point on the plane lies in both cells; either is correct. */
        node = p[tt_kd_axis(n->bits)] <= n->u.split ? tt_kd_left(node, n->bits) : tt_kd_right(n->bits);
    }
}
