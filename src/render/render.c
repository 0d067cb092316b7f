/* tt_render: traces a frame K times (primary pass, then shadow pass, each
 * timed), optionally once more with the counting traversal variants, and
 * keeps what the caller asked for (hit buffer, image, per-pixel counts). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/frame.h"
#include "render/render_gpu.h"

struct tt_render_result {
    tt_context *ctx;
    tt_render_summary summary;
    uint8_t *hits;
    size_t hits_size;
    uint8_t *image;
    uint32_t *pixel_stats[TT_HEAT_METRIC_COUNT];
};

void tt_render_options_default(tt_render_options *o)
{
    memset(o, 0, sizeof *o);
    o->width = 1024;
    o->height = 1024;
    o->shadows = 1;
    o->repeat = 1;
}

void tt_render_result_destroy(tt_render_result *r)
{
    if (!r) return;
    tt_context *ctx = r->ctx;
    tt_free(ctx, r->hits);
    tt_free(ctx, r->image);
    for (int m = 0; m < TT_HEAT_METRIC_COUNT; m++) tt_free(ctx, r->pixel_stats[m]);
    tt_free(ctx, r);
}

const tt_render_summary *tt_render_get_summary(const tt_render_result *r)
{
    return r ? &r->summary : NULL;
}

const uint8_t *tt_render_image(const tt_render_result *r) { return r ? r->image : NULL; }

const uint8_t *tt_render_hits(const tt_render_result *r, size_t *size)
{
    if (size) *size = r && r->hits ? r->hits_size : 0;
    return r ? r->hits : NULL;
}

const uint32_t *tt_render_pixel_stats(const tt_render_result *r, tt_heat_metric metric)
{
    if (!r || (int)metric < 0 || (int)metric >= TT_HEAT_METRIC_COUNT) return NULL;
    return r->pixel_stats[metric];
}

static void put_u32_le(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

/* The hit buffer of the conventions: 12 bytes a pixel, little-endian
 * whatever the host's byte order. */
static void encode_hits(const tt_frame *f, int shadows, uint8_t *out)
{
    size_t n = (size_t)f->width * f->height;
    for (size_t i = 0; i < n; i++) {
        uint32_t tbits;
        float t = f->prim[i] == TT_INVALID_ID ? TT_INF : f->t[i];
        memcpy(&tbits, &t, sizeof tbits);
        put_u32_le(out + 12 * i, f->prim[i]);
        put_u32_le(out + 12 * i + 4, tbits);
        put_u32_le(out + 12 * i + 8, shadows ? f->shadow[i] : 0u);
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double mrays(uint64_t rays, double seconds)
{
    return seconds > 0.0 ? (double)rays / seconds * 1e-6 : 0.0;
}

static tt_status validate(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                          const tt_camera *camera, const tt_render_options *o)
{
    if (!scene || !accel || !camera)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_render: NULL scene, accel or camera");
    if (accel->scene != scene)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_render: the structure was built for another scene");
    if (o->width == 0 || o->height == 0)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_render: image size %ux%u is empty",
                        o->width, o->height);
    if (o->packets > TT_PACKETS_ON)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_render: packets %u is not TT_PACKETS_AUTO, _OFF or _ON", o->packets);
    if (o->repeat < 1)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_render: repeat %d is less than 1",
                        o->repeat);
    if ((o->stats || o->keep_pixel_stats) &&
        (!accel->vt->intersect_stats || !accel->vt->occluded_stats))
        return tt_error(ctx, TT_ERR_UNSUPPORTED,
                        "tt_render: structure '%s' has no counting traversal for statistics",
                        accel->vt->name);
    const char *problem = tt_camera_problem(camera);
    if (problem) return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_render: bad camera: %s", problem);
    if (o->device != TT_DEVICE_CPU && o->device != TT_DEVICE_GPU)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_render: unknown device %d",
                        (int)o->device);
    if (o->device == TT_DEVICE_GPU) {
        /* what the GPU supports first: it holds whatever the machine */
        tt_status st = tt_render_gpu_validate(ctx, accel);
        if (st == TT_OK) st = tt_device_check(ctx, TT_DEVICE_GPU);
        return st;
    }
    return TT_OK;
}

