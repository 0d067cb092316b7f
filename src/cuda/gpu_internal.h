/* Pieces shared by the CUDA translation units (CUDA C++ only): error
 * reporting into the caller's message buffer, the frame's device buffers,
 * the launch shape, and the per-block reduction of the statistics. */
#ifndef TT_CUDA_GPU_INTERNAL_H
#define TT_CUDA_GPU_INTERNAL_H

#include <cuda_runtime.h>

#include "cuda/gpu.h"

/* Where errors go: the caller's buffer. */
struct tt_gpu_err {
    char *msg;
    size_t size;
};

/* Writes "<what>: <CUDA's error string>" and returns the status for err
 * (TT_ERR_OUT_OF_MEMORY for device memory, TT_ERR_NO_DEVICE for a missing
 * or unusable device, TT_ERR_INTERNAL otherwise). */
tt_status tt_gpu_fail(tt_gpu_err *e, cudaError_t err, const char *what);

#define TT_GPU_TRY(e, call, what)                                                          \
    do {                                                                                   \
        cudaError_t tt_c_ = (call);                                                        \
        if (tt_c_ != cudaSuccess) return tt_gpu_fail((e), tt_c_, (what));                  \
    } while (0)

/* One thread per ray in blocks of 128 (Feldmann 2015), as 16 x 8 pixels so
 * that a warp's rays are neighbours (2 rows of 16) and traverse alike. */
#define TT_GPU_BLOCK_X 16
#define TT_GPU_BLOCK_Y 8
#define TT_GPU_THREADS (TT_GPU_BLOCK_X * TT_GPU_BLOCK_Y)

static inline dim3 tt_gpu_block(void) { return dim3(TT_GPU_BLOCK_X, TT_GPU_BLOCK_Y, 1); }
static inline dim3 tt_gpu_grid(uint32_t w, uint32_t h)
{
    return dim3((w + TT_GPU_BLOCK_X - 1) / TT_GPU_BLOCK_X, (h + TT_GPU_BLOCK_Y - 1) / TT_GPU_BLOCK_Y,
                1);
}

/* The per-pixel heatmap counts of the primary rays (tt_heat_metric order). */
struct tt_gpu_pixel_stats {
    uint32_t *m[5];
};

/* A frame's device buffers, w * h entries each. */
struct tt_gpu_io {
    uint32_t width, height;
    uint32_t *prim;  /* primary hit triangle or TT_INVALID_ID            */
    float *t;        /* primary hit distance or +inf                     */
    uint32_t *end;   /* kd-tree: the node the primary ray ended in        */
    uint8_t *shadow; /* 1 when the shadow ray was occluded                */
    tt_gpu_pixel_stats pixel; /* all NULL unless asked for               */
    unsigned long long *sum;  /* 6 counters in tt_ray_stats order (counting passes) */
    const float *tri;         /* the scene's triangles, load order        */
    uint8_t *image;           /* 3 w h bytes of RGB, when asked for       */
};

/* The frame's constants the kernels of every structure read. */
struct tt_gpu_frame_const {
    tt_camera_basis basis;
    float light[3];
    float eps;
    uint32_t eye_hint;
};

/* Adds each thread's counts to sum[0..5]: first within the block in shared
 * memory, then one global atomic per counter and block. Every thread of
 * the block must call it (it synchronizes). */
__device__ inline void tt_gpu_block_sum(const tt_ray_stats *one, unsigned long long *sum)
{
    __shared__ unsigned long long s[6];
    const unsigned tid = threadIdx.y * blockDim.x + threadIdx.x;
    if (tid < 6) s[tid] = 0;
    __syncthreads();
    const unsigned long long v[6] = {one->rays,  one->nodes, one->interior,
                                     one->leaves, one->boxes, one->triangles};
    for (int k = 0; k < 6; k++)
        if (v[k]) atomicAdd(&s[k], v[k]);
    __syncthreads();
    if (tid < 6 && s[tid]) atomicAdd(&sum[tid], s[tid]);
}

__device__ inline uint32_t tt_gpu_saturate(uint64_t v)
{
    return v > 0xFFFFFFFFull ? 0xFFFFFFFFu : (uint32_t)v;
}

/* The primary ray's counts for the heatmaps, as the CPU renderer stores them. */
__device__ inline void tt_gpu_store_pixel_stats(const tt_gpu_pixel_stats &p, size_t i,
                                                const tt_ray_stats *s)
{
    if (!p.m[0]) return;
    p.m[TT_HEAT_NODES][i] = tt_gpu_saturate(s->nodes);
    p.m[TT_HEAT_INTERIOR][i] = tt_gpu_saturate(s->interior);
    p.m[TT_HEAT_LEAVES][i] = tt_gpu_saturate(s->leaves);
    p.m[TT_HEAT_TRIANGLES][i] = tt_gpu_saturate(s->triangles);
    p.m[TT_HEAT_BOXES][i] = tt_gpu_saturate(s->boxes);
}

/* The device arrays of an uploaded structure; the caller frees them all
 * (cudaFree of the non-NULL ones) whatever happens. */
#define TT_GPU_MAX_ARRAYS 8
struct tt_gpu_arrays {
    void *p[TT_GPU_MAX_ARRAYS];
    int n;
};

/* Allocates `bytes` of device memory, records it in *a and copies `bytes`
 * from host pointer src into it. */
tt_status tt_gpu_upload_array(tt_gpu_arrays *a, const void *src, size_t bytes, void **out,
                              tt_gpu_err *e, const char *what);

/* A structure's part of the tracer (gpu_rtree.cu, gpu_kdtree.cu): upload
 * into device memory and into __constant__ memory of its own translation
 * unit (the frame constants too), then launch a pass over the image
 * (counting variant when stats). Launch errors are collected by the caller
 * with cudaGetLastError. */
struct tt_gpu_module {
    /* tri: the scene's triangles already on the device (load order) */
    tt_status (*upload)(const tt_gpu_structure *s, const tt_gpu_frame_const *fc,
                        const float *tri, tt_gpu_arrays *arrays, tt_gpu_err *e);
    void (*primary)(const tt_gpu_structure *s, const tt_gpu_frame_const *fc, const tt_gpu_io *io,
                    int stats);
    void (*shadow)(const tt_gpu_structure *s, const tt_gpu_io *io, int stats);
};

extern const tt_gpu_module tt_gpu_rtree_module;
extern const tt_gpu_module tt_gpu_kdtree_module;

#endif
