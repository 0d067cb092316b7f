/* The R-tree on the GPU (Feldmann 2015, section 5): the packed level-order
 * arrays in linear device memory, read through the read-only data cache
 * (TT_LDG in the traversal templates); the tree's shape (M, L, the level
 * offsets Delta_L and group offsets) in __constant__ memory; one thread per
 * ray. The traversals are the CPU's templates, compiled here as device code
 * through gpu_pixel_rtree.h. The compact layout (rtc_layout.h): its node
 * records and triangle blocks in linear device memory, the tree's header
 * in __constant__ memory, traced by its stackless traversal. */
#include "cuda/gpu_internal.h"

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "cuda/gpu_pixel_rtree.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "cuda/gpu_pixel_rtree.h"
#undef TT_STATS

/* The tree with device pointers, and the frame. */
static __constant__ tt_rtree_packed c_tree;
static __constant__ tt_gpu_frame_const c_frame;
static __constant__ float c_root_box[6];
static __constant__ tt_rtc c_rtc;

/* Primary rays with traversal WHICH (stackless or ordered). */
template <int WHICH, bool STATS>
__global__ void __launch_bounds__(TT_GPU_THREADS)
    rt_primary_kernel(uint32_t *prim, float *dist, tt_gpu_pixel_stats pixel,
                      unsigned long long *sum)
{
    const uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    const uint32_t w = c_frame.basis.width;
    tt_ray_stats one = {0, 0, 0, 0, 0, 0};
    if (x < w && y < c_frame.basis.height) {
        const size_t i = (size_t)y * w + x;
        uint32_t p;
        float d;
        if (STATS) {
            tt_gpu_rt_primary_stats(&c_tree, WHICH, &c_frame.basis, x, y, &p, &d, &one);
            tt_gpu_store_pixel_stats(pixel, i, &one);
        } else {
            tt_gpu_rt_primary(&c_tree, WHICH, &c_frame.basis, x, y, &p, &d, NULL);
        }
        prim[i] = p;
        dist[i] = d;
    }
    if (STATS) tt_gpu_block_sum(&one, sum);
}

/* Shadow rays of the primary hits with TRAVERSAL (auto: by origin). */
template <int TRAVERSAL, bool STATS>
__global__ void __launch_bounds__(TT_GPU_THREADS)
    rt_shadow_kernel(const uint32_t *prim, const float *dist, const float *tri, uint8_t *shadow,
                     unsigned long long *sum)
{
    const uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    const uint32_t w = c_frame.basis.width;
    tt_ray_stats one = {0, 0, 0, 0, 0, 0};
    if (x < w && y < c_frame.basis.height) {
        const size_t i = (size_t)y * w + x;
        const uint32_t p = prim[i];
        int occluded = 0;
        if (p != TT_INVALID_ID) {
            if (STATS)
                occluded = tt_gpu_rt_shadow_stats(&c_tree, TRAVERSAL, c_root_box, &c_frame.basis,
                                                  tri, c_frame.light, c_frame.eps, x, y, p,
                                                  dist[i], &one);
            else
                occluded = tt_gpu_rt_shadow(&c_tree, TRAVERSAL, c_root_box, &c_frame.basis, tri,
                                            c_frame.light, c_frame.eps, x, y, p, dist[i], NULL);
        }
        shadow[i] = (uint8_t)(occluded != 0);
    }
    if (STATS) tt_gpu_block_sum(&one, sum);
}

/* The compact layout's primary and shadow rays (stackless traversal). */
template <bool STATS>
__global__ void __launch_bounds__(TT_GPU_THREADS)
    rtc_primary_kernel(uint32_t *prim, float *dist, tt_gpu_pixel_stats pixel,
                       unsigned long long *sum)
{
    const uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    const uint32_t w = c_frame.basis.width;
    tt_ray_stats one = {0, 0, 0, 0, 0, 0};
    if (x < w && y < c_frame.basis.height) {
        const size_t i = (size_t)y * w + x;
        uint32_t p;
        float d;
        if (STATS) {
            tt_gpu_rtc_primary_stats(&c_rtc, &c_frame.basis, x, y, &p, &d, &one);
            tt_gpu_store_pixel_stats(pixel, i, &one);
        } else {
            tt_gpu_rtc_primary(&c_rtc, &c_frame.basis, x, y, &p, &d, NULL);
        }
        prim[i] = p;
        dist[i] = d;
    }
    if (STATS) tt_gpu_block_sum(&one, sum);
}

