/* The kd-tree's save/load vtable entries: its scalars (effective
 * parameters and shape statistics) as a params section, the nodes,
 * references and sparse boxes verbatim (kd_layout.h). Loading uses the
 * three arrays in place from the mapping after a walk that checks what
 * every traversal relies on: each slot reached once from the root, children
 * after their parent, depth within the traversal stacks, leaf ranges inside
 * the references, references naming real triangles, and each box record
 * belonging to its node and linking to its nearest augmented ancestor. */
#include <string.h>

#include "accel/accel_io.h"
#include "accel/kdtree/kd_io.h"
#include "accel/kdtree/kd_blocks.h"
#include "accel/kdtree/trace/kd_trace_cpu.h"
#include "io/accel_file.h"

#define KD_IO_LAYOUT 1u
#define KD_IO_VERSION 1u

enum { P_DMIN, P_MAX_DEPTH, P_BUDGET_HIT, P_LOOSE, P_CT, P_CI, P_EMPTY_FACTOR, P_NODES_TOTAL,
       P_INTERIOR, P_LEAVES, P_EMPTY_LEAVES, P_DEPTH_MAX, P_DEPTH_MEAN, P_SAH, P_EMPTY, P_COUNT };

tt_status kd_io_save(const tt_accel *a, tt_af_writer *w)
{
    const tt_kdtree *t = a->impl;
    const double p[P_COUNT] = {
        t->dmin,     t->max_depth, t->ref_budget_hit, t->loose_refs,   t->cost_traversal,
        t->cost_intersect, t->empty_factor, t->nodes_total, t->interior, t->leaves,
        t->empty_leaves, t->depth_max, t->depth_mean, t->sah_cost, t->view.empty};
    w->layout = KD_IO_LAYOUT;
    w->layout_version = KD_IO_VERSION;
    tt_status st = tt_af_add_copy(a->ctx, w, TT_AF_SEC_PARAMS, 8, P_COUNT, p);
    if (st == TT_OK)
        st = tt_af_add(a->ctx, w, TT_AF_SEC_KD_NODES, sizeof(tt_kd_node), t->node_slots, t->nodes);
    if (st == TT_OK) st = tt_af_add(a->ctx, w, TT_AF_SEC_KD_REFS, 4, t->ref_count, t->refs);
    if (st == TT_OK)
        st = tt_af_add(a->ctx, w, TT_AF_SEC_KD_AUG, sizeof(tt_kd_aug), t->aug_count, t->aug);
    return st;
}

typedef struct walk_item {
    uint32_t node, depth, aug; /* aug: the nearest augmented ancestor's record */
} walk_item;

static tt_status walk(tt_context *ctx, const tt_af_file *f, const tt_kdtree *t, uint32_t T,
                      uint8_t *seen)
{
    walk_item stack[TT_KD_MAX_DEPTH + 2];
    int sp = 0;
    uint32_t aug_seen = 0;
    stack[sp++] = (walk_item){0, 0, TT_KD_NO_PARENT};
    while (sp > 0) {
        const walk_item it = stack[--sp];
        const uint32_t n = it.node;
        if (n >= t->node_slots || seen[n])
            return tt_af_bad(ctx, f, "node %u is out of range or reached twice", n);
        seen[n] = 1;
        if (it.depth > TT_KD_MAX_DEPTH)
            return tt_af_bad(ctx, f, "node %u is deeper than %d levels", n, TT_KD_MAX_DEPTH);
        const uint32_t bits = t->nodes[n].bits;
        if (tt_kd_is_leaf(bits)) {
            /* a leaf root (a tiny scene) still has record 0, the scene box,
             * without a slot (kd_check.c checks the same) */
            if (n == 0) {
                if (t->aug_count == 0 || t->aug[0].node != 0 || t->aug[0].parent != TT_KD_NO_PARENT)
                    return tt_af_bad(ctx, f, "the root has no box");
                aug_seen++;
            }
            const uint64_t first = t->nodes[n].u.first, count = tt_kd_leaf_count(bits);
            if (first + count > t->ref_count)
                return tt_af_bad(ctx, f, "leaf %u: references %llu..%llu of %zu", n,
                                 (unsigned long long)first, (unsigned long long)(first + count),
                                 t->ref_count);
            continue;
        }
        uint32_t aug = it.aug;
        if (tt_kd_is_aug(bits)) {
            if (n + 1 >= t->node_slots || seen[n + 1])
                return tt_af_bad(ctx, f, "node %u: its box slot is missing", n);
            seen[n + 1] = 1;
            const uint32_t rec = t->nodes[n + 1].u.first;
            if (rec >= t->aug_count || t->aug[rec].node != n || t->aug[rec].parent != it.aug)
                return tt_af_bad(ctx, f, "node %u: box record %u does not belong to it", n, rec);
            aug = rec;
            aug_seen++;
        } else if (n == 0) {
            return tt_af_bad(ctx, f, "the root has no box");
        }
        const uint32_t left = tt_kd_left(n, bits), right = tt_kd_right(bits);
        if (right <= left || right >= t->node_slots || left >= t->node_slots)
            return tt_af_bad(ctx, f, "node %u: children %u and %u of %u slots", n, left, right,
                             t->node_slots);
        stack[sp++] = (walk_item){right, it.depth + 1, aug};
        stack[sp++] = (walk_item){left, it.depth + 1, aug};
    }
    if (aug_seen != t->aug_count)
        return tt_af_bad(ctx, f, "%u box records, %u reached", t->aug_count, aug_seen);
    for (size_t i = 0; i < t->ref_count; i++)
        if (t->refs[i] >= T)
            return tt_af_bad(ctx, f, "reference %zu names triangle %u of %u", i, t->refs[i], T);
    return TT_OK;
}