/* Allocates the frame's per-pixel arrays and the result's kept buffers. */
static tt_status allocate(tt_context *ctx, const tt_render_options *o, tt_frame *f,
                          tt_render_result *r)
{
    size_t n = (size_t)o->width * o->height;
    f->prim = tt_alloc_array(ctx, n, sizeof *f->prim);
    f->t = tt_alloc_array(ctx, n, sizeof *f->t);
    f->end_hint = tt_alloc_array(ctx, n, sizeof *f->end_hint);
    f->shadow = tt_calloc(ctx, n, sizeof *f->shadow);
    int ok = f->prim && f->t && f->end_hint && f->shadow;
    if (o->keep_hits) {
        r->hits = tt_alloc_array(ctx, n, 12);
        r->hits_size = n * 12;
        ok = ok && r->hits;
    }
    if (o->keep_image) {
        r->image = tt_alloc_array(ctx, n, 3);
        ok = ok && r->image;
    }
    if (o->keep_pixel_stats) {
        for (int m = 0; m < TT_HEAT_METRIC_COUNT; m++) {
            r->pixel_stats[m] = tt_calloc(ctx, n, sizeof(uint32_t));
            f->pixel_stats[m] = r->pixel_stats[m];
            ok = ok && r->pixel_stats[m];
        }
    }
    if (!ok)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_render: out of memory for a %ux%u image",
                        o->width, o->height);
    return TT_OK;
}

static void free_frame(tt_context *ctx, tt_frame *f)
{
    tt_free(ctx, f->prim);
    tt_free(ctx, f->t);
    tt_free(ctx, f->end_hint);
    tt_free(ctx, f->shadow);
}

static void init_frame(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                       const tt_camera *camera, const tt_render_options *o, tt_frame *f)
{
    memset(f, 0, sizeof *f);
    f->scene = scene;
    f->accel = accel;
    f->camera = camera;
    f->width = o->width;
    f->height = o->height;
    f->tiles_x = (o->width + TT_TILE - 1) / TT_TILE;
    f->tiles_y = (o->height + TT_TILE - 1) / TT_TILE;
    f->threads = tt_context_team(ctx);
    f->eps = 1e-4f * tt_scene_diagonal(scene);
    tt_camera_basis_init(&f->basis, camera, o->width, o->height);
    /* Only a structure that takes caster hints is handed them (the option
     * is the kd-tree's; other structures ignore its slot). */
    f->caster_hint = (accel->vt->caps & TT_CAP_CASTER_HINT) &&
                     accel->options.kdtree.shadow_caster_hint;
    /* packets where the structure has them (the caster hint is a per-ray
     * chain through a tile's shadow rays: those stay single rays) */
    f->packets = accel->vt->intersect_packet && accel->vt->occluded_packet &&
                         (!accel->vt->packets_for || accel->vt->packets_for(accel))
                     ? o->packets
                     : TT_PACKETS_OFF;
    /* one point location for all primary rays (they share the eye) */
    f->eye_hint = accel->vt->locate ? accel->vt->locate(accel, camera->eye) : TT_INVALID_ID;
}

/* Min of the primary and shadow times over the K repeats, min and median
 * of their totals (the CPU and the GPU path record the same way). */
static tt_status reduce_times(tt_context *ctx, const double *primary_s, const double *shadow_s,
                              int repeat, tt_render_summary *s)
{
    double *totals = tt_alloc_array(ctx, (size_t)repeat, sizeof *totals);
    if (!totals) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_render: out of memory");
    s->primary_s = s->shadow_s = s->trace_s = INFINITY;
    for (int k = 0; k < repeat; k++) {
        totals[k] = primary_s[k] + shadow_s[k];
        s->primary_s = fmin(s->primary_s, primary_s[k]);
        s->shadow_s = fmin(s->shadow_s, shadow_s[k]);
        s->trace_s = fmin(s->trace_s, totals[k]);
    }
    qsort(totals, (size_t)repeat, sizeof *totals, cmp_double);
    int mid = repeat / 2;
    s->trace_median_s = repeat % 2 ? totals[mid] : 0.5 * (totals[mid - 1] + totals[mid]);
    tt_free(ctx, totals);
    return TT_OK;
}

