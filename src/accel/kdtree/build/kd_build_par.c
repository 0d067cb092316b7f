/* The parallel builds' shared parts (see kd_build_par.h). */
#include "accel/kdtree/build/kd_build_par.h"

#include <string.h>

uint32_t kd_par_cutoff = 4096;

int kd_par_threads(tt_context *ctx)
{
    return tt_context_team(ctx);
}

int kd_par_account(kd_builder *b, uint32_t n, const kd_split *best)
{
    const size_t after = (size_t)best->n_left + best->n_right;
    const size_t add = after > n ? after - n : 0;
    size_t g;
#pragma omp atomic capture
    g = b->par->growth += add;
    if (b->par->m + g > b->ref_budget) {
#pragma omp atomic write
        b->par->abort = 1;
    }
    return 1;
}

int kd_par_aborted(const kd_builder *b)
{
    if (!b->par) return 0;
    int a;
#pragma omp atomic read
    a = b->par->abort;
    return a;
}

kd_sub *kd_sub_new(const kd_builder *b)
{
    kd_sub *s = tt_calloc(b->ctx, 1, sizeof *s);
    if (!s) return NULL;
    s->split.axis = -1;
    s->out = *b;
    s->out.nodes = NULL;
    s->out.node_count = s->out.node_cap = 0;
    s->out.refs = NULL;
    s->out.ref_count = s->out.ref_cap = 0;
    s->out.aug = NULL;
    s->out.aug_count = s->out.aug_cap = 0;
    s->out.live = 0;
    s->st = TT_OK;
    return s;
}

void kd_sub_free(tt_context *ctx, kd_sub *s)
{
    if (!s) return;
    kd_sub_free(ctx, s->kid[0]);
    kd_sub_free(ctx, s->kid[1]);
    tt_free(ctx, s->out.nodes);
    tt_free(ctx, s->out.refs);
    tt_free(ctx, s->out.aug);
    tt_free(ctx, s);
}

kd_place kd_child_place(const kd_builder *b, const kd_place *here)
{
    const int aug = here->depth == 0 || (b->dmin > 0 && here->aug_dist >= b->dmin);
    kd_place c = {here->depth + 1, aug ? 1 : here->aug_dist + 1, TT_KD_NO_PARENT};
    return c;
}

/* One serially built subtree, from its local node i. */
static tt_status replay_nodes(kd_builder *b, kd_builder *sub, uint32_t i, const tt_aabb *cell,
                              const kd_place *here)
{
    const tt_kd_node x = sub->nodes[i];
    if (tt_kd_is_leaf(x.bits)) {
        const uint32_t n = tt_kd_leaf_count(x.bits);
        /* A subtree of empty leaves has no reference array. */
        return kd_emit_leaf(b, n ? sub->refs + x.u.first : NULL, n);
    }
    kd_split s = {tt_kd_axis(x.bits), x.u.split, 0, 0.0, 0, 0};
    uint32_t me;
    kd_place child;
    tt_status st = kd_emit_interior(b, &s, cell, here, &me, &child);
    if (st != TT_OK) return st;
    tt_aabb l, r;
    kd_split_cell(cell, &s, &l, &r);
    st = replay_nodes(b, sub, tt_kd_left(i, x.bits), &l, &child);
    if (st != TT_OK) return st;
    kd_link_right(b, me);
    return replay_nodes(b, sub, tt_kd_right(x.bits), &r, &child);
}

/* A serially built subtree below the root, appended whole: the serial
 * build would emit its nodes, references and sparse boxes in the order the
 * subtree's own build did (depth first), so only indices move: the
 * references' first, the right-child links and the boxes' records by where
 * the subtree lands, and a box record's parent outside the subtree (none
 * in it) becomes the subtree's. The subtree was built at its real place
 * (depth and distance to the nearest box), so its boxes are where the
 * serial build puts them. Much faster than re-emitting node by node, which
 * ran alone at the end of a parallel build. */
