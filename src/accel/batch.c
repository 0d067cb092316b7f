/* Batches of rays (tt_intersect, tt_occluded and their strided forms): the
 * rays are read through byte strides, checked against the ray contract one
 * by one, and traced through the structure's dispatch table on the
 * context's OpenMP threads, like the renderer's passes. The AoS calls are
 * the strided ones over tt_ray / tt_hit, so there is one loop to trust. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "accel/accel.h"
#include "accel/ray_check.h"

#include <omp.h>

#define DEFAULT_CHUNK 64u

void tt_batch_options_default(tt_batch_options *o)
{
    if (!o) return;
    memset(o, 0, sizeof *o);
    o->start_hint = TT_INVALID_ID;
    o->stats = NULL;
    o->chunk = 0;
}

static const float *at_f(const float *base, ptrdiff_t stride, size_t i)
{
    return (const float *)(const void *)((const char *)base + (ptrdiff_t)i * stride);
}

static void load_ray(const tt_ray_arrays *a, size_t i, float org[3], float dir[3], float *tmin,
                     float *tmax)
{
    for (int k = 0; k < 3; k++) {
        org[k] = *at_f(a->org[k], a->org_stride, i);
        dir[k] = *at_f(a->dir[k], a->dir_stride, i);
    }
    *tmin = a->tmin ? *at_f(a->tmin, a->tmin_stride, i) : 0.0f;
    *tmax = a->tmax ? *at_f(a->tmax, a->tmax_stride, i) : TT_INF;
}

static void store_hit(const tt_hit_arrays *h, size_t i, const tt_hit *hit)
{
    if (h->t) *(float *)(void *)((char *)h->t + (ptrdiff_t)i * h->t_stride) = hit->t;
    if (h->u) *(float *)(void *)((char *)h->u + (ptrdiff_t)i * h->u_stride) = hit->u;
    if (h->v) *(float *)(void *)((char *)h->v + (ptrdiff_t)i * h->v_stride) = hit->v;
    if (h->prim)
        *(uint32_t *)(void *)((char *)h->prim + (ptrdiff_t)i * h->prim_stride) = hit->prim;
}

static int arrays_ok(const tt_ray_arrays *a)
{
    return a && a->org[0] && a->org[1] && a->org[2] && a->dir[0] && a->dir[1] && a->dir[2];
}

static void add_stats(tt_ray_stats *sum, const tt_ray_stats *s)
{
    sum->rays += s->rays;
    sum->nodes += s->nodes;
    sum->interior += s->interior;
    sum->leaves += s->leaves;
    sum->boxes += s->boxes;
    sum->triangles += s->triangles;
}

static int threads_of(const tt_accel *accel)
{
    int t = tt_context_threads(accel->ctx);
    return t > 0 ? t : omp_get_max_threads();
}

/* After the batch: the context's message names the first bad ray, in the
 * single-ray calls' words, prefixed by its index. */
static tt_status report_bad(const tt_accel *accel, const tt_ray_arrays *a, size_t n, size_t bad,
                            size_t bad_count, const char *call)
{
    if (bad_count == 0) return TT_OK;
    float org[3], dir[3], tmin, tmax;
    char why[160];
    load_ray(a, bad, org, dir, &tmin, &tmax);
    tt_ray_check(org, dir, tmin, tmax, why, sizeof why);
    return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT, "%s: ray %zu of %zu: %s (%zu bad ray%s)",
                    call, bad, n, why, bad_count, bad_count == 1 ? "" : "s");
}

static tt_status check_call(const tt_accel *accel, const tt_batch_options *o, const char *call)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    if (o && o->chunk > (1u << 30))
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT, "%s: chunk %u is too large", call,
                        o->chunk);
    return TT_OK;
}

tt_status tt_intersect_arrays(const tt_accel *accel, const tt_ray_arrays *rays, size_t n,
                              const tt_hit_arrays *hits, tt_status *ray_status,
                              const tt_batch_options *options)
{
    static const char call[] = "tt_intersect";
    tt_status st = check_call(accel, options, call);
    if (st != TT_OK) return st;
    if (n == 0) return TT_OK;
    if (!arrays_ok(rays) || !hits)
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: %zu rays but no ray or result arrays", call, n);
    tt_batch_options def;
    tt_batch_options_default(&def);
    const tt_batch_options *o = options ? options : &def;
    const tt_accel_vtable *vt = accel->vt;
    const long chunk = (long)(o->chunk ? o->chunk : DEFAULT_CHUNK);
    const long count = (long)((n + (size_t)chunk - 1) / (size_t)chunk);
    size_t bad = SIZE_MAX, bad_count = 0;
#pragma omp parallel num_threads(threads_of(accel)) reduction(min : bad) reduction(+ : bad_count)
    {
        tt_ray_stats local;
        memset(&local, 0, sizeof local);
#pragma omp for schedule(dynamic)
        for (long c = 0; c < count; c++) {
            size_t end = ((size_t)c + 1) * (size_t)chunk;
            if (end > n) end = n;
            for (size_t i = (size_t)c * (size_t)chunk; i < end; i++) {
                float org[3], dir[3], tmin, tmax;
                tt_hit h;
                load_ray(rays, i, org, dir, &tmin, &tmax);
                tt_status rs = tt_ray_check(org, dir, tmin, tmax, NULL, 0);
                if (rs == TT_OK) {
                    tt_wray w;
                    tt_trace_args args = {o->start_hint, TT_INVALID_ID, NULL};
                    tt_wray_init(&w, org, dir, tmin, tmax);
                    if (o->stats) {
                        args.stats = &local;
                        vt->intersect_stats(accel, &w, &h, &args, &local);
                    } else {
                        vt->intersect(accel, &w, &h, &args);
                    }
                } else {
                    tt_hit_clear(&h);
                    if (i < bad) bad = i;
                    bad_count++;
                }
                if (ray_status) ray_status[i] = rs;
                store_hit(hits, i, &h);
            }
        }
        if (o->stats) {
#pragma omp critical(tt_batch_stats)
            add_stats(o->stats, &local);
        }
    }
    return report_bad(accel, rays, n, bad, bad_count, call);
}

