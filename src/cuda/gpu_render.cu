/* One frame on the GPU: upload (timed), an optional counting pass, K timed
 * passes (CUDA events around each kernel), the copy back (timed), and the
 * device memory freed on every path. */
#include <string.h>

#include "cuda/gpu_internal.h"
#include "render/shade_hd.h"

namespace {

/* The image from the final results, shaded as on the CPU (shade_hd.h). */
__global__ void __launch_bounds__(TT_GPU_THREADS)
    shade_kernel(tt_gpu_frame_const fc, int has_light, int shadows, const float *tri,
                 const uint32_t *prim, const float *t, const uint8_t *shadow, uint8_t *rgb)
{
    const uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= fc.basis.width || y >= fc.basis.height) return;
    const size_t i = (size_t)y * fc.basis.width + x;
    tt_shade_pixel(&fc.basis, tri, fc.light, has_light, shadows, x, y, prim[i], t[i], shadow[i],
                   rgb + 3 * i);
}

/* Everything the frame allocates on the device, freed by the destructor. */
struct frame_resources {
    tt_gpu_arrays arrays = {};  /* the structure's and the scene's arrays */
    void *buffers[12] = {};     /* the per-pixel buffers and the counters */
    int buffer_count = 0;
    cudaEvent_t events[4] = {};
    int event_count = 0;

    ~frame_resources()
    {
        for (int i = 0; i < arrays.n; i++) cudaFree(arrays.p[i]);
        for (int i = 0; i < buffer_count; i++) cudaFree(buffers[i]);
        for (int i = 0; i < event_count; i++) cudaEventDestroy(events[i]);
    }
};

tt_status alloc_buffer(frame_resources *r, size_t bytes, void **out, tt_gpu_err *e,
                       const char *what)
{
    TT_GPU_TRY(e, cudaMalloc(out, bytes), what);
    r->buffers[r->buffer_count++] = *out;
    return TT_OK;
}

const tt_gpu_module *module_of(tt_gpu_kind kind)
{
    switch (kind) {
    case TT_GPU_RTREE:
        return &tt_gpu_rtree_module;
    case TT_GPU_KDTREE:
        return &tt_gpu_kdtree_module;
    default:
        return NULL;
    }
}

/* Elapsed seconds between two recorded events (waits for the second). */
tt_status seconds(cudaEvent_t a, cudaEvent_t b, double *out, tt_gpu_err *e)
{
    float ms = 0.0f;
    TT_GPU_TRY(e, cudaEventSynchronize(b), "waiting for the GPU");
    TT_GPU_TRY(e, cudaEventElapsedTime(&ms, a, b), "timing");
    *out = (double)ms * 1e-3;
    return TT_OK;
}

tt_status allocate_io(frame_resources *r, const tt_gpu_frame *f, tt_gpu_io *io, tt_gpu_err *e)
{
    const size_t n = (size_t)io->width * io->height;
    tt_status st;
    void *p;
    if ((st = alloc_buffer(r, n * sizeof(uint32_t), &p, e, "hit buffer")) != TT_OK) return st;
    io->prim = (uint32_t *)p;
    if ((st = alloc_buffer(r, n * sizeof(float), &p, e, "hit buffer")) != TT_OK) return st;
    io->t = (float *)p;
    if ((st = alloc_buffer(r, n * sizeof(uint32_t), &p, e, "end hints")) != TT_OK) return st;
    io->end = (uint32_t *)p;
    if ((st = alloc_buffer(r, n, &p, e, "shadow flags")) != TT_OK) return st;
    io->shadow = (uint8_t *)p;
    /* all lit until a shadow pass says otherwise (none without a light) */
    TT_GPU_TRY(e, cudaMemset(io->shadow, 0, n), "shadow flags");
    if (f->image) {
        if ((st = alloc_buffer(r, 3 * n, &p, e, "image")) != TT_OK) return st;
        io->image = (uint8_t *)p;
    }
    if ((st = alloc_buffer(r, 6 * sizeof(unsigned long long), &p, e, "statistics")) != TT_OK)
        return st;
    io->sum = (unsigned long long *)p;
    if (f->pixel_stats[0]) {
        for (int m = 0; m < 5; m++) {
            if ((st = alloc_buffer(r, n * sizeof(uint32_t), &p, e, "per-pixel counts")) != TT_OK)
                return st;
            io->pixel.m[m] = (uint32_t *)p;
        }
    }
    return TT_OK;
}