static tt_status append_subtree(kd_builder *b, kd_builder *sub, const tt_aabb *cell,
                                const kd_place *here)
{
    const uint32_t node_off = b->node_count, aug_off = b->aug_count;
    const size_t ref_off = b->ref_count;
    /* kd_replay sized the arrays unless the tree passes the layout's
     * limits: then the node by node emission reports which. */
    if ((size_t)node_off + sub->node_count > b->node_cap || ref_off + sub->ref_count > b->ref_cap ||
        ref_off + sub->ref_count > UINT32_MAX)
        return replay_nodes(b, sub, 0, cell, here);
    if (sub->aug_count > b->aug_cap - b->aug_count) {
        uint32_t cap = b->aug_cap ? b->aug_cap : 256;
        while (cap - b->aug_count < sub->aug_count) cap *= 2;
        tt_kd_aug *p = tt_realloc_array(b->ctx, b->aug, cap, sizeof *p);
        if (!p) return kd_oom(b);
        b->aug = p;
        b->aug_cap = cap;
    }
    tt_kd_node *out = b->nodes + node_off;
    for (uint32_t i = 0; i < sub->node_count; i++) {
        tt_kd_node x = sub->nodes[i];
        if (tt_kd_is_leaf(x.bits)) {
            x.u.first += (uint32_t)ref_off;
        } else {
            x.bits += node_off << 3; /* the right child's index */
            if (tt_kd_is_aug(x.bits)) {
                /* The extension slot behind it holds the box's record. */
                out[i] = x;
                i++;
                x = sub->nodes[i];
                x.u.first += aug_off;
            }
        }
        out[i] = x;
    }
    if (sub->ref_count) memcpy(b->refs + ref_off, sub->refs, sub->ref_count * sizeof *b->refs);
    for (uint32_t r = 0; r < sub->aug_count; r++) {
        tt_kd_aug a = sub->aug[r];
        a.node += node_off;
        a.parent = a.parent == TT_KD_NO_PARENT ? here->parent_aug : a.parent + aug_off;
        b->aug[aug_off + r] = a;
    }
    b->node_count += sub->node_count;
    b->ref_count += sub->ref_count;
    b->aug_count += sub->aug_count;
    return TT_OK;
}

static tt_status replay(kd_builder *b, kd_sub *s, const tt_aabb *cell, const kd_place *here)
{
    if (s->split.axis < 0) {
        /* The root itself (its box is record 0, made before the build) is
         * re-emitted node by node. */
        if (here->depth == 0) return replay_nodes(b, &s->out, 0, cell, here);
        return append_subtree(b, &s->out, cell, here);
    }
    uint32_t me;
    kd_place child;
    tt_status st = kd_emit_interior(b, &s->split, cell, here, &me, &child);
    if (st != TT_OK) return st;
    tt_aabb l, r;
    kd_split_cell(cell, &s->split, &l, &r);
    st = replay(b, s->kid[0], &l, &child);
    if (st != TT_OK) return st;
    kd_link_right(b, me);
    return replay(b, s->kid[1], &r, &child);
}

/* Node slots and references of all results: the final arrays are made
 * that large at once instead of growing by doubling. */
static void totals(const kd_sub *s, size_t *nodes, size_t *refs)
{
    if (s->split.axis < 0) {
        *nodes += s->out.node_count;
        *refs += s->out.ref_count;
        return;
    }
    *nodes += 2;
    totals(s->kid[0], nodes, refs);
    totals(s->kid[1], nodes, refs);
}

tt_status kd_replay(kd_builder *b, kd_sub *root, const tt_aabb *cell)
{
    size_t nodes = 0, refs = 0;
    totals(root, &nodes, &refs);
    if (nodes < TT_KD_MAX_NODES && nodes > b->node_cap) {
        tt_kd_node *p = tt_realloc_array(b->ctx, b->nodes, nodes, sizeof *p);
        if (!p) return kd_oom(b);
        b->nodes = p;
        b->node_cap = (uint32_t)nodes;
    }
    if (refs > b->ref_cap) {
        uint32_t *p = tt_realloc_array(b->ctx, b->refs, refs ? refs : 1, sizeof *p);
        if (!p) return kd_oom(b);
        b->refs = p;
        b->ref_cap = refs ? refs : 1;
    }
    kd_place here = {0, 0, TT_KD_NO_PARENT};
    return replay(b, root, cell, &here);
}