template <bool STATS>
__global__ void __launch_bounds__(TT_GPU_THREADS)
    rtc_shadow_kernel(const uint32_t *prim, const float *dist, const float *tri, uint8_t *shadow,
                      unsigned long long *sum)
{
    const uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    const uint32_t w = c_frame.basis.width;
    tt_ray_stats one = {0, 0, 0, 0, 0, 0};
    if (x < w && y < c_frame.basis.height) {
        const size_t i = (size_t)y * w + x;
        const uint32_t p = prim[i];
        int occluded = 0;
        if (p != TT_INVALID_ID) {
            if (STATS)
                occluded = tt_gpu_rtc_shadow_stats(&c_rtc, &c_frame.basis, tri, c_frame.light,
                                                   c_frame.eps, x, y, p, dist[i], &one);
            else
                occluded = tt_gpu_rtc_shadow(&c_rtc, &c_frame.basis, tri, c_frame.light,
                                             c_frame.eps, x, y, p, dist[i], NULL);
        }
        shadow[i] = (uint8_t)(occluded != 0);
    }
    if (STATS) tt_gpu_block_sum(&one, sum);
}

/* The compact layout's two arrays (cudaMalloc aligns to 256 bytes, more
 * than the records' and blocks' 64). */
static tt_status rtc_upload(const tt_gpu_structure *s, const tt_gpu_frame_const *fc,
                            tt_gpu_arrays *arrays, tt_gpu_err *e)
{
    tt_rtc d = s->rtc;
    void *p;
    tt_status st;
    if ((st = tt_gpu_upload_array(arrays, s->rtc.node,
                                  (size_t)s->rtc.nodes * s->rtc.words * sizeof(float), &p, e,
                                  "rtree compact nodes")) != TT_OK)
        return st;
    d.node = (const float *)p;
    if ((st = tt_gpu_upload_array(arrays, s->rtc.block,
                                  (size_t)(s->rtc.blocks ? s->rtc.blocks : 1) * sizeof(tt_tri_block),
                                  &p, e, "rtree compact triangle blocks")) != TT_OK)
        return st;
    d.block = (const tt_tri_block *)p;
    TT_GPU_TRY(e, cudaMemcpyToSymbol(c_rtc, &d, sizeof d), "rtree compact constants");
    TT_GPU_TRY(e, cudaMemcpyToSymbol(c_frame, fc, sizeof *fc), "frame constants");
    return TT_OK;
}

static tt_status rt_upload(const tt_gpu_structure *s, const tt_gpu_frame_const *fc,
                           const float *, tt_gpu_arrays *arrays, tt_gpu_err *e)
{
    if (s->rtree_compact) return rtc_upload(s, fc, arrays, e);
    const tt_rtree_packed *h = &s->rtree;
    tt_rtree_packed d = *h;
    void *p;
    tt_status st;
    if ((st = tt_gpu_upload_array(arrays, h->box, s->rtree_box_floats * sizeof(float), &p, e,
                                  "rtree boxes")) != TT_OK)
        return st;
    d.box = (const float *)p;
    if ((st = tt_gpu_upload_array(arrays, h->count, (size_t)h->delta[0] * sizeof(uint8_t), &p, e,
                                  "rtree counts")) != TT_OK)
        return st;
    d.count = (const uint8_t *)p;
    if ((st = tt_gpu_upload_array(arrays, h->leaf_start,
                                  ((size_t)h->leaf_slots + 1) * sizeof(uint32_t), &p, e,
                                  "rtree leaf ranges")) != TT_OK)
        return st;
    d.leaf_start = (const uint32_t *)p;
    if ((st = tt_gpu_upload_array(arrays, h->tri, (size_t)h->triangles * 9 * sizeof(float), &p, e,
                                  "rtree triangles")) != TT_OK)
        return st;
    d.tri = (const float *)p;
    if ((st = tt_gpu_upload_array(arrays, h->prim, (size_t)h->triangles * sizeof(uint32_t), &p, e,
                                  "rtree triangle ids")) != TT_OK)
        return st;
    d.prim = (const uint32_t *)p;
    TT_GPU_TRY(e, cudaMemcpyToSymbol(c_tree, &d, sizeof d), "rtree constants");
    TT_GPU_TRY(e, cudaMemcpyToSymbol(c_frame, fc, sizeof *fc), "frame constants");
    TT_GPU_TRY(e, cudaMemcpyToSymbol(c_root_box, s->rtree_root_box, sizeof s->rtree_root_box),
               "rtree root box");
    return TT_OK;
}

