/* The kd-tree with sparse boxes on the GPU (Havran & Bittner 2007 designed
 * SLTR for it): nodes, triangle references and sparse boxes in linear
 * device memory, the view of them in __constant__ memory, one thread per
 * ray; SLTR needs no stack, HTR its fixed one of TT_KD_STACK entries. The
 * traversals are the CPU's templates, compiled here as device code through
 * gpu_pixel_kdtree.h. */
#include "cuda/gpu_internal.h"

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "cuda/gpu_pixel_kdtree.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "cuda/gpu_pixel_kdtree.h"
#undef TT_STATS

static __constant__ tt_kd_view c_kd;
static __constant__ tt_gpu_frame_const c_frame;

/* Primary rays with TRAVERSAL from the eye's node; each ray's end node
 * is kept for its shadow ray. */
template <int TRAVERSAL, bool STATS>
__global__ void __launch_bounds__(TT_GPU_THREADS)
    kd_primary_kernel(uint32_t *prim, float *dist, uint32_t *end, tt_gpu_pixel_stats pixel,
                      unsigned long long *sum)
{
    const uint32_t x = blockIdx.x * blockDim.x + threadIdx.x;
    const uint32_t y = blockIdx.y * blockDim.y + threadIdx.y;
    const uint32_t w = c_frame.basis.width;
    tt_ray_stats one = {0, 0, 0, 0, 0, 0};
    if (x < w && y < c_frame.basis.height) {
        const size_t i = (size_t)y * w + x;
        uint32_t p, e;
        float d;
        if (STATS) {
            tt_gpu_kd_primary_stats(&c_kd, TRAVERSAL, c_frame.eye_hint, &c_frame.basis, x, y, &p,
                                    &d, &e, &one);
            tt_gpu_store_pixel_stats(pixel, i, &one);
        } else {
            tt_gpu_kd_primary(&c_kd, TRAVERSAL, c_frame.eye_hint, &c_frame.basis, x, y, &p, &d, &e,
                              NULL);
        }
        prim[i] = p;
        dist[i] = d;
        end[i] = e;
    }
    if (STATS) tt_gpu_block_sum(&one, sum);
}

template <int TRAVERSAL, bool STATS>
__global__ void __launch_bounds__(TT_GPU_THREADS)
    kd_shadow_kernel(const uint32_t *prim, const float *dist, const uint32_t *end,
                     uint8_t *shadow, unsigned long long *sum)
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
                occluded = tt_gpu_kd_shadow_stats(&c_kd, TRAVERSAL, end[i], &c_frame.basis,
                                                  c_frame.light, c_frame.eps, x, y, p, dist[i],
                                                  &one);
            else
                occluded = tt_gpu_kd_shadow(&c_kd, TRAVERSAL, end[i], &c_frame.basis,
                                            c_frame.light, c_frame.eps, x, y, p, dist[i], NULL);
        }
        shadow[i] = (uint8_t)(occluded != 0);
    }
    if (STATS) tt_gpu_block_sum(&one, sum);
}

static tt_status kd_upload(const tt_gpu_structure *s, const tt_gpu_frame_const *fc,
                           const float *tri, tt_gpu_arrays *arrays, tt_gpu_err *e)
{
    const tt_kd_view *h = &s->kd;
    tt_kd_view d = *h;
    void *p;
    tt_status st;
    if ((st = tt_gpu_upload_array(arrays, h->nodes, s->kd_node_slots * sizeof(tt_kd_node), &p, e,
                                  "kd-tree nodes")) != TT_OK)
        return st;
    d.nodes = (const tt_kd_node *)p;
    if ((st = tt_gpu_upload_array(arrays, h->refs, s->kd_refs * sizeof(uint32_t), &p, e,
                                  "kd-tree triangle references")) != TT_OK)
        return st;
    d.refs = (const uint32_t *)p;
    if ((st = tt_gpu_upload_array(arrays, h->aug, (size_t)h->aug_count * sizeof(tt_kd_aug), &p, e,
                                  "kd-tree sparse boxes")) != TT_OK)
        return st;
    d.aug = (const tt_kd_aug *)p;
    d.tri = tri; /* the scene's triangles, uploaded once for both uses */
    TT_GPU_TRY(e, cudaMemcpyToSymbol(c_kd, &d, sizeof d), "kd-tree constants");
    TT_GPU_TRY(e, cudaMemcpyToSymbol(c_frame, fc, sizeof *fc), "frame constants");
    return TT_OK;
}

template <bool STATS>
static void kd_primary_launch(int traversal, const tt_gpu_io *io)
{
    const dim3 grid = tt_gpu_grid(io->width, io->height), block = tt_gpu_block();
    if (traversal == TT_KD_HTR)
        kd_primary_kernel<TT_KD_HTR, STATS><<<grid, block>>>(io->prim, io->t, io->end, io->pixel,
                                                             io->sum);
    else
        kd_primary_kernel<TT_KD_SLTR, STATS><<<grid, block>>>(io->prim, io->t, io->end, io->pixel,
                                                              io->sum);
}

static void kd_primary(const tt_gpu_structure *s, const tt_gpu_frame_const *,
                       const tt_gpu_io *io, int stats)
{
    if (stats) kd_primary_launch<true>(s->traversal, io);
    else kd_primary_launch<false>(s->traversal, io);
}

template <bool STATS>
static void kd_shadow_launch(int traversal, const tt_gpu_io *io)
{
    const dim3 grid = tt_gpu_grid(io->width, io->height), block = tt_gpu_block();
    if (traversal == TT_KD_HTR)
        kd_shadow_kernel<TT_KD_HTR, STATS><<<grid, block>>>(io->prim, io->t, io->end, io->shadow,
                                                            io->sum);
    else
        kd_shadow_kernel<TT_KD_SLTR, STATS><<<grid, block>>>(io->prim, io->t, io->end, io->shadow,
                                                             io->sum);
}

static void kd_shadow(const tt_gpu_structure *s, const tt_gpu_io *io, int stats)
{
    if (stats) kd_shadow_launch<true>(s->traversal, io);
    else kd_shadow_launch<false>(s->traversal, io);
}

const tt_gpu_module tt_gpu_kdtree_module = {kd_upload, kd_primary, kd_shadow};