/* A pass's counters from the device into *out. */
tt_status read_sum(const tt_gpu_io *io, tt_ray_stats *out, tt_gpu_err *e)
{
    unsigned long long v[6];
    TT_GPU_TRY(e, cudaMemcpy(v, io->sum, sizeof v, cudaMemcpyDeviceToHost), "statistics");
    out->rays = v[0];
    out->nodes = v[1];
    out->interior = v[2];
    out->leaves = v[3];
    out->boxes = v[4];
    out->triangles = v[5];
    return TT_OK;
}

tt_status counting_pass(const tt_gpu_module *mod, const tt_gpu_structure *s,
                        const tt_gpu_frame_const *fc, const tt_gpu_io *io, int shadows,
                        tt_gpu_frame *f, tt_gpu_err *e)
{
    tt_status st;
    TT_GPU_TRY(e, cudaMemset(io->sum, 0, 6 * sizeof(unsigned long long)), "statistics");
    mod->primary(s, fc, io, 1);
    TT_GPU_TRY(e, cudaGetLastError(), "the counting primary pass");
    if ((st = read_sum(io, &f->primary_stats, e)) != TT_OK) return st;
    if (shadows) {
        TT_GPU_TRY(e, cudaMemset(io->sum, 0, 6 * sizeof(unsigned long long)), "statistics");
        mod->shadow(s, io, 1);
        TT_GPU_TRY(e, cudaGetLastError(), "the counting shadow pass");
        if ((st = read_sum(io, &f->shadow_stats, e)) != TT_OK) return st;
    }
    return TT_OK;
}

tt_status timed_passes(const tt_gpu_module *mod, const tt_gpu_structure *s,
                       const tt_gpu_frame_const *fc, const tt_gpu_io *io, int shadows,
                       const cudaEvent_t *ev, tt_gpu_frame *f, tt_gpu_err *e)
{
    tt_status st;
    for (int k = 0; k < f->repeat; k++) {
        TT_GPU_TRY(e, cudaEventRecord(ev[0]), "timing");
        mod->primary(s, fc, io, 0);
        TT_GPU_TRY(e, cudaGetLastError(), "the primary pass");
        TT_GPU_TRY(e, cudaEventRecord(ev[1]), "timing");
        if (shadows) {
            mod->shadow(s, io, 0);
            TT_GPU_TRY(e, cudaGetLastError(), "the shadow pass");
        }
        TT_GPU_TRY(e, cudaEventRecord(ev[2]), "timing");
        if ((st = seconds(ev[0], ev[1], &f->primary_s[k], e)) != TT_OK) return st;
        if ((st = seconds(ev[1], ev[2], &f->shadow_s[k], e)) != TT_OK) return st;
    }
    return TT_OK;
}