template <bool STATS>
static void rt_primary_launch(int which, const tt_gpu_io *io)
{
    const dim3 grid = tt_gpu_grid(io->width, io->height), block = tt_gpu_block();
    if (which == TT_RTREE_ORDERED)
        rt_primary_kernel<TT_RTREE_ORDERED, STATS><<<grid, block>>>(io->prim, io->t, io->pixel,
                                                                      io->sum);
    else
        rt_primary_kernel<TT_RTREE_STACKLESS, STATS><<<grid, block>>>(io->prim, io->t, io->pixel,
                                                                        io->sum);
}

/* The primary rays all start at the eye: its traversal (eye_hint, from
 * rt_locate on the host) holds for the whole pass. */
static void rt_primary(const tt_gpu_structure *s, const tt_gpu_frame_const *fc,
                       const tt_gpu_io *io, int stats)
{
    if (s->rtree_compact) {
        const dim3 grid = tt_gpu_grid(io->width, io->height), block = tt_gpu_block();
        if (stats) rtc_primary_kernel<true><<<grid, block>>>(io->prim, io->t, io->pixel, io->sum);
        else rtc_primary_kernel<false><<<grid, block>>>(io->prim, io->t, io->pixel, io->sum);
        return;
    }
    if (stats) rt_primary_launch<true>((int)fc->eye_hint, io);
    else rt_primary_launch<false>((int)fc->eye_hint, io);
}

template <bool STATS>
static void rt_shadow_launch(int traversal, const tt_gpu_io *io)
{
    const dim3 grid = tt_gpu_grid(io->width, io->height), block = tt_gpu_block();
    if (traversal == TT_RTREE_ORDERED)
        rt_shadow_kernel<TT_RTREE_ORDERED, STATS><<<grid, block>>>(io->prim, io->t, io->tri,
                                                                     io->shadow, io->sum);
    else if (traversal == TT_RTREE_STACKLESS)
        rt_shadow_kernel<TT_RTREE_STACKLESS, STATS><<<grid, block>>>(io->prim, io->t, io->tri,
                                                                       io->shadow, io->sum);
    else
        rt_shadow_kernel<TT_RTREE_AUTO, STATS><<<grid, block>>>(io->prim, io->t, io->tri,
                                                                  io->shadow, io->sum);
}

static void rt_shadow(const tt_gpu_structure *s, const tt_gpu_io *io, int stats)
{
    if (s->rtree_compact) {
        const dim3 grid = tt_gpu_grid(io->width, io->height), block = tt_gpu_block();
        if (stats)
            rtc_shadow_kernel<true><<<grid, block>>>(io->prim, io->t, io->tri, io->shadow, io->sum);
        else
            rtc_shadow_kernel<false><<<grid, block>>>(io->prim, io->t, io->tri, io->shadow,
                                                      io->sum);
        return;
    }
    if (stats) rt_shadow_launch<true>(s->traversal, io);
    else rt_shadow_launch<false>(s->traversal, io);
}

const tt_gpu_module tt_gpu_rtree_module = {rt_upload, rt_primary, rt_shadow};
