/* The registry of structures and the public calls that dispatch to them. */
#include "accel/accel.h"
#include "accel/ray_check.h"
#include "core/isa.h"
#include "io/scene_guard.h"
#include "io/accel_file.h"

#include <string.h>

static const tt_accel_vtable *const registry[] = {
    &tt_bruteforce_vtable,
    &tt_rtree_vtable,
    &tt_kdtree_vtable,
    &tt_wbvh_vtable,
#ifdef TT_HAVE_EMBREE
    &tt_embree_vtable,
#endif
};

#define REGISTRY_SIZE (sizeof registry / sizeof registry[0])

const char *const *tt_accel_names(void)
{
    static const char *names[REGISTRY_SIZE + 1];
    for (size_t i = 0; i < REGISTRY_SIZE; i++) names[i] = registry[i]->name;
    names[REGISTRY_SIZE] = NULL;
    return names;
}

const tt_accel_vtable *tt_accel_find(const char *name)
{
    if (!name) return NULL;
    for (size_t i = 0; i < REGISTRY_SIZE; i++)
        if (strcmp(registry[i]->name, name) == 0) return registry[i];
    return NULL;
}

void tt_build_options_default(tt_build_options *o)
{
    memset(o, 0, sizeof *o);
    o->accel = "rtree";
    o->isa = TT_ISA_AUTO;
    /* The engine: bulk-loaded by the SAH into the compact layout. Feldmann's
     * configuration is build = INSERT, layout = COMPLETE, M = 4. */
    o->rtree.build = TT_RTREE_BUILD_SAH;
    o->rtree.layout = TT_RTREE_LAYOUT_COMPACT;
    o->rtree.strategy = TT_RTREE_RSTAR_SURFACE;
    o->rtree.m = 2;
    o->rtree.M = 0; /* tt_rtree_max_entries */
    o->rtree.reinsert = 1;
    o->rtree.reinsert_fraction = 0.3f;
    o->rtree.reinsert_far = 1;
    o->rtree.split = TT_RTREE_SPLIT_RSTAR;
    o->rtree.traversal = TT_RTREE_AUTO;
    o->rtree.split_budget = 0.0f; /* early split clipping: off (it did not pay everywhere) */
    o->kdtree.builder = TT_KD_NLOGN;
    o->kdtree.dmin = 0; /* auto: see tt_kdtree_options */
    o->kdtree.cost_traversal = 1.0f;
    /* C_I = C_T / 5, not the 1.5 the papers' tables use (bench_kdtree_build):
     * a leaf's triangles are tested eight at a time with plain loads
     * (kd_leaf_block.h), so an extra triangle costs far less than a node
     * step, whose cost is mostly a hard-to-predict branch. Against 0.5 (the
     * default before), on the shared views against Embree (1 thread, CPU
     * time): bunny shadow rays 0.40x -> 0.54x, primary +10-15%, sibenik and
     * conference level or better, cornell level; 0.3 and 0.25 trace alike,
     * 0.1 tests too many triangles. Conference's exact build has 3x fewer
     * nodes (504k -> 171k), about 35% less build time and half the memory. */
    o->kdtree.cost_intersect = 0.2f;
    /* Cost factor 0.8: Wald & Havran's lambda. The shape is no lever left
     * for single rays: over C_I 0.15-0.3, bonus 0-0.1 and a depth limit
     * of 20 the interior nodes a ray visits move by at most ~10% (fewer
     * for primary rays, more for shadow rays or the reverse), and pricing
     * a leaf in whole 8-triangle blocks trades a few nodes for 2-4x the
     * triangles; bonus 0.35 and 0.5 traced slower (B/A 0.86-1.05). */
    o->kdtree.empty_bonus = 0.2f;
    o->kdtree.max_depth = 0;
    o->kdtree.traversal = TT_KD_HTR;
    o->kdtree.shadow_caster_hint = 0;
    o->embree.quality = TT_EMBREE_HIGH;
}

