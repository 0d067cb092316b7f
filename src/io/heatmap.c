/* Heatmap PNGs: per-pixel counts in false colour, with a colour bar on the
 * right (tick marks every 32 steps, labels 0, 64, 128, 192 and 255+), so a
 * picture can be read without the program that made it. */
#include "io/heatmap.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/context.h"

static float clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }

void tt_heat_colour(uint32_t count, uint8_t rgb[3])
{
    /* Jet: three overlapping tent functions; red peaks at 3/4, green at
     * 1/2, blue at 1/4, each halved at the ends (dark blue, dark red). */
    float v = (float)(count > TT_HEAT_MAX ? TT_HEAT_MAX : count) / (float)TT_HEAT_MAX;
    float r = clamp01(1.5f - fabsf(4.0f * v - 3.0f));
    float g = clamp01(1.5f - fabsf(4.0f * v - 2.0f));
    float b = clamp01(1.5f - fabsf(4.0f * v - 1.0f));
    rgb[0] = (uint8_t)(r * 255.0f + 0.5f);
    rgb[1] = (uint8_t)(g * 255.0f + 0.5f);
    rgb[2] = (uint8_t)(b * 255.0f + 0.5f);
}

/* A 3x5 pixel font for the labels: each glyph is five rows of three bits,
 * the high bit the left column. Index 10 is '+'. */
static const uint8_t glyphs[11][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7},
    {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1},
    {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}, {0, 2, 7, 2, 0},
};

/* Layout of the panel in units of the glyph scale s. */
enum { GAP = 3, BAR = 8, TICK = 3, LABEL_GAP = 2, LABEL_CHARS = 4, MARGIN = 2 };

static uint32_t glyph_scale(uint32_t height)
{
    uint32_t s = height / 200;
    return s < 1 ? 1 : s;
}

uint32_t tt_heat_panel_width(uint32_t height)
{
    return glyph_scale(height) * (GAP + BAR + TICK + LABEL_GAP + 4 * LABEL_CHARS + MARGIN);
}

typedef struct canvas {
    uint8_t *rgb;
    uint32_t width, height;
} canvas;

static void put(canvas *c, long x, long y, const uint8_t *colour)
{
    if (x < 0 || y < 0 || x >= (long)c->width || y >= (long)c->height) return;
    memcpy(c->rgb + 3 * ((size_t)y * c->width + (size_t)x), colour, 3);
}

static void fill(canvas *c, long x0, long y0, long x1, long y1, const uint8_t *colour)
{
    for (long y = y0; y < y1; y++)
        for (long x = x0; x < x1; x++) put(c, x, y, colour);
}

/* Draws text (digits and '+') with its left edge at x and centred on row yc. */
static void label(canvas *c, long x, long yc, const char *text, uint32_t s, const uint8_t *colour)
{
    long y0 = yc - (long)(5 * s) / 2;
    for (; *text; text++, x += 4 * (long)s) {
        int g = *text == '+' ? 10 : *text - '0';
        for (int row = 0; row < 5; row++)
            for (int col = 0; col < 3; col++)
                if (glyphs[g][row] & (4 >> col))
                    fill(c, x + col * (long)s, y0 + row * (long)s, x + (col + 1) * (long)s,
                         y0 + (row + 1) * (long)s, colour);
    }
}

static void draw_panel(canvas *c, uint32_t x_start, uint32_t s)
{
    static const uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0};
    fill(c, x_start, 0, c->width, c->height, white);
    /* Room above and below for half a label; tiny images get the bar alone. */
    int labels = c->height >= 48 * s;
    long top = labels ? 4 * (long)s : 0, bottom = (long)c->height - 1 - top;
    long bar_x0 = x_start + GAP * (long)s, bar_x1 = bar_x0 + BAR * (long)s;
    long span = bottom - top;
    for (long y = top; y <= bottom; y++) {
        uint8_t colour[3];
        uint32_t value = span > 0 ? (uint32_t)((bottom - y) * (long)TT_HEAT_MAX / span) : 0;
        tt_heat_colour(value, colour);
        fill(c, bar_x0, y, bar_x1, y + 1, colour);
    }
    static const uint32_t ticks[] = {0, 32, 64, 96, 128, 160, 192, 224, TT_HEAT_MAX};
    for (size_t k = 0; k < sizeof ticks / sizeof ticks[0]; k++) {
        uint32_t v = ticks[k];
        long y = bottom - (span * (long)v + (long)TT_HEAT_MAX / 2) / (long)TT_HEAT_MAX;
        int major = v % 64 == 0 || v == TT_HEAT_MAX;
        long len = (major ? TICK : (TICK + 1) / 2) * (long)s;
        fill(c, bar_x1, y, bar_x1 + len, y + (long)s, black);
        if (labels && major) {
            char text[8];
            snprintf(text, sizeof text, v == TT_HEAT_MAX ? "%u+" : "%u", v);
            label(c, bar_x1 + (TICK + LABEL_GAP) * (long)s, y, text, s, black);
        }
    }
}

tt_status tt_write_heatmap_png(tt_context *ctx, const char *path, const uint32_t *counts,
                               uint32_t width, uint32_t height)
{
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if (!path || !counts)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_write_heatmap_png: NULL path or counts");
    if (width == 0 || height == 0 || width > 1000000u || height > 1000000u)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "%s: cannot write a %ux%u heatmap", path,
                        width, height);
    uint32_t s = glyph_scale(height);
    canvas c = {NULL, width + tt_heat_panel_width(height), height};
    c.rgb = tt_alloc_array(ctx, (size_t)c.width * c.height, 3);
    if (!c.rgb)
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory for a %ux%u heatmap", path,
                        width, height);
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++)
            tt_heat_colour(counts[(size_t)y * width + x],
                           c.rgb + 3 * ((size_t)y * c.width + x));
    draw_panel(&c, width, s);
    tt_status st = tt_write_png(ctx, path, c.rgb, c.width, c.height);
    tt_free(ctx, c.rgb);
    return st;
}
