/* Packing the pointer tree into the level-order array of the complete M-ary
 * tree (rtree_packed.h). Boxes are copied verbatim from the pointer tree,
 * never recomputed, so the packed check also verifies that construction
 * kept every node box the exact union of its entries. */
#include <string.h>

#include "accel/rtree/rtree.h"
#include "accel/rtree/rtree_box.h"

size_t rt_tree_bytes(const rt_tree *t)
{
    const tt_rtree_packed *p = &t->p;
    return t->box_floats * sizeof(float) + (size_t)p->delta[0] * sizeof(uint8_t) +
           ((size_t)p->leaf_slots + 1) * sizeof(uint32_t) +
           (size_t)p->triangles * (9 * sizeof(float) + sizeof(uint32_t));
}

void rt_tree_free(tt_context *ctx, rt_tree *t)
{
    rtc_free(ctx, &t->compact);
    tt_free(ctx, t->box);
    tt_free(ctx, t->count);
    tt_free(ctx, t->leaf_start);
    tt_free(ctx, t->tri);
    tt_free(ctx, t->prim);
    t->box = NULL;
    t->count = NULL;
    t->leaf_start = NULL;
    t->tri = NULL;
    t->prim = NULL;
}

static void put_slot_box(rt_tree *t, uint32_t n, const float b[6])
{
    uint32_t pos;
    float *g = (float *)tt_rt_group(&t->p, n, &pos);
    for (int k = 0; k < 6; k++) g[k * t->p.M + pos] = b[k];
}

tt_status rt_pack(tt_context *ctx, const rt_builder *b, const float *scene_tri, rt_tree *t)
{
    tt_rtree_packed *p = &t->p;
    const uint32_t M = (uint32_t)b->M, L = b->hdr[b->root].level;
    if (L + 1 > TT_RT_MAX_LEVELS || (L + 1) * M > TT_RT_STACK_SIZE)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "rtree: the tree has %u levels; the packed layout supports %d (at most "
                        "%d stack entries (L+1)*M)", L + 1, TT_RT_MAX_LEVELS, TT_RT_STACK_SIZE);
    /* Delta_L(l) and the slot count, in 64 bits to catch overflow. */
    uint64_t level_size = 1, first = 0, delta[TT_RT_MAX_LEVELS + 1];
    for (int l = (int)L; l >= 0; l--) {
        delta[l] = first;
        first += level_size;
        if (l > 0) level_size *= M;
    }
    const uint64_t slots = first, leaf_slots = level_size;
    if (slots + M >= UINT32_MAX)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "rtree: the complete %u-ary tree of %u levels has %llu slots, beyond "
                        "32-bit indices (use a larger m or M)", M, L + 1,
                        (unsigned long long)slots);
    memset(p, 0, sizeof *p);
    p->M = M;
    p->L = L;
    for (uint32_t s = 1; s < 31; s++)
        if ((1u << s) == M) p->m_shift = s;
    p->slots = (uint32_t)slots;
    p->leaf_slots = (uint32_t)leaf_slots;
    p->triangles = b->triangles;
    for (uint32_t l = 0; l <= L; l++) {
        p->delta[l] = (uint32_t)delta[l];
        p->gfirst[l] = l == L ? 0 : (uint32_t)((delta[l] - 1) / M + 1);
    }

    const size_t groups = (size_t)(slots - 1) / M + 1;
    t->box_floats = groups * 6 * M;
    t->box = tt_alloc_array(ctx, t->box_floats, sizeof(float));
    t->count = tt_calloc(ctx, p->delta[0] ? p->delta[0] : 1, 1);
    t->leaf_start = tt_calloc(ctx, (size_t)leaf_slots + 1, sizeof(uint32_t));
    t->tri = tt_alloc_array(ctx, (size_t)b->triangles ? b->triangles : 1, 9 * sizeof(float));
    t->prim = tt_alloc_array(ctx, (size_t)b->triangles ? b->triangles : 1, sizeof(uint32_t));
    if (!t->box || !t->count || !t->leaf_start || !t->tri || !t->prim)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY,
                        "rtree: out of memory packing %llu slots (%.1f MB)",
                        (unsigned long long)slots, (double)rt_tree_bytes(t) / 1e6);
    for (size_t i = 0; i < t->box_floats; i++) t->box[i] = TT_INF; /* all slots empty */
    p->box = t->box;
    p->count = t->count;
    p->leaf_start = t->leaf_start;
    p->tri = t->tri;
    p->prim = t->prim;

    /* The root's box, then a depth-first walk that writes every node's
     * entries into its child slots. Children are pushed last-first, so
     * leaves are reached in increasing slot order and their triangles land
     * in leaf order. */
    float rb[6];
    rt_node_bounds(b, b->root, rb);
    memcpy(t->root_box, rb, sizeof rb);
    if (b->hdr[b->root].count > 0) put_slot_box(t, 0, rb);
    uint32_t stack_node[TT_RT_MAX_LEVELS * TT_RT_CAP], stack_slot[TT_RT_MAX_LEVELS * TT_RT_CAP];
    int sp = 0;
    stack_node[sp] = b->root;
    stack_slot[sp++] = 0;
    uint32_t placed = 0, present = b->hdr[b->root].count > 0;
    while (sp > 0) {
        uint32_t n = stack_node[--sp], s = stack_slot[sp];
        const rt_node_hdr *h = &b->hdr[n];
        const float *soa = rt_node_box(b, n);
        const uint32_t *ch = rt_node_child(b, n);
        if (h->level > 0) {
            uint32_t first_child = tt_rt_first_child(p, s, h->level);
            t->count[s] = h->count;
            for (int i = 0; i < h->count; i++) {
                float eb[6];
                rt_soa_get(soa, b->cap, i, eb);
                put_slot_box(t, first_child + (uint32_t)i, eb);
                present++;
            }
            for (int i = h->count - 1; i >= 0; i--) {
                stack_node[sp] = ch[i];
                stack_slot[sp++] = first_child + (uint32_t)i;
            }
        } else {
            uint32_t j = s - p->delta[0];
            t->leaf_start[j] = h->count; /* counts now, prefix sums below */
            for (int i = 0; i < h->count; i++) {
                memcpy(t->tri + 9 * (size_t)placed, scene_tri + 9 * (size_t)ch[i],
                       9 * sizeof(float));
                t->prim[placed++] = ch[i];
            }
        }
    }
    uint32_t sum = 0;
    for (uint64_t j = 0; j <= leaf_slots; j++) {
        uint32_t c = t->leaf_start[j];
        t->leaf_start[j] = sum;
        sum += c;
    }
    t->real_nodes = present;
    if (placed != b->triangles)
        return tt_error(ctx, TT_ERR_INTERNAL, "rtree: packed %u of %u triangles", placed,
                        b->triangles);
    return TT_OK;
}
