/* The threading contract of a changing scene, enforced: traces (through any
 * structure built on the scene) may run together; a scene edit or a
 * structure update runs alone. One atomic counter on the scene: a trace
 * adds 1 while it runs; a writer swaps 0 for a large negative value. A
 * trace that finds a writer, or a writer that finds traces or another
 * writer, backs out and the call fails with TT_ERR_BUSY: a race in the
 * caller's code becomes an error, never a torn read. */
#ifndef TT_IO_SCENE_GUARD_H
#define TT_IO_SCENE_GUARD_H

#include <stdatomic.h>

#include "io/scene.h"

#define TT_SCENE_WRITER (-(1L << 40))

/* 1: the trace may run (call tt_scene_trace_leave after); 0: a writer holds
 * the scene. The counter is logically mutable state of a const scene. */
static inline int tt_scene_trace_enter(const tt_scene *s)
{
    _Atomic long *g = (_Atomic long *)&s->guard;
    if (atomic_fetch_add_explicit(g, 1, memory_order_acquire) >= 0) return 1;
    atomic_fetch_sub_explicit(g, 1, memory_order_relaxed);
    return 0;
}
static inline void tt_scene_trace_leave(const tt_scene *s)
{
    atomic_fetch_sub_explicit((_Atomic long *)&s->guard, 1, memory_order_release);
}
/* 1: the caller now holds the scene alone (tt_scene_write_leave after). */
static inline int tt_scene_write_enter(const tt_scene *s)
{
    long zero = 0;
    return atomic_compare_exchange_strong_explicit((_Atomic long *)&s->guard, &zero,
                                                   TT_SCENE_WRITER, memory_order_acquire,
                                                   memory_order_relaxed);
}
static inline void tt_scene_write_leave(const tt_scene *s)
{
    atomic_fetch_sub_explicit((_Atomic long *)&s->guard, TT_SCENE_WRITER, memory_order_release);
}

#endif
