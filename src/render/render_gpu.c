/* The C side of the GPU path: checks what the GPU supports, hands the
 * packed structure and the frame to the CUDA tracer (src/cuda/gpu.h) as
 * plain arrays, and turns its status and message into the context's error.
 * A build without CUDA compiles this file too and says so. */
#include <string.h>

#include "render/render_gpu.h"

#ifdef TT_HAVE_CUDA
#include <pthread.h>

#include "accel/kdtree/kd_tree.h"
#include "accel/rtree/rtree.h"
#include "cuda/gpu.h"
#endif

#ifndef TT_NO_CUDA_REASON
#define TT_NO_CUDA_REASON "nvcc was not found at configure time"
#endif

#define SUPPORTED                                                                          \
    "the GPU traces rtree with the auto, stackless or ordered traversal (in the compact "  \
    "layout: auto or stackless) and kdtree with sltr or htr"

tt_status tt_render_gpu_validate(tt_context *ctx, const tt_accel *accel)
{
    switch (accel->vt->gpu) {
    case TT_ACCEL_GPU_RTREE:
        if (accel->options.rtree.layout == TT_RTREE_LAYOUT_COMPACT &&
            accel->options.rtree.traversal == TT_RTREE_ORDERED)
            return tt_error(ctx, TT_ERR_UNSUPPORTED,
                            "tt_render: " SUPPORTED
                            ", not rtree in the compact layout with the ordered traversal");
        if (accel->options.rtree.traversal == TT_RTREE_STACK)
            return tt_error(ctx, TT_ERR_UNSUPPORTED,
                            "tt_render: " SUPPORTED ", not rtree with the stack traversal");
        return TT_OK;
    case TT_ACCEL_GPU_KDTREE: {
        static const char *const names[] = {"htr", "btr", "sltr", "seq"};
        const tt_kdtree_options *k = &accel->options.kdtree;
        if (k->traversal != TT_KD_SLTR && k->traversal != TT_KD_HTR)
            return tt_error(ctx, TT_ERR_UNSUPPORTED,
                            "tt_render: " SUPPORTED ", not kdtree with the %s traversal",
                            (unsigned)k->traversal < 4 ? names[k->traversal] : "unknown");
        /* one thread per ray has no "previous shadow ray" to take it from */
        if (k->shadow_caster_hint)
            return tt_error(ctx, TT_ERR_UNSUPPORTED,
                            "tt_render: " SUPPORTED ", not the kd-tree's shadow-caster hint");
        return TT_OK;
    }
    case TT_ACCEL_GPU_NONE: break;
    }
    return tt_error(ctx, TT_ERR_UNSUPPORTED, "tt_render: " SUPPORTED ", not %s", accel->vt->name);
}

#ifndef TT_HAVE_CUDA

tt_status tt_device_check(tt_context *ctx, tt_device device)
{
    if (device == TT_DEVICE_CPU) return TT_OK;
    if (device != TT_DEVICE_GPU)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "unknown device %d", (int)device);
    return tt_error(ctx, TT_ERR_UNSUPPORTED, "this build has no CUDA (" TT_NO_CUDA_REASON ")");
}

tt_status tt_render_gpu_passes(tt_context *ctx, tt_frame *f, const tt_render_options *o,
                               double *primary_s, double *shadow_s, uint8_t *image,
                               tt_render_summary *s)
{
    (void)f;
    (void)o;
    (void)primary_s;
    (void)shadow_s;
    (void)image;
    (void)s;
    return tt_device_check(ctx, TT_DEVICE_GPU);
}

#else

/* The tracer keeps the structure's shape in __constant__ memory, one copy
 * per process: frames from several threads take turns. */
static pthread_mutex_t gpu_lock = PTHREAD_MUTEX_INITIALIZER;

