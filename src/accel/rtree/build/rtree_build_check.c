/* Invariants of the pointer tree during and after construction; used by the
 * white-box tests after every insertion (the packed tree has its own check
 * in rtree_check.c). */
#include <string.h>

#include "accel/rtree/rtree_box.h"
#include "accel/rtree/build/rtree_build.h"

typedef struct walk {
    const rt_builder *b;
    uint8_t *seen; /* per triangle id */
    uint32_t triangles;
    uint32_t nodes;
} walk;

#define FAIL(...) tt_error(w->b->ctx, TT_ERR_INVARIANT, __VA_ARGS__)

static tt_status check_node(walk *w, uint32_t n, int level)
{
    const rt_builder *b = w->b;
    if (n >= b->node_count) return FAIL("rtree build: node index %u out of the pool", n);
    if (++w->nodes > b->node_count)
        return FAIL("rtree build: the tree has a cycle (more nodes reached than exist)");
    const rt_node_hdr *h = &b->hdr[n];
    const int cnt = h->count;
    if (h->level != level)
        return FAIL("rtree build: node %u is on level %d, expected %d (leaves not all on level 0)",
                    n, h->level, level);
    if (n == b->root) {
        int lo = level > 0 ? 2 : 0;
        if (cnt < lo || cnt > b->M)
            return FAIL("rtree build: root %u holds %d entries, expected %d..%d", n, cnt, lo,
                        b->M);
    } else if (cnt < b->m || cnt > b->M) {
        return FAIL("rtree build: node %u (level %d) holds %d entries, expected %d..%d", n, level,
                    cnt, b->m, b->M);
    }
    const float *s = rt_node_box(b, n);
    const uint32_t *ch = rt_node_child(b, n);
    for (int i = 0; i < cnt; i++) {
        float eb[6], want[6];
        rt_soa_get(s, b->cap, i, eb);
        if (level == 0) {
            uint32_t t = ch[i];
            if (t >= w->triangles)
                return FAIL("rtree build: leaf %u entry %d holds triangle %u, beyond the %u "
                            "inserted", n, i, t, w->triangles);
            if (w->seen[t]++)
                return FAIL("rtree build: triangle %u is stored twice (again in leaf %u)", t, n);
            memcpy(want, b->tri_box + 6 * (size_t)t, sizeof want);
        } else {
            uint32_t c = ch[i];
            if (c >= b->node_count)
                return FAIL("rtree build: node %u entry %d points outside the pool", n, i);
            if (b->hdr[c].parent != n || b->hdr[c].slot != i)
                return FAIL("rtree build: node %u's parent link says (%u, %d), it is entry %d of "
                            "node %u", c, b->hdr[c].parent, b->hdr[c].slot, i, n);
            rt_node_bounds(b, c, want);
            tt_status st = check_node(w, c, level - 1);
            if (st != TT_OK) return st;
        }
        if (!rt_box_equal(eb, want))
            return FAIL("rtree build: node %u entry %d: box is not the exact union of its "
                        "content", n, i);
    }
    return TT_OK;
}

tt_status rt_builder_check(const rt_builder *b)
{
    walk w = {b, NULL, b->triangles, 0};
    w.seen = tt_calloc(b->ctx, b->triangles ? b->triangles : 1, 1);
    if (!w.seen) return tt_error(b->ctx, TT_ERR_OUT_OF_MEMORY, "rtree build check: out of memory");
    tt_status st;
    if (b->hdr[b->root].parent != TT_INVALID_ID)
        st = tt_error(b->ctx, TT_ERR_INVARIANT, "rtree build: the root %u has a parent", b->root);
    else st = check_node(&w, b->root, b->hdr[b->root].level);
    if (st == TT_OK) {
        for (uint32_t t = 0; t < b->triangles; t++)
            if (!w.seen[t]) {
                st = tt_error(b->ctx, TT_ERR_INVARIANT, "rtree build: triangle %u is missing", t);
                break;
            }
    }
    if (st == TT_OK && w.nodes != b->node_count)
        st = tt_error(b->ctx, TT_ERR_INVARIANT,
                      "rtree build: %u of the %u pool nodes are not in the tree", b->node_count - w.nodes,
                      b->node_count);
    tt_free(b->ctx, w.seen);
    return st;
}
