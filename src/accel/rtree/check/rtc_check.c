/* Invariants of the compact layout (rtc_layout.h), re-read from the arrays
 * by a walk from the root:
 *  1. the header: M, the row stride and record size agree; the root is
 *     node 0 without a parent, on level `height`;
 *  2. every node is reached exactly once; its level is its parent's minus
 *     one (so all leaves are on one level); it holds m..M entries (the root
 *     up to M); its unused child lanes are the +inf mark with no
 *     reference; its interior children are consecutive nodes whose parent
 *     link names it;
 *  3. every child box is finite and exactly the union of the child's
 *     content (child boxes, or the leaf's triangles' vertices); level-1
 *     entries are leaf references, the others node references;
 *  4. leaves: m..M triangles (the root's only leaf may hold fewer) in
 *     lanes inside the block array that no other leaf holds, a node's
 *     leaves within 2 M blocks from its first leaf's (the traversal keeps a
 *     64-bit set of the node's tested blocks); every triangle
 *     id exactly once, its lanes the scene's vertices (NaN for a zero-area
 *     triangle, as tt_tri_block_pack writes them); lanes of no leaf NaN
 *     with no id;
 *  5. records the walk does not reach are free (tt_rtc_is_free): the slack
 *     of a layout updated in place (rtree/update/).
 * A tree built with split references (rtc_tree.split) differs in 3 and 4:
 * a triangle may sit in several leaves, once in each; a leaf's box lies
 * inside the union of its triangles' boxes and meets each of them, and the
 * parts of a triangle's box inside its leaves' boxes make up the whole
 * triangle box (a necessary condition for the pieces to cover the
 * triangle); leaves hold 1..M triangles.
 * Mixed records (the wide BVH's, wbvh/wbvh.h: the root's level field 0):
 * every record says level 0 and lies at most `height` records deep; its
 * leaf entries come first, its node entries after them (consecutive
 * nodes), and the leaf span rule of 4 holds for its leaves.
 */
#include <math.h>
#include <string.h>

#include "accel/rtree/rtc.h"
#include "accel/rtree/rtree_box.h"

typedef struct walk {
    tt_context *ctx;
    const rtc_tree *t;
    const tt_scene *scene;
    uint8_t *reached; /* per node */
    uint8_t *seen;    /* per triangle id */
    uint8_t *lane_owned; /* per triangle lane of the blocks */
    float *cover;        /* split trees: per triangle, its box's part in its leaves */
    int mixed;           /* mixed records: levels count down the depth left */
} walk;

#define FAIL(...) tt_error(w->ctx, TT_ERR_INVARIANT, __VA_ARGS__)

/* The intersection of two boxes into out; 0 when they do not meet. */
static int box_meet(const float a[6], const float b[6], float out[6])
{
    for (int k = 0; k < 3; k++) {
        out[k] = rt_max(a[k], b[k]);
        out[k + 3] = rt_min(a[k + 3], b[k + 3]);
        if (out[k] > out[k + 3]) return 0;
    }
    return 1;
}

/* 4: the leaf `ref` (entry i of node n, whose box is lb); *box gets its
 * triangles' union. */
static tt_status check_leaf(walk *w, uint32_t n, uint32_t i, uint32_t ref, int lone,
                            const float lb[6], float box[6])
{
    const tt_rtc *c = &w->t->c;
    uint32_t nb;
    (void)tt_rtc_leaf_blocks(c, ref, &nb);
    const uint64_t first =
        (uint64_t)tt_rtc_leaf_block(ref) * TT_TRI_BLOCK_W + tt_rtc_leaf_lane(ref);
    const uint32_t cnt = tt_rtc_leaf_count(ref);
    if (!tt_rtc_is_leaf(ref))
        return FAIL("rtree compact: entry %u of node %u (level 1) is not tagged a leaf", i, n);
    if ((uint64_t)tt_rtc_leaf_block(ref) + nb > c->blocks)
        return FAIL("rtree compact: leaf %u of node %u runs past the %u blocks", i, n, c->blocks);
    const uint32_t lo = lone ? 1u : (uint32_t)w->t->m;
    if (cnt < lo || cnt > c->M)
        return FAIL("rtree compact: leaf %u of node %u holds %u triangles, expected %u..%u", i, n,
                    cnt, lo, c->M);
    rt_box_empty(box);
    for (uint32_t k = 0; k < cnt; k++) {
        const uint64_t g = first + k;
        const tt_tri_block *bk = &c->block[g / TT_TRI_BLOCK_W];
        const uint32_t l = (uint32_t)(g % TT_TRI_BLOCK_W);
        if (w->lane_owned[g]++)
            return FAIL("rtree compact: leaf %u of node %u claims lane %llu, which another "
                        "leaf holds", i, n, (unsigned long long)g);
        const uint32_t id = bk->prim[l];
        if (id >= w->scene->triangle_count)
            return FAIL("rtree compact: leaf %u of node %u holds triangle id %u, the scene has "
                        "%zu", i, n, id, w->scene->triangle_count);
        if (w->cover) { /* split: once in this leaf, maybe in others */
            for (uint32_t q = 0; q < k; q++)
                if (c->block[(first + q) / TT_TRI_BLOCK_W].prim[(first + q) % TT_TRI_BLOCK_W] == id)
                    return FAIL("rtree compact: triangle %u is stored twice in leaf %u of node %u",
                                id, i, n);
            if (w->seen[id] < 255) w->seen[id]++;
        } else if (w->seen[id]++) {
            return FAIL("rtree compact: triangle %u is stored twice (again in leaf %u of node "
                        "%u)", id, i, n);
        }
        const float *v = w->scene->tri + 9 * (size_t)id;
        const int dead = tt_tri_is_degenerate(v, v + 3, v + 6);
        for (int q = 0; q < 9; q++) {
            const float s = bk->v[q][l];
            if (dead ? !isnan(s) : memcmp(&s, &v[q], sizeof s) != 0)
                return FAIL("rtree compact: leaf %u of node %u: the stored vertices of triangle "
                            "%u differ from the scene's", i, n, id);
        }
        float tb[6];
        rt_box_of_triangle(v, tb);
        rt_box_grow(box, tb);
        if (w->cover) {
            float part[6];
            if (!box_meet(lb, tb, part))
                return FAIL("rtree compact: the box of leaf %u of node %u misses triangle %u's",
                            i, n, id);
            rt_box_grow(w->cover + 6 * (size_t)id, part);
        }
    }
    return TT_OK;
}

