/* The running result of one kd-tree ray (closest so far, see
 * kd_trace_common.h), apart so that the per-ISA leaf kernels can use it. */
#ifndef TT_ACCEL_KDTREE_KD_BEST_H
#define TT_ACCEL_KDTREE_KD_BEST_H

#include "accel/kdtree/kd_layout.h"
#include "geometry/ray.h"
#include "geometry/triangle.h"
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

/* The scalar leaf loop: tests refs[0..count) in order with the watertight
 * test, a triangle replacing the best so far only when strictly nearer.
 * Closest hit (any == 0): narrows *best, returns 0. Any hit: returns 1 at
 * the first hit on [tmin, best->t). *tested: how many triangles it tested
 * (the counting variant's statistic; a dead store elsewhere). The
 * template's leaf (kd_trace_common.h) in every variant but the AVX2 /
 * AVX-512 fast ones (kd_leaf_block.h). */
TT_HD int tt_kd_leaf_refs(const tt_kd_view *T, const uint32_t *refs, uint32_t count,
                          const tt_wray *r, int any, tt_kd_best *best, uint32_t *tested)
{
    for (uint32_t i = 0; i < count; i++) {
        const uint32_t id = TT_LDG(&refs[i]);
        const float *p = T->tri + 9 * (size_t)id;
        float t, u, v;
        if (tt_intersect_triangle(r, p, p + 3, p + 6, best->t, &t, &u, &v)) {
            best->t = t;
            best->u = u;
            best->v = v;
            best->prim = id;
            if (any) {
                *tested = i + 1;
                return 1;
            }
        }
    }
    *tested = count;
    return 0;
}

#endif
