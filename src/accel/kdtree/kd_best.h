/* The running result of one kd-tree ray (closest so far, see
 * kd_trace_common.h), apart so that the per-ISA leaf kernels can use it. */
#ifndef TT_ACCEL_KDTREE_KD_BEST_H
#define TT_ACCEL_KDTREE_KD_BEST_H

#include "geometry/ray.h"
#include "treetrace/treetrace.h"

typedef struct tt_kd_best {
    float t, u, v;
    uint32_t prim;
} tt_kd_best;

TT_HD void tt_kd_best_init(tt_kd_best *b, const tt_wray *r)
{
    b->t = r->tmax;
    b->u = b->v = 0.0f;
    b->prim = TT_INVALID_ID;
}

TT_HD void tt_kd_best_store(const tt_kd_best *b, tt_hit *hit)
{
    hit->t = b->prim == TT_INVALID_ID ? TT_INF : b->t;
    hit->u = b->u;
    hit->v = b->v;
    hit->prim = b->prim;
}

#endif