/* 4: lanes no leaf holds are unused: NaN, no id. */
static tt_status check_free_lanes(walk *w)
{
    const tt_rtc *c = &w->t->c;
    for (uint64_t g = 0; g < (uint64_t)c->blocks * TT_TRI_BLOCK_W; g++) {
        if (w->lane_owned[g]) continue;
        const tt_tri_block *bk = &c->block[g / TT_TRI_BLOCK_W];
        const uint32_t l = (uint32_t)(g % TT_TRI_BLOCK_W);
        int bad = bk->prim[l] != TT_INVALID_ID;
        for (int q = 0; q < 9; q++) bad |= !isnan(bk->v[q][l]);
        if (bad)
            return FAIL("rtree compact: lane %llu is in no leaf but is not marked unused",
                        (unsigned long long)g);
    }
    return TT_OK;
}

/* 2, 3: node n on level l; *box gets the union of its entries. */
static tt_status check_node(walk *w, uint32_t n, uint32_t l, uint32_t parent, float box[6])
{
    const tt_rtc *c = &w->t->c;
    if (n >= c->nodes) return FAIL("rtree compact: node %u of %u does not exist", n, c->nodes);
    if (w->reached[n]++) return FAIL("rtree compact: node %u is reached twice", n);
    const float *rec = tt_rtc_node(c, n);
    const uint32_t *ref = tt_rtc_child(c, rec);
    const uint32_t cnt = tt_rtc_count(c, rec), is_root = n == 0;
    if (w->mixed ? tt_rtc_level(c, rec) != 0 || l == 0 : tt_rtc_level(c, rec) != l)
        return FAIL("rtree compact: node %u says level %u, its place in the tree is level %u%s",
                    n, tt_rtc_level(c, rec), l, w->mixed ? " (mixed records: 0, depth left)" : "");
    if (tt_rtc_parent(c, rec) != parent)
        return FAIL("rtree compact: node %u links to parent %u, its parent is %u", n,
                    tt_rtc_parent(c, rec), parent);
    const uint32_t lo = is_root ? 0u : (uint32_t)w->t->m;
    if (cnt < lo || cnt > c->M)
        return FAIL("rtree compact: %s %u on level %u holds %u entries, expected %u..%u",
                    is_root ? "root" : "node", n, l, cnt, lo, c->M);
    /* the stack traversal's per-node block set needs the first leaf's
     * block lowest and every other within 2 M blocks of it */
    uint32_t leaves = l == 1 ? cnt : 0; /* the leading leaf entries */
    if (w->mixed)
        while (leaves < cnt && tt_rtc_is_leaf(ref[leaves])) leaves++;
    for (uint32_t i = 0; i < leaves; i++)
        if (tt_rtc_leaf_block(ref[i]) < tt_rtc_leaf_block(ref[0]) ||
            tt_rtc_leaf_block(ref[i]) - tt_rtc_leaf_block(ref[0]) + 2 > 2 * c->M)
            return FAIL("rtree compact: leaf %u of node %u starts at block %u, outside the "
                        "node's span from block %u", i, n, tt_rtc_leaf_block(ref[i]),
                        tt_rtc_leaf_block(ref[0]));
    for (uint32_t i = leaves; i < cnt; i++)
        if (tt_rtc_is_leaf(ref[i]) || ref[i] != ref[leaves] + i - leaves || ref[leaves] == n)
            return FAIL("rtree compact: the children of node %u are not consecutive nodes "
                        "(entry %u is node %u)", n, i, ref[i]);
    rt_box_empty(box);
    for (uint32_t i = 0; i < c->S; i++) {
        float cb[6];
        rtc_child_box(c, rec, i, cb);
        if (i >= cnt) {
            if (!rt_box_is_empty_mark(cb) || ref[i] != TT_INVALID_ID)
                return FAIL("rtree compact: entry %u of node %u (which holds %u) is not marked "
                            "empty", i, n, cnt);
            continue;
        }
        if (!rt_box_is_finite(cb))
            return FAIL("rtree compact: entry %u of node %u has no valid box", i, n);
        float content[6];
        tt_status st;
        if (w->mixed ? i < leaves : l == 1) {
            st = check_leaf(w, n, i, ref[i], is_root && cnt == 1, cb, content);
        } else {
            st = check_node(w, ref[i], l - 1, n, content);
        }
        if (st != TT_OK) return st;
        float in[6];
        if (w->cover && (w->mixed ? i < leaves : l == 1)) {
            if (!box_meet(cb, content, in) || !rt_box_equal(in, cb))
                return FAIL("rtree compact: the box of leaf %u of node %u reaches past its "
                            "triangles' boxes", i, n);
        } else if (!rt_box_equal(cb, content))
            return FAIL("rtree compact: the box of entry %u of node %u (level %u) is not the "
                        "exact union of its content", i, n, l);
        rt_box_grow(box, cb);
    }
    return TT_OK;
}

