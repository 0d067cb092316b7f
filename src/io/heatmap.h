/* The false-colour scale of the heatmaps (after Havran & Bittner 2007,
 * Figure 5): 0 is dark blue, 255 or more dark red, jet-like in between. */
#ifndef TT_IO_HEATMAP_H
#define TT_IO_HEATMAP_H

#include <stdint.h>

/* Counts at or above this get the top colour. */
#define TT_HEAT_MAX 255u

void tt_heat_colour(uint32_t count, uint8_t rgb[3]);

/* Width in pixels of the colour-bar panel added right of a heatmap of the
 * given height (it grows with the height so the labels stay legible). */
uint32_t tt_heat_panel_width(uint32_t height);

#endif
