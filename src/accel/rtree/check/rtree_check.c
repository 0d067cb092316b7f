/* Invariants of the packed R-tree (the pointer tree is gone by now, so the
 * tree is re-read from the array by an explicit recursive walk using the
 * stored counts):
 *  1. the index formulas n_e, n_p, chi and Delta_L agree with an explicit
 *     level-by-level enumeration of the complete M-ary tree's slots;
 *  2. from the root, every node's entries are its first `count` child
 *     slots, present (finite boxes), all leaves are on level 0, every
 *     non-root node holds m..M entries (the root 2..M, or 0..M if it is a
 *     leaf: fewer than 2 triangles, or few enough to fit one leaf);
 *  3. every node box is exactly the union of its entries' boxes (child
 *     boxes, or the boxes of the leaf's triangles);
 *  4. every slot the walk does not reach is empty (the +inf mark, count 0,
 *     an empty triangle range);
 *  5. the leaf ranges are prefix sums over all leaf slots, covering the
 *     triangle array exactly; every triangle id occurs exactly once and its
 *     9 floats equal the scene's. */
#include <string.h>

#include "accel/rtree/rtree.h"
#include "accel/rtree/rtree_box.h"

typedef struct walk {
    tt_context *ctx;
    const rt_tree *t;
    const tt_scene *scene;
    uint8_t *reached; /* bit per slot */
    uint8_t *seen;    /* per triangle id */
} walk;

#define FAIL(...) tt_error(w->ctx, TT_ERR_INVARIANT, __VA_ARGS__)

static void slot_box(const tt_rtree_packed *p, uint32_t n, float out[6])
{
    uint32_t pos;
    const float *g = tt_rt_group(p, n, &pos);
    for (int k = 0; k < 6; k++) out[k] = g[k * p->M + pos];
}

/* 1: Delta_L, n_e, n_p and chi against a plain enumeration of slot ids. */
static tt_status check_index_formulas(walk *w)
{
    const tt_rtree_packed *p = &w->t->p;
    uint64_t next = 1, level_first = 0, level_size = 1;
    if (p->delta[p->L] != 0) return FAIL("rtree: Delta_L(L) = %u, expected 0", p->delta[p->L]);
    for (uint32_t l = p->L; l >= 1; l--) {
        const uint64_t child_first = next;
        if (p->delta[l - 1] != child_first)
            return FAIL("rtree: Delta_L(%u) = %u, but level %u starts at slot %llu", l - 1,
                        p->delta[l - 1], l - 1, (unsigned long long)child_first);
        for (uint64_t s = level_first; s < level_first + level_size; s++) {
            const uint32_t e = tt_rt_first_child(p, (uint32_t)s, l);
            for (uint32_t i = 0; i < p->M; i++) {
                const uint32_t c = (uint32_t)next++;
                if (e + i != c)
                    return FAIL("rtree: n_e(%llu) + %u = %u, but that child is slot %u",
                                (unsigned long long)s, i, e + i, c);
                if (tt_rt_parent(p, c, l - 1) != s)
                    return FAIL("rtree: n_p(%u) = %u, expected %llu", c, tt_rt_parent(p, c, l - 1),
                                (unsigned long long)s);
                if (tt_rt_chi(p, c, l - 1) != i)
                    return FAIL("rtree: chi(%u) = %u, expected %u", c, tt_rt_chi(p, c, l - 1), i);
            }
        }
        level_first = child_first;
        level_size = next - child_first;
    }
    if (next != p->slots)
        return FAIL("rtree: the enumeration found %llu slots, the tree says N = %u",
                    (unsigned long long)next, p->slots);
    if (level_size != p->leaf_slots)
        return FAIL("rtree: %llu leaf slots enumerated, the tree says %u",
                    (unsigned long long)level_size, p->leaf_slots);
    return TT_OK;
}

/* 2, 3, 5: the recursive walk from slot n on level l; *box gets the union
 * of n's content for the caller's comparison. */
