/* The R-tree's save/load vtable entries: the scalars both layouts share
 * (fill minimum, traversal, root box, counts, timings) as one params
 * section, then the layout's own sections (layout/rtc_io.c,
 * layout/rtree_packed_io.c). A loaded tree's arrays are the file's; only the
 * rt_tree itself is allocated. */
#include <string.h>

#include "accel/accel_io.h"
#include "accel/rtree/rtree_io.h"

enum { P_M_FILL, P_TRAVERSAL, P_LAYOUT, P_REAL_NODES, P_ROOT_BOX, P_INSERT_S = P_ROOT_BOX + 6,
       P_PACK_S, P_COUNT };

tt_status rtree_io_save(const tt_accel *a, tt_af_writer *w)
{
    const rt_tree *t = a->impl;
    double p[P_COUNT];
    /* the fill the check enforces: 1 once updates deleted lazily */
    p[P_M_FILL] = t->layout == TT_RTREE_LAYOUT_COMPACT ? t->compact.m : t->m;
    p[P_TRAVERSAL] = t->traversal;
    p[P_LAYOUT] = t->layout;
    p[P_REAL_NODES] = t->real_nodes;
    for (int k = 0; k < 6; k++) p[P_ROOT_BOX + k] = t->root_box[k];
    p[P_INSERT_S] = t->insert_s;
    p[P_PACK_S] = t->pack_s;
    tt_status st = tt_af_add_copy(a->ctx, w, TT_AF_SEC_PARAMS, 8, P_COUNT, p);
    if (st != TT_OK) return st;
    return t->layout == TT_RTREE_LAYOUT_COMPACT ? rtc_io_save(a->ctx, &t->compact, w)
                                                : rt_packed_io_save(a->ctx, t, w);
}

tt_status rtree_io_load(tt_accel *a, const tt_af_file *f)
{
    const tt_rtree_options *o = &a->options.rtree;
    const double *p;
    tt_status st = tt_af_get_n(a->ctx, f, TT_AF_SEC_PARAMS, 8, P_COUNT, (const void **)&p);
    if (st != TT_OK) return st;
    if (p[P_LAYOUT] != (double)o->layout || p[P_TRAVERSAL] != (double)o->traversal ||
        !(p[P_M_FILL] >= 1 && p[P_M_FILL] <= 8) || !(p[P_REAL_NODES] >= 0 && p[P_REAL_NODES] < 4e9))
        return tt_af_bad(a->ctx, f, "the parameters disagree with the options");
    for (int k = 0; k < 6; k++) /* floats, converted below */
        if (!(p[P_ROOT_BOX + k] >= -3.4e38 && p[P_ROOT_BOX + k] <= 3.4e38) &&
            !(p[P_ROOT_BOX + k] == 1.0 / 0.0 || p[P_ROOT_BOX + k] == -1.0 / 0.0))
            return tt_af_bad(a->ctx, f, "root box bound %d is out of range", k);
    const uint32_t want = o->layout == TT_RTREE_LAYOUT_COMPACT ? RT_IO_LAYOUT_COMPACT
                                                               : RT_IO_LAYOUT_COMPLETE;
    if (f->h->layout != want)
        return tt_af_bad(a->ctx, f, "layout id %u, the options say %u", f->h->layout, want);
    rt_tree *t = tt_calloc(a->ctx, 1, sizeof *t);
    if (!t) return tt_error(a->ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory", f->name);
    a->impl = t;
    t->layout = o->layout;
    t->traversal = o->traversal;
    t->m = (int)p[P_M_FILL];
    t->compact.m = t->m;
    t->real_nodes = (uint32_t)p[P_REAL_NODES];
    for (int k = 0; k < 6; k++) t->root_box[k] = (float)p[P_ROOT_BOX + k];
    t->insert_s = p[P_INSERT_S];
    t->pack_s = p[P_PACK_S];
    const uint32_t T = (uint32_t)a->scene->triangle_count;
    if (t->layout == TT_RTREE_LAYOUT_COMPACT) {
        st = rtc_io_load(a->ctx, f, T, &t->compact);
        if (st == TT_OK) {
            if (t->compact.c.M != (uint32_t)o->M)
                return tt_af_bad(a->ctx, f, "M = %u, the options say %d", t->compact.c.M, o->M);
            rtc_select(&t->compact, (int)o->traversal, a->isa);
        }
    } else {
        st = rt_packed_io_load(a->ctx, f, T, t);
        if (st == TT_OK && t->p.M != (uint32_t)o->M)
            return tt_af_bad(a->ctx, f, "M = %u, the options say %d", t->p.M, o->M);
    }
    return st;
}

void rtree_io_unload(tt_accel *a)
{
    tt_free(a->ctx, a->impl); /* the arrays are the file's */
    a->impl = NULL;
}
