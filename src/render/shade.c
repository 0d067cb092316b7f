/* The shaded image of a CPU frame (render/shade_hd.h). Not timed. */
#include "render/frame.h"
#include "render/shade_hd.h"

void tt_frame_shade(const tt_frame *f, int shadows, uint8_t *rgb)
{
    const long h = (long)f->height;
#pragma omp parallel for schedule(dynamic) num_threads(f->threads)
    for (long y = 0; y < h; y++)
        for (uint32_t x = 0; x < f->width; x++) {
            const size_t i = (size_t)y * f->width + x;
            tt_shade_pixel(&f->basis, f->scene->tri, f->camera->light, f->camera->has_light,
                           shadows, x, (uint32_t)y, f->prim[i], f->t[i], f->shadow[i],
                           rgb + 3 * i);
        }
}