tt_status tt_occluded_arrays(const tt_accel *accel, const tt_ray_arrays *rays, size_t n,
                             uint8_t *occluded, ptrdiff_t occluded_stride,
                             tt_status *ray_status, const tt_batch_options *options)
{
    static const char call[] = "tt_occluded";
    tt_status st = check_call(accel, options, call);
    if (st != TT_OK) return st;
    if (n == 0) return TT_OK;
    if (!arrays_ok(rays) || !occluded)
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: %zu rays but no ray or result arrays", call, n);
    if (occluded_stride == 0) occluded_stride = 1;
    tt_batch_options def;
    tt_batch_options_default(&def);
    const tt_batch_options *o = options ? options : &def;
    const tt_accel_vtable *vt = accel->vt;
    const long chunk = (long)(o->chunk ? o->chunk : DEFAULT_CHUNK);
    const long count = (long)((n + (size_t)chunk - 1) / (size_t)chunk);
    size_t bad = SIZE_MAX, bad_count = 0;
#pragma omp parallel num_threads(threads_of(accel)) reduction(min : bad) reduction(+ : bad_count)
    {
        tt_ray_stats local;
        memset(&local, 0, sizeof local);
#pragma omp for schedule(dynamic)
        for (long c = 0; c < count; c++) {
            size_t end = ((size_t)c + 1) * (size_t)chunk;
            if (end > n) end = n;
            for (size_t i = (size_t)c * (size_t)chunk; i < end; i++) {
                float org[3], dir[3], tmin, tmax;
                int occ = 0;
                load_ray(rays, i, org, dir, &tmin, &tmax);
                tt_status rs = tt_ray_check(org, dir, tmin, tmax, NULL, 0);
                if (rs == TT_OK) {
                    tt_wray w;
                    tt_trace_args args = {o->start_hint, TT_INVALID_ID, NULL};
                    tt_wray_init(&w, org, dir, tmin, tmax);
                    if (o->stats) {
                        args.stats = &local;
                        occ = vt->occluded_stats(accel, &w, &args, &local);
                    } else {
                        occ = vt->occluded(accel, &w, &args);
                    }
                } else {
                    if (i < bad) bad = i;
                    bad_count++;
                }
                if (ray_status) ray_status[i] = rs;
                occluded[(ptrdiff_t)i * occluded_stride] = (uint8_t)(occ != 0);
            }
        }
        if (o->stats) {
#pragma omp critical(tt_batch_stats)
            add_stats(o->stats, &local);
        }
    }
    return report_bad(accel, rays, n, bad, bad_count, call);
}

/* The AoS forms: the same loops over tt_ray's and tt_hit's own layout. */
static void aos_rays(const tt_ray *rays, tt_ray_arrays *a)
{
    memset(a, 0, sizeof *a);
    for (int k = 0; k < 3; k++) {
        a->org[k] = &rays[0].org[k];
        a->dir[k] = &rays[0].dir[k];
    }
    a->org_stride = a->dir_stride = a->tmin_stride = a->tmax_stride = (ptrdiff_t)sizeof(tt_ray);
    a->tmin = &rays[0].tmin;
    a->tmax = &rays[0].tmax;
}

tt_status tt_intersect(const tt_accel *accel, const tt_ray *rays, size_t n, tt_hit *hits,
                       tt_status *ray_status, const tt_batch_options *options)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    if (n > 0 && (!rays || !hits))
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_intersect: %zu rays but no ray or hit array", n);
    if (n == 0) return check_call(accel, options, "tt_intersect");
    tt_ray_arrays a;
    aos_rays(rays, &a);
    const ptrdiff_t s = (ptrdiff_t)sizeof(tt_hit);
    tt_hit_arrays h = {&hits[0].t, s, &hits[0].u, s, &hits[0].v, s, &hits[0].prim, s};
    return tt_intersect_arrays(accel, &a, n, &h, ray_status, options);
}

tt_status tt_occluded(const tt_accel *accel, const tt_ray *rays, size_t n, uint8_t *occluded,
                      tt_status *ray_status, const tt_batch_options *options)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    if (n > 0 && (!rays || !occluded))
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_occluded: %zu rays but no ray or result array", n);
    if (n == 0) return check_call(accel, options, "tt_occluded");
    tt_ray_arrays a;
    aos_rays(rays, &a);
    return tt_occluded_arrays(accel, &a, n, occluded, 1, ray_status, options);
}
