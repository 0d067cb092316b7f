/* The boundary between the C library and the CUDA tracer (the .cu files here):
 * plain data only, so that the C side (render/render_gpu.c) knows no CUDA
 * and the CUDA side knows no library internals beyond the packed trees.
 * The CUDA side never allocates host memory and never calls back into the
 * library: errors come back as a status and a message in a caller's buffer. */
#ifndef TT_CUDA_GPU_H
#define TT_CUDA_GPU_H

#include <stddef.h>
#include <stdint.h>

#include "accel/kdtree/kd_layout.h"
#include "accel/rtree/layout/rtc_layout.h"
#include "accel/rtree/layout/rtree_packed.h"
#include "render/camera_hd.h"
#include "treetrace/treetrace.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TT_GPU_MESSAGE 512

typedef enum tt_gpu_kind { TT_GPU_RTREE = 1, TT_GPU_KDTREE } tt_gpu_kind;

/* A structure to upload, its arrays given by host pointers and sizes. */
typedef struct tt_gpu_structure {
    tt_gpu_kind kind;
    /* rtree: TT_RTREE_AUTO, _STACKLESS or _ORDERED; kdtree: TT_KD_SLTR or _HTR */
    int traversal;
    /* rtree: the packed tree; its array lengths follow from its fields
     * (box_floats = 6 M groups, count: delta[0], leaf_start: leaf_slots + 1,
     * tri: 9 triangles, prim: triangles) */
    tt_rtree_packed rtree;
    size_t rtree_box_floats;
    float rtree_root_box[6]; /* the auto traversal's inside test (rt_locate) */
    /* rtree in the compact layout (rtree_compact = 1): the tree (host
     * pointers; nodes * words floats of records, blocks triangle blocks),
     * traced by its stackless traversal; the fields above are unused */
    int rtree_compact;
    tt_rtc rtc;
    /* kdtree: the view (host pointers; its tri is the scene's), nodes[]
     * entries (extension slots included) and refs[] entries */
    tt_kd_view kd;
    size_t kd_node_slots, kd_refs;
    /* the scene's triangles in load order (shadow-ray normals) */
    const float *tri;
    uint32_t triangles;
} tt_gpu_structure;

/* One frame: inputs, the caller's host buffers for the results (w * h each;
 * pixel_stats NULL or all five set), and what was measured. */
typedef struct tt_gpu_frame {
    tt_camera_basis basis;
    float light[3];
    int has_light; /* shadow rays are traced when shadows && has_light     */
    int shadows;
    float eps;            /* shadow-ray offset                              */
    uint32_t eye_hint;    /* the structure's hint for rays from the eye     */
    int repeat;           /* timed passes                                   */
    int stats;            /* one counting pass first (also for pixel_stats) */
    uint32_t *prim;
    float *t;
    uint8_t *shadow;
    uint32_t *pixel_stats[5]; /* tt_heat_metric order                        */
    uint8_t *image;           /* NULL, or 3 w h bytes: shaded on the GPU      */
    /* out */
    double *primary_s, *shadow_s; /* `repeat` entries each, caller's arrays */
    double upload_s, download_s;
    tt_ray_stats primary_stats, shadow_stats;
    char device_name[64];
} tt_gpu_frame;

/* Whether a usable CUDA device is present: TT_OK and its name, or
 * TT_ERR_NO_DEVICE with "no usable CUDA device: <why>" in msg, where <why>
 * is either "no device here (...)" (CUDA finds none and there is no
 * /dev/nvidia0 or NVIDIA kernel driver) or "a device is present but
 * failing (...)" (driver mismatch, failed initialisation, no kernel for
 * the card: a broken setup, which GPU tests must not skip). */
tt_status tt_gpu_probe(char *name, size_t name_size, char *msg, size_t msg_size);

/* Uploads the structure, traces the frame (counting pass first when asked,
 * then `repeat` timed passes), copies the results back and frees the
 * device memory. Statuses: TT_ERR_NO_DEVICE, TT_ERR_OUT_OF_MEMORY (device
 * memory), TT_ERR_INTERNAL (any other CUDA error), each with a message. */
tt_status tt_gpu_render(const tt_gpu_structure *s, tt_gpu_frame *f, char *msg, size_t msg_size);

#ifdef __cplusplus
}
#endif
#endif