/* The CPU's timed passes, K times, into primary_s[k] and shadow_s[k]. */
static void timed_passes(tt_frame *f, const tt_render_options *o, double *primary_s,
                         double *shadow_s)
{
    for (int k = 0; k < o->repeat; k++) {
        double t0 = tt_now();
        tt_frame_trace_primary(f);
        double t1 = tt_now();
        if (o->shadows) tt_frame_trace_shadow(f);
        double t2 = tt_now();
        primary_s[k] = t1 - t0;
        shadow_s[k] = t2 - t1;
    }
}

/* The passes on the CPU: the counting pass first, so that the buffers
 * finally hold the fast variant's results (the ones the timings are about),
 * then the timed ones. */
static void cpu_passes(tt_frame *f, const tt_render_options *o, double *primary_s,
                       double *shadow_s, tt_render_summary *s)
{
    if (o->stats || o->keep_pixel_stats) {
        tt_frame_trace_primary_stats(f, &s->primary_stats);
        if (o->shadows) tt_frame_trace_shadow_stats(f, &s->shadow_stats);
        s->has_stats = 1;
        const tt_packet_stats *ps[2] = {&f->packet_primary, &f->packet_shadow};
        tt_packet_counts *pc[2] = {&s->primary_packets, &s->shadow_packets};
        for (int k = 0; k < 2; k++) {
            pc[k]->packets = ps[k]->packets;
            pc[k]->node_visits = ps[k]->node_visits;
            pc[k]->active_lanes = ps[k]->active_lanes;
            pc[k]->fallback_rays = ps[k]->fallback_rays;
        }
    }
    s->packets = f->packets != TT_PACKETS_OFF;
    timed_passes(f, o, primary_s, shadow_s);
}

static void count_results(const tt_frame *f, int shadows, tt_render_summary *s)
{
    size_t n = (size_t)f->width * f->height;
    int traced_shadows = shadows && f->camera->has_light;
    s->primary_rays = n;
    s->primary_hits = s->shadow_rays = s->shadow_occluded = 0;
    for (size_t i = 0; i < n; i++) {
        if (f->prim[i] == TT_INVALID_ID) continue;
        s->primary_hits++;
        if (traced_shadows) {
            s->shadow_rays++;
            s->shadow_occluded += f->shadow[i];
        }
    }
    s->primary_mrays_per_s = mrays(s->primary_rays, s->primary_s);
    s->shadow_mrays_per_s = mrays(s->shadow_rays, s->shadow_s);
    s->mrays_per_s = mrays(s->primary_rays + s->shadow_rays, s->trace_s);
}

static tt_status render_entered(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                                const tt_camera *camera, const tt_render_options *options,
                                tt_render_result **out);

tt_status tt_render(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                    const tt_camera *camera, const tt_render_options *options,
                    tt_render_result **out)
{
    if (!out) return TT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    tt_render_options o;
    if (options) o = *options;
    else tt_render_options_default(&o);
    tt_status st = validate(ctx, scene, accel, camera, &o);
    if (st != TT_OK) return st;
    st = tt_accel_trace_enter(accel, "tt_render");
    if (st != TT_OK) return st;
    st = render_entered(ctx, scene, accel, camera, &o, out);
    tt_accel_trace_leave(accel);
    return st;
}

