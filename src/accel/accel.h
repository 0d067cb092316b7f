/* The acceleration-structure interface: one dispatch table per structure.
 * Every structure (bruteforce, rtree, kdtree, embree) fills one of these; the
 * renderer and the public API call through it and know nothing else. */
#ifndef TT_ACCEL_ACCEL_H
#define TT_ACCEL_ACCEL_H

#include "core/context.h"
#include "geometry/ray.h"
#include "io/scene.h"

/* What a structure offers besides the required entries; the renderer asks
 * these instead of comparing names, so a new structure that offers the same
 * gets the same treatment. */
#define TT_CAP_CASTER_HINT 0x1u /* honours options.kdtree.shadow_caster_hint: a
                                   shadow ray's start_hint may be the caster the
                                   previous shadow ray ended at               */

/* The GPU tracer's structure layouts (src/cuda/gpu.h, tt_gpu_kind): which
 * one a structure's arrays are handed over as; NONE: the GPU cannot trace
 * it. The GPU's limits within a layout (traversals, options) are checked by
 * render/render_gpu.c, which knows what the tracer implements. */
typedef enum tt_accel_gpu {
    TT_ACCEL_GPU_NONE = 0,
    TT_ACCEL_GPU_RTREE,  /* rt_tree's complete M-ary level-order arrays */
    TT_ACCEL_GPU_KDTREE  /* tt_kdtree's view                            */
} tt_accel_gpu;

/* The most rays one packet call takes: a batch's 16 x 16 tile. */
#define TT_PACKET_MAX 256u

/* A packet traversal's counts (the counting variant only): the rays'
 * per-ray counts as single rays report them, and per packet what explains
 * a win or a loss. */
typedef struct tt_packet_stats {
    tt_ray_stats rays;     /* nodes, boxes, triangles: summed over the rays */
    uint64_t packets;      /* packet calls                                  */
    uint64_t node_visits;  /* nodes the packet visited (once per packet)    */
    uint64_t active_lanes; /* rays active at those visits, summed           */
    uint64_t fallback_rays; /* rays finished as single rays (divergence)    */
} tt_packet_stats;

/* A packet's rays as rows (structure of arrays), the way the batch calls
 * and the renderer gather them: org, dir, tmin and tmax of ray i at [i],
 * i < n <= TT_PACKET_MAX, every ray one the contract admits. Was an array
 * of tt_wray's, which the kernels copied again into rows: building them
 * (the nine divisions, the shear's selects, the AoS stores) and reading
 * them back was about 40% of a shadow ray's instructions (callgrind,
 * sibenik, 2026-12-02). A kernel may load whole vectors of a row past n
 * (never past TT_PACKET_MAX) and drops those lanes. */
typedef struct tt_packet_rays {
    _Alignas(64) float org[3][TT_PACKET_MAX];
    _Alignas(64) float dir[3][TT_PACKET_MAX];
    _Alignas(64) float tmin[TT_PACKET_MAX];
    _Alignas(64) float tmax[TT_PACKET_MAX];
    uint32_t n;
} tt_packet_rays;

/* Row i as the single-ray entries take it (a packet kernel's fallbacks,
 * structures without a kernel). */
static inline void tt_packet_ray_wray(const tt_packet_rays *p, uint32_t i, tt_wray *w)
{
    const float org[3] = {p->org[0][i], p->org[1][i], p->org[2][i]};
    const float dir[3] = {p->dir[0][i], p->dir[1][i], p->dir[2][i]};
    tt_wray_init(w, org, dir, p->tmin[i], p->tmax[i]);
}
/* Sets row i (the callers' gathering loops). */
static inline void tt_packet_ray_set(tt_packet_rays *p, uint32_t i, const float *org,
                                     const float *dir, float tmin, float tmax)
{
    for (int k = 0; k < 3; k++) {
        p->org[k][i] = org[k];
        p->dir[k][i] = dir[k];
    }
    p->tmin[i] = tmin;
    p->tmax[i] = tmax;
}

struct tt_af_writer;
struct tt_af_file;

