/* tt_render's GPU path (render_gpu.c): what the GPU supports, and the
 * passes of a frame traced there. Compiled in every build; without CUDA it
 * reports that the build has none. */
#ifndef TT_RENDER_RENDER_GPU_H
#define TT_RENDER_RENDER_GPU_H

#include "render/frame.h"

/* TT_OK when the GPU traces this structure with its options (rtree: auto,
 * stackless, ordered; kdtree: sltr, htr, no shadow-caster hint), else
 * TT_ERR_UNSUPPORTED naming what the GPU supports. */
tt_status tt_render_gpu_validate(tt_context *ctx, const tt_accel *accel);

/* The frame's passes on the GPU: fills f->prim, f->t, f->shadow (and
 * f->pixel_stats), primary_s[k] and shadow_s[k] for each of the o->repeat
 * timed passes, in *s the statistics, the copy times and the device, and
 * when image is not NULL the image shaded on the GPU (w h RGB bytes). */
tt_status tt_render_gpu_passes(tt_context *ctx, tt_frame *f, const tt_render_options *o,
                               double *primary_s, double *shadow_s, uint8_t *image,
                               tt_render_summary *s);

#endif