/* tt_render inside the scene's trace bracket (io/scene_guard.h). */
static tt_status render_entered(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                                const tt_camera *camera, const tt_render_options *options,
                                tt_render_result **out)
{
    tt_render_options o = *options;
    tt_status st;
    tt_render_result *r = tt_calloc(ctx, 1, sizeof *r);
    if (!r) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_render: out of memory");
    r->ctx = ctx;
    tt_frame f;
    init_frame(ctx, scene, accel, camera, &o, &f);
    st = allocate(ctx, &o, &f, r);
    if (st != TT_OK) goto fail;

    tt_render_summary *s = &r->summary;
    s->width = o.width;
    s->height = o.height;
    s->device = o.device;
    double *times = tt_alloc_array(ctx, 2 * (size_t)o.repeat, sizeof *times);
    if (!times) {
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_render: out of memory");
        goto fail;
    }
    if (o.device == TT_DEVICE_GPU) {
        st = tt_render_gpu_passes(ctx, &f, &o, times, times + o.repeat, r->image, s);
    } else {
        s->threads = f.threads;
        cpu_passes(&f, &o, times, times + o.repeat, s);
    }
    if (st == TT_OK) st = reduce_times(ctx, times, times + o.repeat, o.repeat, s);
    tt_free(ctx, times);
    if (st != TT_OK) goto fail;
    count_results(&f, o.shadows, s);
    if (r->hits) encode_hits(&f, o.shadows, r->hits);
    if (r->image && o.device == TT_DEVICE_CPU) tt_frame_shade(&f, o.shadows, r->image);
    free_frame(ctx, &f);
    *out = r;
    return TT_OK;
fail:
    free_frame(ctx, &f);
    tt_render_result_destroy(r);
    return st;
}

/* ---- a frame traced in parts (frame.h; the MPI renderer) ---- */

tt_status tt_frame_open(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                        const tt_camera *camera, const tt_render_options *o, tt_frame *f)
{
    memset(f, 0, sizeof *f);
    tt_status st = validate(ctx, scene, accel, camera, o);
    if (st != TT_OK) return st;
    if (o->device != TT_DEVICE_CPU)
        return tt_error(ctx, TT_ERR_UNSUPPORTED, "tt_render: a frame in parts traces on the CPU");
    init_frame(ctx, scene, accel, camera, o, f);
    tt_render_options arrays = *o; /* the frame's own arrays only */
    arrays.keep_hits = arrays.keep_image = arrays.keep_pixel_stats = 0;
    tt_render_result scratch;
    memset(&scratch, 0, sizeof scratch);
    st = allocate(ctx, &arrays, f, &scratch);
    for (int m = 0; m < TT_HEAT_METRIC_COUNT && st == TT_OK && o->keep_pixel_stats; m++) {
        f->pixel_stats[m] = tt_calloc(ctx, (size_t)o->width * o->height, sizeof(uint32_t));
        if (!f->pixel_stats[m]) st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_render: out of memory");
    }
    if (st != TT_OK) tt_frame_close(ctx, f);
    return st;
}

void tt_frame_close(tt_context *ctx, tt_frame *f)
{
    free_frame(ctx, f);
    for (int m = 0; m < TT_HEAT_METRIC_COUNT; m++) tt_free(ctx, f->pixel_stats[m]);
    memset(f, 0, sizeof *f);
}

tt_status tt_frame_result(tt_context *ctx, const tt_frame *f, const tt_render_options *o,
                          const tt_render_summary *s, tt_render_result **out)
{
    *out = NULL;
    tt_render_result *r = tt_calloc(ctx, 1, sizeof *r);
    if (!r) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_render: out of memory");
    r->ctx = ctx;
    r->summary = *s;
    const tt_render_options kept = *o;
    size_t n = (size_t)o->width * o->height;
    int ok = 1;
    if (kept.keep_hits) {
        r->hits = tt_alloc_array(ctx, n, 12);
        r->hits_size = n * 12;
        ok = r->hits != NULL;
    }
    if (kept.keep_image) ok = ok && (r->image = tt_alloc_array(ctx, n, 3)) != NULL;
    for (int m = 0; m < TT_HEAT_METRIC_COUNT && kept.keep_pixel_stats; m++) {
        r->pixel_stats[m] = tt_alloc_array(ctx, n, sizeof(uint32_t));
        ok = ok && r->pixel_stats[m];
        if (r->pixel_stats[m]) memcpy(r->pixel_stats[m], f->pixel_stats[m], n * sizeof(uint32_t));
    }
    if (!ok) {
        tt_render_result_destroy(r);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "tt_render: out of memory for a %ux%u image",
                        o->width, o->height);
    }
    count_results(f, o->shadows, &r->summary);
    if (r->hits) encode_hits(f, o->shadows, r->hits);
    if (r->image) tt_frame_shade(f, o->shadows, r->image);
    *out = r;
    return TT_OK;
}