typedef struct tt_accel_vtable {
    const char *name;
    unsigned caps;    /* TT_CAP_* bits */
    tt_accel_gpu gpu; /* layout the GPU tracer takes it in */
    /* Builds accel->impl from accel->scene and accel->options. */
    tt_status (*build)(tt_accel *accel);
    void (*destroy)(tt_accel *accel);
    /* The fast path: closest hit on [ray->tmin, ray->tmax); hit->prim is
     * TT_INVALID_ID and hit->t +inf on a miss. args may be NULL. */
    void (*intersect)(const tt_accel *accel, const tt_wray *ray, tt_hit *hit,
                      tt_trace_args *args);
    int (*occluded)(const tt_accel *accel, const tt_wray *ray, tt_trace_args *args);
    /* The counting variant, compiled separately so the fast path pays
     * nothing; adds this ray's counts to *stats (stats->rays too). */
    void (*intersect_stats)(const tt_accel *accel, const tt_wray *ray, tt_hit *hit,
                            tt_trace_args *args, tt_ray_stats *stats);
    int (*occluded_stats)(const tt_accel *accel, const tt_wray *ray, tt_trace_args *args,
                          tt_ray_stats *stats);
    /* Optional (NULL: the batch traces ray by ray): rays->n <= TT_PACKET_MAX
     * checked rays traced together as one coherent packet (a batch's tile),
     * handed over as rows (tt_packet_rays): the kernel derives what it needs
     * (reciprocals, shear, octants) itself, vectorised. Every result equals
     * `intersect`'s / `occluded`'s for that ray's tt_wray_init, bit for bit
     * (prim, t, u, v); hits[i] / occluded[i] answer row i. The _stats forms
     * are the counting variants, compiled separately; they add into *stats. */
    void (*intersect_packet)(const tt_accel *accel, const tt_packet_rays *rays, tt_hit *hits);
    void (*occluded_packet)(const tt_accel *accel, const tt_packet_rays *rays,
                            uint8_t *occluded);
    void (*intersect_packet_stats)(const tt_accel *accel, const tt_packet_rays *rays,
                                   tt_hit *hits, tt_packet_stats *stats);
    void (*occluded_packet_stats)(const tt_accel *accel, const tt_packet_rays *rays,
                                  uint8_t *occluded, tt_packet_stats *stats);
    /* Optional (NULL: the batch calls `intersect` / `occluded` a ray at a
     * time): rays->n <= TT_PACKET_MAX checked rays traced one by one, as
     * single rays (the batch's items that are not packets: packets off,
     * incoherent rays, the counting variants excepted), each with
     * start_hint as its tt_trace_args' start hint. hits[i] / occluded[i]
     * answer row i, equal bit for bit to `intersect`'s / `occluded`'s for
     * that row's tt_wray_init. The rows go to the structure's kernel unit,
     * which prepares them vectorised (accel/wray_rows.h) and calls its own
     * traversal directly: the per-ray glue (the nine divisions, the shear,
     * two calls through pointers) was 3-9% of an R-tree single ray and
     * 9-22% of a kd-tree one. */
    void (*intersect_rows)(const tt_accel *accel, const tt_packet_rays *rays,
                           uint32_t start_hint, tt_hit *hits);
    void (*occluded_rows)(const tt_accel *accel, const tt_packet_rays *rays, uint32_t start_hint,
                          uint8_t *occluded);
    /* Optional (NULL: yes): whether the batch calls and the renderer should
     * use the packet entries for this structure's options; 0 keeps them ray
     * by ray, with their start and caster hints (a kd-tree traversal that
     * uses hints and has no packet kernel). */
    int (*packets_for)(const tt_accel *accel);
    /* Optional (NULL: yes): whether packets pay against single rays for a
     * batch whose items pass the coherence rule (tt_packet_coherent), judged
     * from a probe: the counting variant's counts of one item's packets
     * (any: occlusion). The rule sees only the rays' geometry; how many of a
     * packet's rays share its nodes depends on the structure too (shadow
     * rays converging on a light from hits scattered over an edited scene
     * share few), which only the walk's counts show. The batch calls
     * (batch.c) probe a thread's first coherent item and then at growing
     * gaps, and take rows for the items between while the answer is 0. */
    int (*packets_pay)(const tt_accel *accel, int any, const tt_packet_stats *probe);
    /* Optional (NULL: TT_INVALID_ID): start hint for rays from point p. */
    uint32_t (*locate)(const tt_accel *accel, const float *p);
    /* Verifies the invariants; on failure reports through tt_error on
     * accel->ctx and returns TT_ERR_INVARIANT. */
    tt_status (*check)(const tt_accel *accel);
    /* Emits structure statistics as key/value pairs. */
    void (*statistics)(const tt_accel *accel, tt_stat_fn fn, void *user);
    size_t (*memory)(const tt_accel *accel);

    /* Dynamic scenes (optional; NULL: tt_accel_update rebuilds). Brings
     * accel->impl up to date with the scene's edits since version `since`
     * (the ids whose stamp is above it, io/scene.h), in place. Returns
     * TT_ERR_UNSUPPORTED, having changed nothing and reported nothing, to
     * be rebuilt instead (e.g. an option set it cannot update); on another
     * error the structure must still answer for the old scene. */
    tt_status (*update)(tt_accel *accel, uint64_t since);
    /* 1 when `update` works in place for this structure's options. */
    int (*updates_in_place)(const tt_accel *accel);
    /* Optional: saved structures (io/accel_file.h, docs/accel-file.md).
     * save adds the built structure's sections to *w; NULL: it cannot be
     * saved, and no_save says why. load fills accel->impl from a verified
     * file (accel->options already read from it), using its arrays in place
     * where the layout allows, and validates every index its traversals
     * follow, so that a hostile file is refused, never traced; unload frees
     * what load allocated (never the file's arrays) and replaces destroy
     * for a loaded structure. */
    tt_status (*save)(const tt_accel *accel, struct tt_af_writer *w);
    tt_status (*load)(tt_accel *accel, const struct tt_af_file *f);
    void (*unload)(tt_accel *accel);
    const char *no_save;
} tt_accel_vtable;