tt_status tt_accel_build(tt_context *ctx, const tt_scene *scene, const tt_build_options *options,
                         tt_accel **out)
{
    if (!out) return TT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if (!scene) return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_accel_build: no scene");
    tt_build_options def;
    if (!options) {
        tt_build_options_default(&def);
        options = &def;
    }
    const tt_accel_vtable *vt = tt_accel_find(options->accel);
    if (!vt) {
        if (options->accel && strcmp(options->accel, "embree") == 0)
            return tt_error(ctx, TT_ERR_UNSUPPORTED,
                            "accel 'embree': this build has no Embree (install libembree-dev "
                            "and rebuild)");
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "unknown accel '%s'",
                        options->accel ? options->accel : "(null)");
    }
    tt_isa isa;
    tt_status ist = tt_isa_resolve(ctx, options->isa, &isa);
    if (ist != TT_OK) return ist;
    tt_accel *a = tt_calloc(ctx, 1, sizeof *a);
    if (!a) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "out of memory");
    a->vt = vt;
    a->ctx = ctx;
    a->scene = scene;
    a->options = *options;
    a->isa = isa;
    a->options.accel = vt->name; /* the caller's string need not outlive us */
    a->version = scene->version;
    double t0 = tt_now();
    tt_status st = vt->build(a);
    a->build_s = tt_now() - t0;
    if (st != TT_OK) {
        if (a->impl) vt->destroy(a);
        tt_free(ctx, a);
        return st;
    }
    *out = a;
    return TT_OK;
}

void tt_accel_destroy(tt_accel *accel)
{
    if (!accel) return;
    if (accel->file) { /* a loaded structure (accel_io.c) */
        tt_accel_unload(accel);
        return;
    }
    accel->vt->destroy(accel);
    tt_free(accel->ctx, accel);
}

const char *tt_accel_name(const tt_accel *accel) { return accel ? accel->vt->name : ""; }
double tt_accel_build_seconds(const tt_accel *accel) { return accel ? accel->build_s : 0.0; }
tt_isa tt_accel_isa(const tt_accel *accel) { return accel ? accel->isa : TT_ISA_SCALAR; }
/* A loaded structure's arrays are the mapped file's (accel_io.c). */
size_t tt_accel_memory_bytes(const tt_accel *accel)
{
    if (!accel) return 0;
    return accel->file ? accel->file->size : accel->vt->memory(accel);
}

tt_status tt_accel_check(const tt_accel *accel)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    return accel->vt->check(accel);
}

tt_status tt_accel_statistics(const tt_accel *accel, tt_stat_fn fn, void *user)
{
    if (!accel || !fn) return TT_ERR_INVALID_ARGUMENT;
    accel->vt->statistics(accel, fn, user);
    return TT_OK;
}

uint32_t tt_accel_locate(const tt_accel *accel, const float point[3])
{
    if (!accel || !point || !accel->vt->locate) return TT_INVALID_ID;
    return accel->vt->locate(accel, point);
}

static tt_status prepare(const tt_accel *accel, const tt_ray *ray, tt_wray *w)
{
    char why[160];
    if (tt_ray_check(ray->org, ray->dir, ray->tmin, ray->tmax, why, sizeof why) != TT_OK)
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT, "%s", why);
    tt_wray_init(w, ray->org, ray->dir, ray->tmin, ray->tmax);
    return TT_OK;
}

tt_status tt_intersect1_ex(const tt_accel *accel, const tt_ray *ray, tt_hit *hit,
                           tt_trace_args *args)
{
    if (!accel || !ray || !hit) return TT_ERR_INVALID_ARGUMENT;
    tt_wray w;
    tt_status st = prepare(accel, ray, &w);
    if (st != TT_OK) return st;
    st = tt_accel_trace_enter(accel, "tt_intersect1");
    if (st != TT_OK) return st;
    if (args && args->stats) accel->vt->intersect_stats(accel, &w, hit, args, args->stats);
    else accel->vt->intersect(accel, &w, hit, args);
    tt_accel_trace_leave(accel);
    return TT_OK;
}