static tt_status check_node(walk *w, uint32_t n, uint32_t l, float box[6])
{
    const rt_tree *t = w->t;
    const tt_rtree_packed *p = &t->p;
    w->reached[n >> 3] |= (uint8_t)(1u << (n & 7));
    const int is_root = n == 0;
    uint32_t cnt;
    if (l > 0) cnt = p->count[n];
    else {
        uint32_t j = n - p->delta[0];
        if (p->leaf_start[j + 1] < p->leaf_start[j])
            return FAIL("rtree: leaf slot %u has a negative triangle range", n);
        cnt = p->leaf_start[j + 1] - p->leaf_start[j];
    }
    uint32_t lo = is_root ? (l > 0 ? 2u : 0u) : (uint32_t)t->m;
    if (cnt < lo || cnt > p->M)
        return FAIL("rtree: %s slot %u on level %u holds %u entries, expected %u..%u",
                    is_root ? "root" : "node", n, l, cnt, lo, p->M);
    rt_box_empty(box);
    if (l > 0) {
        const uint32_t e = tt_rt_first_child(p, n, l);
        for (uint32_t i = 0; i < p->M; i++) {
            float cb[6];
            slot_box(p, e + i, cb);
            if (i >= cnt) {
                if (!rt_box_is_empty_mark(cb))
                    return FAIL("rtree: slot %u (entry %u of node %u, which holds %u) is not "
                                "marked empty", e + i, i, n, cnt);
                continue;
            }
            if (!rt_box_is_finite(cb))
                return FAIL("rtree: slot %u (entry %u of node %u) has no valid box", e + i, i, n);
            float content[6];
            tt_status st = check_node(w, e + i, l - 1, content);
            if (st != TT_OK) return st;
            if (!rt_box_equal(cb, content))
                return FAIL("rtree: the box of slot %u (level %u) is not the exact union of its "
                            "entries", e + i, l - 1);
            rt_box_grow(box, cb);
        }
    } else {
        const uint32_t j = n - p->delta[0];
        for (uint32_t k = p->leaf_start[j]; k < p->leaf_start[j + 1]; k++) {
            if (k >= p->triangles)
                return FAIL("rtree: leaf slot %u refers to triangle %u of %u", n, k, p->triangles);
            const uint32_t id = p->prim[k];
            if (id >= w->scene->triangle_count)
                return FAIL("rtree: leaf slot %u holds triangle id %u, the scene has %zu", n, id,
                            w->scene->triangle_count);
            if (w->seen[id]++)
                return FAIL("rtree: triangle %u is stored twice (again in leaf slot %u)", id, n);
            const float *v = p->tri + 9 * (size_t)k;
            if (memcmp(v, w->scene->tri + 9 * (size_t)id, 9 * sizeof(float)) != 0)
                return FAIL("rtree: leaf slot %u: the stored vertices of triangle %u differ from "
                            "the scene's", n, id);
            for (int c = 0; c < 3; c++) {
                for (int a = 0; a < 3; a++) {
                    box[a] = rt_min(box[a], v[3 * c + a]);
                    box[a + 3] = rt_max(box[a + 3], v[3 * c + a]);
                }
            }
        }
    }
    return TT_OK;
}

tt_status rt_check(tt_context *ctx, const rt_tree *t, const tt_scene *scene)
{
    const tt_rtree_packed *p = &t->p;
    walk w = {ctx, t, scene, NULL, NULL};
    if (p->triangles != scene->triangle_count)
        return tt_error(ctx, TT_ERR_INVARIANT, "rtree: %u triangles packed, the scene has %zu",
                        p->triangles, scene->triangle_count);
    w.reached = tt_calloc(ctx, (size_t)p->slots / 8 + 1, 1);
    w.seen = tt_calloc(ctx, scene->triangle_count ? scene->triangle_count : 1, 1);
    tt_status st = TT_OK;
    if (!w.reached || !w.seen) st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree check: out of memory");
    if (st == TT_OK) st = check_index_formulas(&w);
    if (st == TT_OK && (p->leaf_start[0] != 0 || p->leaf_start[p->leaf_slots] != p->triangles))
        st = tt_error(ctx, TT_ERR_INVARIANT,
                      "rtree: the leaf ranges cover [%u, %u), expected [0, %u)", p->leaf_start[0],
                      p->leaf_start[p->leaf_slots], p->triangles);
    float root[6];
    slot_box(p, 0, root);
    if (st == TT_OK && p->triangles == 0) {
        if (!rt_box_is_empty_mark(root) || p->L != 0)
            st = tt_error(ctx, TT_ERR_INVARIANT, "rtree: an empty tree must be one empty leaf");
    } else if (st == TT_OK) {
        float content[6];
        if (!rt_box_is_finite(root))
            st = tt_error(ctx, TT_ERR_INVARIANT, "rtree: the root slot has no valid box");
        if (st == TT_OK) st = check_node(&w, 0, p->L, content);
        if (st == TT_OK && !rt_box_equal(root, content))
            st = tt_error(ctx, TT_ERR_INVARIANT,
                          "rtree: the root box is not the exact union of its entries");
        for (uint32_t id = 0; st == TT_OK && id < p->triangles; id++)
            if (!w.seen[id])
                st = tt_error(ctx, TT_ERR_INVARIANT, "rtree: triangle %u is not in the tree", id);
    }
    /* 4: every slot the walk did not reach is empty. */
    for (uint32_t n = 0; st == TT_OK && n < p->slots; n++) {
        if (w.reached[n >> 3] & (1u << (n & 7))) continue;
        float b[6];
        slot_box(p, n, b);
        int bad = !rt_box_is_empty_mark(b);
        if (n < p->delta[0]) bad |= p->count[n] != 0;
        else bad |= p->leaf_start[n - p->delta[0]] != p->leaf_start[n - p->delta[0] + 1];
        if (bad)
            st = tt_error(ctx, TT_ERR_INVARIANT,
                          "rtree: slot %u is not in the tree but is not marked empty", n);
    }
    tt_free(ctx, w.reached);
    tt_free(ctx, w.seen);
    return st;
}