struct tt_accel {
    const tt_accel_vtable *vt;
    tt_context *ctx;
    const tt_scene *scene;
    tt_build_options options;
    tt_isa isa; /* options.isa resolved (core/isa.h) before build runs */
    double build_s;
    void *impl;
    /* the scene version it answers for (tt_accel_update), and the time of
     * its last update */
    uint64_t version;
    double update_s;
    struct tt_af_file *file; /* the mapped file of a loaded structure, else NULL */
};

/* Every trace entry point (single rays, batches, tt_render) brackets its
 * work with these: enter refuses a structure older than its scene
 * (TT_ERR_STALE) or a scene held by an edit or update (TT_ERR_BUSY), with
 * the message naming `call`; on TT_OK the caller must leave after. */
tt_status tt_accel_trace_enter(const tt_accel *accel, const char *call);
void tt_accel_trace_leave(const tt_accel *accel);

/* The structures compiled into this build. */
extern const tt_accel_vtable tt_bruteforce_vtable;
extern const tt_accel_vtable tt_rtree_vtable;
extern const tt_accel_vtable tt_kdtree_vtable;
extern const tt_accel_vtable tt_wbvh_vtable;
#ifdef TT_HAVE_EMBREE
extern const tt_accel_vtable tt_embree_vtable;
#endif

/* Lookup by name; NULL if unknown. */
const tt_accel_vtable *tt_accel_find(const char *name);

/* Saved structures (accel_io.c): a loaded structure's teardown (unload, the
 * file closed, the accel freed), and the loader over an opened file, which
 * it takes over (closed on error too); the fuzzer and tests call it. */
void tt_accel_unload(tt_accel *accel);
tt_status tt_accel_load_opened(tt_context *ctx, const tt_scene *scene, struct tt_af_file *file,
                               tt_isa isa, tt_accel **out);

/* Helpers for implementations. */

/* Adds one thread's or one ray's counts into a sum (the renderer's passes
 * and the batch calls both gather per-thread sums this way). */
static inline void tt_ray_stats_add(tt_ray_stats *sum, const tt_ray_stats *s)
{
    sum->rays += s->rays;
    sum->nodes += s->nodes;
    sum->interior += s->interior;
    sum->leaves += s->leaves;
    sum->boxes += s->boxes;
    sum->triangles += s->triangles;
}
static inline void tt_hit_clear(tt_hit *hit)
{
    hit->t = TT_INF;
    hit->u = hit->v = 0.0f;
    hit->prim = TT_INVALID_ID;
}

#endif
