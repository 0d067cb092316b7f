/* The complete level-order layout (rtree_packed.h) in a saved file: M, L
 * and the triangle count, and the five arrays verbatim. The index tables
 * (Delta_L, gfirst) follow from M and L and are recomputed on load, as
 * rt_pack computes them, so a file cannot make the index arithmetic leave
 * the arrays; the arrays are then used in place from the mapping. */
#include <string.h>

#include "accel/accel_io.h"
#include "accel/rtree/rtree_io.h"

enum { H_M, H_L, H_TRIANGLES, H_COUNT };

tt_status rt_packed_io_save(tt_context *ctx, const rt_tree *t, tt_af_writer *w)
{
    const tt_rtree_packed *p = &t->p;
    const uint32_t h[H_COUNT] = {p->M, p->L, p->triangles};
    w->layout = RT_IO_LAYOUT_COMPLETE;
    w->layout_version = RT_IO_COMPLETE_VERSION;
    tt_status st = tt_af_add_copy(ctx, w, TT_AF_SEC_RTP_HEADER, 4, H_COUNT, h);
    if (st == TT_OK) st = tt_af_add(ctx, w, TT_AF_SEC_RTP_BOX, 4, t->box_floats, p->box);
    if (st == TT_OK) st = tt_af_add(ctx, w, TT_AF_SEC_RTP_COUNT, 1, p->delta[0], p->count);
    if (st == TT_OK)
        st = tt_af_add(ctx, w, TT_AF_SEC_RTP_LEAF_START, 4, (uint64_t)p->leaf_slots + 1,
                       p->leaf_start);
    if (st == TT_OK) st = tt_af_add(ctx, w, TT_AF_SEC_RTP_TRI, 36, p->triangles, p->tri);
    if (st == TT_OK) st = tt_af_add(ctx, w, TT_AF_SEC_RTP_PRIM, 4, p->triangles, p->prim);
    return st;
}

tt_status rt_packed_io_load(tt_context *ctx, const tt_af_file *f, uint32_t triangles, rt_tree *t)
{
    if (f->h->layout_version != RT_IO_COMPLETE_VERSION)
        return tt_error(ctx, TT_ERR_UNSUPPORTED,
                        "%s: complete R-tree records of version %u; this library reads version "
                        "%u: rebuild the structure", f->name, f->h->layout_version,
                        RT_IO_COMPLETE_VERSION);
    const uint32_t *h;
    tt_status st = tt_af_get_n(ctx, f, TT_AF_SEC_RTP_HEADER, 4, H_COUNT, (const void **)&h);
    if (st != TT_OK) return st;
    const uint32_t M = h[H_M], L = h[H_L];
    if (M < 4 || M > TT_RT_MAX_M || L + 1 > TT_RT_MAX_LEVELS || (L + 1) * M > TT_RT_STACK_SIZE ||
        h[H_TRIANGLES] != triangles)
        return tt_af_bad(ctx, f, "M = %u, L = %u, %u triangles: out of range", M, L,
                         h[H_TRIANGLES]);
    /* the tables exactly as rt_pack makes them */
    uint64_t level_size = 1, first = 0, delta[TT_RT_MAX_LEVELS + 1] = {0};
    for (int l = (int)L; l >= 0; l--) {
        delta[l] = first;
        first += level_size;
        if (l > 0) level_size *= M;
    }
    const uint64_t slots = first, leaf_slots = level_size;
    if (slots + M >= UINT32_MAX) return tt_af_bad(ctx, f, "%llu slots", (unsigned long long)slots);
    tt_rtree_packed *p = &t->p;
    memset(p, 0, sizeof *p);
    p->M = M;
    p->L = L;
    for (uint32_t s = 1; s < 31; s++)
        if ((1u << s) == M) p->m_shift = s;
    p->slots = (uint32_t)slots;
    p->leaf_slots = (uint32_t)leaf_slots;
    p->triangles = triangles;
    for (uint32_t l = 0; l <= L; l++) {
        p->delta[l] = (uint32_t)delta[l];
        p->gfirst[l] = l == L ? 0 : (uint32_t)((delta[l] - 1) / M + 1);
    }
    const uint64_t groups = (slots - 1) / M + 1;
    t->box_floats = (size_t)(groups * 6 * M);
    const void *box, *count, *leaf_start, *tri, *prim;
    st = tt_af_get_n(ctx, f, TT_AF_SEC_RTP_BOX, 4, t->box_floats, &box);
    if (st == TT_OK) st = tt_af_get_n(ctx, f, TT_AF_SEC_RTP_COUNT, 1, p->delta[0], &count);
    if (st == TT_OK)
        st = tt_af_get_n(ctx, f, TT_AF_SEC_RTP_LEAF_START, 4, leaf_slots + 1, &leaf_start);
    if (st == TT_OK) st = tt_af_get_n(ctx, f, TT_AF_SEC_RTP_TRI, 36, triangles, &tri);
    if (st == TT_OK) st = tt_af_get_n(ctx, f, TT_AF_SEC_RTP_PRIM, 4, triangles, &prim);
    if (st != TT_OK) return st;
    p->box = box;
    p->count = count;
    p->leaf_start = leaf_start;
    p->tri = tri;
    p->prim = prim;
    for (uint32_t s = 0; s < p->delta[0]; s++)
        if (p->count[s] > M) return tt_af_bad(ctx, f, "slot %u: %u entries, M = %u", s, p->count[s], M);
    if (p->leaf_start[0] != 0 || p->leaf_start[leaf_slots] != triangles)
        return tt_af_bad(ctx, f, "leaf ranges do not cover the %u triangles", triangles);
    for (uint64_t j = 0; j < leaf_slots; j++)
        if (p->leaf_start[j] > p->leaf_start[j + 1])
            return tt_af_bad(ctx, f, "leaf slot %llu: its range runs backwards",
                             (unsigned long long)j);
    for (uint32_t i = 0; i < triangles; i++)
        if (p->prim[i] >= triangles)
            return tt_af_bad(ctx, f, "triangle %u is id %u of %u", i, p->prim[i], triangles);
    return TT_OK;
}