tt_status kd_io_load(tt_accel *a, const tt_af_file *f)
{
    tt_context *ctx = a->ctx;
    if (f->h->layout != KD_IO_LAYOUT || f->h->layout_version != KD_IO_VERSION)
        return tt_error(ctx, TT_ERR_UNSUPPORTED,
                        "%s: kd-tree layout %u version %u; this library reads layout %u version "
                        "%u: rebuild the structure", f->name, f->h->layout, f->h->layout_version,
                        KD_IO_LAYOUT, KD_IO_VERSION);
    const double *p;
    const void *nodes, *refs, *aug;
    uint64_t n_nodes, n_refs, n_aug;
    tt_status st = tt_af_get_n(ctx, f, TT_AF_SEC_PARAMS, 8, P_COUNT, (const void **)&p);
    if (st == TT_OK) st = tt_af_get(ctx, f, TT_AF_SEC_KD_NODES, sizeof(tt_kd_node), &nodes, &n_nodes);
    if (st == TT_OK) st = tt_af_get(ctx, f, TT_AF_SEC_KD_REFS, 4, &refs, &n_refs);
    if (st == TT_OK) st = tt_af_get(ctx, f, TT_AF_SEC_KD_AUG, sizeof(tt_kd_aug), &aug, &n_aug);
    if (st != TT_OK) return st;
    if (n_nodes < 1 || n_nodes >= TT_KD_MAX_NODES || n_aug < 1 || n_aug > n_nodes ||
        n_refs >= ((uint64_t)1 << 32) || !(p[P_MAX_DEPTH] >= 0 && p[P_MAX_DEPTH] <= TT_KD_MAX_DEPTH) ||
        (p[P_EMPTY] != 0 && p[P_EMPTY] != 1) || p[P_DMIN] != a->options.kdtree.dmin)
        return tt_af_bad(ctx, f, "%llu nodes, %llu references, %llu boxes, or the parameters: "
                         "out of range", (unsigned long long)n_nodes, (unsigned long long)n_refs,
                         (unsigned long long)n_aug);
    /* every scalar converted to an integer below must fit it (a hostile
     * file's 1e300 would make the conversion undefined; found by fuzz_accel) */
    static const int counts[] = {P_BUDGET_HIT, P_LOOSE, P_NODES_TOTAL, P_INTERIOR, P_LEAVES,
                                 P_EMPTY_LEAVES, P_DEPTH_MAX};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++)
        if (!(p[counts[i]] >= 0 && p[counts[i]] < 2147483647.0))
            return tt_af_bad(ctx, f, "parameter %d is out of range", counts[i]);
    tt_kdtree *t = tt_calloc(ctx, 1, sizeof *t);
    if (!t) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", f->name);
    a->impl = t;
    /* the arrays are the file's, read-only; the structure never writes them */
    t->nodes = (tt_kd_node *)nodes;
    t->node_slots = (uint32_t)n_nodes;
    t->refs = (uint32_t *)refs;
    t->ref_count = (size_t)n_refs;
    t->aug = (tt_kd_aug *)aug;
    t->aug_count = (uint32_t)n_aug;
    t->dmin = (int)p[P_DMIN];
    t->max_depth = (int)p[P_MAX_DEPTH];
    t->ref_budget_hit = (int)p[P_BUDGET_HIT];
    t->loose_refs = (int)p[P_LOOSE];
    t->cost_traversal = p[P_CT];
    t->cost_intersect = p[P_CI];
    t->empty_factor = p[P_EMPTY_FACTOR];
    t->nodes_total = (uint32_t)p[P_NODES_TOTAL];
    t->interior = (uint32_t)p[P_INTERIOR];
    t->leaves = (uint32_t)p[P_LEAVES];
    t->empty_leaves = (uint32_t)p[P_EMPTY_LEAVES];
    t->depth_max = (int)p[P_DEPTH_MAX];
    t->depth_mean = p[P_DEPTH_MEAN];
    t->sah_cost = p[P_SAH];
    t->view.nodes = t->nodes;
    t->view.refs = t->refs;
    t->view.tri = a->scene->tri;
    t->view.aug = t->aug;
    t->view.aug_count = t->aug_count;
    t->view.empty = p[P_EMPTY] != 0;
    uint8_t *seen = tt_calloc(ctx, t->node_slots, 1);
    if (!seen) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", f->name);
    st = walk(ctx, f, t, (uint32_t)a->scene->triangle_count, seen);
    tt_free(ctx, seen);
    t->fast_view = t->view;
    /* The leaf blocks are the engine's, not the file's: rebuilt here. */
    if (st == TT_OK) st = tt_kdtree_use_isa(ctx, t, a->isa, a->scene->tri, a->scene->triangle_count);
    return st;
}

void kd_io_unload(tt_accel *a)
{
    if (a->impl) tt_kdtree_blocks_free(a->ctx, a->impl); /* the engine's own copy */
    tt_free(a->ctx, a->impl); /* the other arrays are the file's */
    a->impl = NULL;
}