tt_status tt_device_check(tt_context *ctx, tt_device device)
{
    if (device == TT_DEVICE_CPU) return TT_OK;
    if (device != TT_DEVICE_GPU)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "unknown device %d", (int)device);
    char name[64], msg[TT_GPU_MESSAGE];
    pthread_mutex_lock(&gpu_lock);
    tt_status st = tt_gpu_probe(name, sizeof name, msg, sizeof msg);
    pthread_mutex_unlock(&gpu_lock);
    return st == TT_OK ? TT_OK : tt_error(ctx, st, "%s", msg);
}

/* The structure's arrays as the tracer wants them. */
static tt_status describe(tt_context *ctx, const tt_accel *accel, tt_gpu_structure *g)
{
    const tt_scene *scene = accel->scene;
    memset(g, 0, sizeof *g);
    if (scene->triangle_count > UINT32_MAX)
        return tt_error(ctx, TT_ERR_UNSUPPORTED, "tt_render: %zu triangles are too many for the GPU",
                        scene->triangle_count);
    g->tri = scene->tri;
    g->triangles = (uint32_t)scene->triangle_count;
    if (accel->vt->gpu == TT_ACCEL_GPU_RTREE) {
        const rt_tree *t = accel->impl;
        g->kind = TT_GPU_RTREE;
        g->traversal = (int)t->traversal;
        g->rtree = t->p;
        g->rtree_box_floats = t->box_floats;
        /* the compact layout: auto means stackless on the GPU */
        g->rtree_compact = t->layout == TT_RTREE_LAYOUT_COMPACT;
        g->rtc = t->compact.c;
        memcpy(g->rtree_root_box, t->root_box, sizeof g->rtree_root_box);
        return TT_OK;
    }
    const tt_kdtree *kd = accel->vt->gpu == TT_ACCEL_GPU_KDTREE ? tt_kdtree_of(accel) : NULL;
    if (kd) {
        g->kind = TT_GPU_KDTREE;
        g->traversal = (int)accel->options.kdtree.traversal;
        g->kd = kd->view;
        g->kd_node_slots = kd->node_slots;
        g->kd_refs = kd->ref_count;
        return TT_OK;
    }
    return tt_render_gpu_validate(ctx, accel);
}

tt_status tt_render_gpu_passes(tt_context *ctx, tt_frame *f, const tt_render_options *o,
                               double *primary_s, double *shadow_s, uint8_t *image,
                               tt_render_summary *s)
{
    tt_gpu_structure g;
    tt_status st = describe(ctx, f->accel, &g);
    if (st != TT_OK) return st;
    tt_gpu_frame gf;
    memset(&gf, 0, sizeof gf);
    gf.basis = f->basis;
    memcpy(gf.light, f->camera->light, sizeof gf.light);
    gf.has_light = f->camera->has_light;
    gf.shadows = o->shadows;
    gf.eps = f->eps;
    gf.eye_hint = f->eye_hint;
    gf.repeat = o->repeat;
    gf.stats = o->stats || o->keep_pixel_stats;
    gf.prim = f->prim;
    gf.t = f->t;
    gf.shadow = f->shadow;
    for (int m = 0; m < TT_HEAT_METRIC_COUNT; m++) gf.pixel_stats[m] = f->pixel_stats[m];
    gf.image = image;
    gf.primary_s = primary_s;
    gf.shadow_s = shadow_s;
    char msg[TT_GPU_MESSAGE];
    pthread_mutex_lock(&gpu_lock);
    st = tt_gpu_render(&g, &gf, msg, sizeof msg);
    pthread_mutex_unlock(&gpu_lock);
    if (st != TT_OK) return tt_error(ctx, st, "tt_render: %s", msg);
    s->upload_s = gf.upload_s;
    s->download_s = gf.download_s;
    memcpy(s->device_name, gf.device_name, sizeof s->device_name);
    if (gf.stats) {
        s->primary_stats = gf.primary_stats;
        s->shadow_stats = gf.shadow_stats;
        s->has_stats = 1;
    }
    return TT_OK;
}

#endif