tt_status rtc_check(tt_context *ctx, const rtc_tree *t, const tt_scene *scene)
{
    const tt_rtc *c = &t->c;
    walk w = {ctx, t, scene, NULL, NULL, NULL, NULL, 0};
    /* a tree updated in place holds the live triangles; a built one every
     * id slot (removed ones as points, io/scene.h) */
    if (c->triangles > scene->triangle_count || c->triangles < tt_scene_live_triangle_count(scene))
        return tt_error(ctx, TT_ERR_INVARIANT,
                        "rtree compact: %u triangles packed, the scene has %zu (%zu live)",
                        c->triangles, scene->triangle_count, tt_scene_live_triangle_count(scene));
    if (c->M < 4 || c->M > TT_RT_MAX_M || c->S != ((c->M + 3u) & ~3u) ||
        c->words != tt_rtc_words(c->M) || c->nodes == 0 || c->height == 0)
        return tt_error(ctx, TT_ERR_INVARIANT,
                        "rtree compact: inconsistent header (M %u, stride %u, %u words a node, %u "
                        "nodes, height %u)", c->M, c->S, c->words, c->nodes, c->height);
    w.reached = tt_calloc(ctx, c->nodes, 1);
    w.seen = tt_calloc(ctx, scene->triangle_count ? scene->triangle_count : 1, 1);
    w.lane_owned = tt_calloc(ctx, (size_t)c->blocks * TT_TRI_BLOCK_W + 1, 1);
    if (t->split) {
        w.cover = tt_alloc_array(ctx, scene->triangle_count ? scene->triangle_count : 1,
                                 6 * sizeof(float));
        for (size_t id = 0; w.cover && id < scene->triangle_count; id++)
            rt_box_empty(w.cover + 6 * id);
    }
    tt_status st = TT_OK;
    if (!w.reached || !w.seen || !w.lane_owned || (t->split && !w.cover))
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree compact check: out of memory");
    float root[6];
    w.mixed = c->nodes > 0 && tt_rtc_level(c, tt_rtc_node(c, 0)) == 0;
    if (st == TT_OK) st = check_node(&w, 0, c->height, TT_INVALID_ID, root);
    for (uint32_t n = 0; st == TT_OK && n < c->nodes; n++)
        if (!w.reached[n] && !tt_rtc_is_free(c, tt_rtc_node(c, n)))
            st = tt_error(ctx, TT_ERR_INVARIANT,
                          "rtree compact: node %u is not in the tree and not marked free", n);
    if (st == TT_OK) st = check_free_lanes(&w);
    size_t stored = 0;
    for (size_t id = 0; st == TT_OK && id < scene->triangle_count; id++) {
        stored += w.seen[id] != 0;
        if (!w.seen[id] && !tt_scene_is_dead(scene, id))
            st = tt_error(ctx, TT_ERR_INVARIANT, "rtree compact: triangle %zu is not in the tree",
                          id);
        if (st == TT_OK && w.cover && w.seen[id]) {
            const float *v = scene->tri + 9 * id;
            float tb[6];
            rt_box_of_triangle(v, tb);
            if (!rt_box_equal(tb, w.cover + 6 * id))
                st = tt_error(ctx, TT_ERR_INVARIANT, "rtree compact: the leaves of triangle %zu "
                              "do not cover its box", id);
        }
    }
    if (st == TT_OK && stored != c->triangles)
        st = tt_error(ctx, TT_ERR_INVARIANT, "rtree compact: %zu triangles stored, the header "
                      "says %u", stored, c->triangles);
    tt_free(ctx, w.reached);
    tt_free(ctx, w.seen);
    tt_free(ctx, w.lane_owned);
    tt_free(ctx, w.cover);
    return st;
}
