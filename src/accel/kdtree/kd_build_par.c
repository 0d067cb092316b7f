/* The parallel builds' shared parts (see kd_build_par.h). */
#include "accel/kdtree/kd_build_par.h"

#include <omp.h>
#include <string.h>

uint32_t kd_par_cutoff = 4096;

int kd_par_threads(tt_context *ctx)
{
    int t = tt_context_threads(ctx);
    return t > 0 ? t : omp_get_max_threads();
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

static tt_status replay(kd_builder *b, kd_sub *s, const tt_aabb *cell, const kd_place *here)
{
    if (s->split.axis < 0) return replay_nodes(b, &s->out, 0, cell, here);
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