tt_status download(const tt_gpu_io *io, int shadows, tt_gpu_frame *f, tt_gpu_err *e)
{
    const size_t n = (size_t)io->width * io->height;
    TT_GPU_TRY(e, cudaMemcpy(f->prim, io->prim, n * sizeof(uint32_t), cudaMemcpyDeviceToHost),
               "hit buffer");
    TT_GPU_TRY(e, cudaMemcpy(f->t, io->t, n * sizeof(float), cudaMemcpyDeviceToHost),
               "hit buffer");
    if (shadows)
        TT_GPU_TRY(e, cudaMemcpy(f->shadow, io->shadow, n, cudaMemcpyDeviceToHost),
                   "shadow flags");
    if (f->image)
        TT_GPU_TRY(e, cudaMemcpy(f->image, io->image, 3 * n, cudaMemcpyDeviceToHost), "image");
    if (f->pixel_stats[0])
        for (int m = 0; m < 5; m++)
            TT_GPU_TRY(e, cudaMemcpy(f->pixel_stats[m], io->pixel.m[m], n * sizeof(uint32_t),
                                     cudaMemcpyDeviceToHost),
                       "per-pixel counts");
    return TT_OK;
}

tt_status run(const tt_gpu_module *mod, const tt_gpu_structure *s, tt_gpu_frame *f,
              frame_resources *r, tt_gpu_err *e)
{
    tt_status st;
    for (int i = 0; i < 4; i++) {
        TT_GPU_TRY(e, cudaEventCreate(&r->events[i]), "timing");
        r->event_count++;
    }
    const cudaEvent_t *ev = r->events;
    tt_gpu_io io = {};
    io.width = f->basis.width;
    io.height = f->basis.height;
    tt_gpu_frame_const fc = {};
    fc.basis = f->basis;
    memcpy(fc.light, f->light, sizeof fc.light);
    fc.eps = f->eps;
    fc.eye_hint = f->eye_hint;
    const int shadows = f->shadows && f->has_light;

    /* upload: the scene's triangles (load order), then the structure */
    TT_GPU_TRY(e, cudaEventRecord(ev[0]), "timing");
    void *tri;
    if ((st = tt_gpu_upload_array(&r->arrays, s->tri, (size_t)s->triangles * 9 * sizeof(float),
                                  &tri, e, "scene triangles")) != TT_OK)
        return st;
    io.tri = (const float *)tri;
    if ((st = mod->upload(s, &fc, io.tri, &r->arrays, e)) != TT_OK) return st;
    TT_GPU_TRY(e, cudaEventRecord(ev[1]), "timing");
    if ((st = seconds(ev[0], ev[1], &f->upload_s, e)) != TT_OK) return st;

    if ((st = allocate_io(r, f, &io, e)) != TT_OK) return st;
    /* counting first, so that the buffers end with the fast variant's
     * results, as on the CPU */
    if (f->stats && (st = counting_pass(mod, s, &fc, &io, shadows, f, e)) != TT_OK) return st;
    if ((st = timed_passes(mod, s, &fc, &io, shadows, ev, f, e)) != TT_OK) return st;
    if (f->image) {
        shade_kernel<<<tt_gpu_grid(io.width, io.height), tt_gpu_block()>>>(
            fc, f->has_light, f->shadows, io.tri, io.prim, io.t, io.shadow, io.image);
        TT_GPU_TRY(e, cudaGetLastError(), "shading");
    }

    TT_GPU_TRY(e, cudaEventRecord(ev[3]), "timing");
    if ((st = download(&io, shadows, f, e)) != TT_OK) return st;
    TT_GPU_TRY(e, cudaEventRecord(ev[2]), "timing");
    return seconds(ev[3], ev[2], &f->download_s, e);
}

} // namespace

tt_status tt_gpu_render(const tt_gpu_structure *s, tt_gpu_frame *f, char *msg, size_t msg_size)
{
    tt_gpu_err e = {msg, msg_size};
    if (msg && msg_size) msg[0] = '\0';
    tt_status st = tt_gpu_probe(f->device_name, sizeof f->device_name, msg, msg_size);
    if (st != TT_OK) return st;
    const tt_gpu_module *mod = module_of(s->kind);
    if (!mod) {
        if (msg && msg_size) strncpy(msg, "GPU: unknown structure kind", msg_size - 1);
        return TT_ERR_INTERNAL;
    }
    frame_resources r;
    return run(mod, s, f, &r, &e);
}