tt_status tt_occluded1_ex(const tt_accel *accel, const tt_ray *ray, int *occluded,
                          tt_trace_args *args)
{
    if (!accel || !ray || !occluded) return TT_ERR_INVALID_ARGUMENT;
    tt_wray w;
    tt_status st = prepare(accel, ray, &w);
    if (st != TT_OK) return st;
    st = tt_accel_trace_enter(accel, "tt_occluded1");
    if (st != TT_OK) return st;
    if (args && args->stats) *occluded = accel->vt->occluded_stats(accel, &w, args, args->stats);
    else *occluded = accel->vt->occluded(accel, &w, args);
    tt_accel_trace_leave(accel);
    return TT_OK;
}

tt_status tt_intersect1(const tt_accel *accel, const tt_ray *ray, tt_hit *hit)
{
    return tt_intersect1_ex(accel, ray, hit, NULL);
}

tt_status tt_occluded1(const tt_accel *accel, const tt_ray *ray, int *occluded)
{
    return tt_occluded1_ex(accel, ray, occluded, NULL);
}

/* ---------------------------------------------------- dynamic scenes */

tt_status tt_accel_trace_enter(const tt_accel *accel, const char *call)
{
    /* the guard first: the versions are written under a writer's hold */
    if (!tt_scene_trace_enter(accel->scene))
        return tt_error(accel->ctx, TT_ERR_BUSY,
                        "%s: the scene is being edited or updated on another thread; traces "
                        "must not overlap edits (treetrace.h: the threading contract)", call);
    if (accel->version != accel->scene->version) {
        const unsigned long long sv = accel->scene->version, av = accel->version;
        tt_scene_trace_leave(accel->scene);
        return tt_error(accel->ctx, TT_ERR_STALE,
                        "%s: the scene was edited after this %s structure was built or updated "
                        "(scene version %llu, structure %llu): call tt_accel_update first", call,
                        accel->vt->name, sv, av);
    }
    return TT_OK;
}

void tt_accel_trace_leave(const tt_accel *accel) { tt_scene_trace_leave(accel->scene); }

/* The answer of every structure without an in-place update: a new build of
 * the edited scene, swapped in only when it succeeded. */
static tt_status rebuild(tt_accel *a)
{
    tt_accel fresh = *a;
    fresh.impl = NULL;
    fresh.file = NULL;
    double t0 = tt_now();
    tt_status st = a->vt->build(&fresh);
    if (st != TT_OK) {
        if (fresh.impl) a->vt->destroy(&fresh);
        return st;
    }
    if (a->file) { /* a loaded structure: its arrays were the mapped file's */
        if (a->impl && a->vt->unload) a->vt->unload(a);
        tt_af_close(a->file);
        tt_free(a->ctx, a->file);
        a->file = NULL;
    } else {
        a->vt->destroy(a);
    }
    a->impl = fresh.impl;
    a->options = fresh.options;
    a->build_s = tt_now() - t0;
    return TT_OK;
}

tt_status tt_accel_update(tt_accel *accel)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    const tt_scene *s = accel->scene;
    if (!tt_scene_write_enter(s))
        return tt_error(accel->ctx, TT_ERR_BUSY,
                        "tt_accel_update: the scene is being traced, edited or updated on another "
                        "thread; updates must run alone (treetrace.h: the threading contract)");
    tt_status st = TT_OK;
    if (accel->version != s->version) {
        double t0 = tt_now();
        /* a loaded structure's arrays are a read-only mapping: rebuilt */
        st = accel->vt->update && !accel->file ? accel->vt->update(accel, accel->version)
                                               : TT_ERR_UNSUPPORTED;
        if (st == TT_ERR_UNSUPPORTED) st = rebuild(accel);
        if (st == TT_OK) {
            accel->version = s->version;
            accel->update_s = tt_now() - t0;
        }
    }
    tt_scene_write_leave(s);
    return st;
}

int tt_accel_updates_in_place(const tt_accel *accel)
{
    return accel && !accel->file && accel->vt->updates_in_place &&
           accel->vt->updates_in_place(accel);
}
