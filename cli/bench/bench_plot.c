/* Line plots for the report (Havran & Bittner's Figure 3), drawn into an
 * RGB buffer by this file and written with tt_write_png: a frame with
 * "nice" ticks and grid lines, one coloured polyline with square markers
 * per series, a legend, a title and axis labels in the 5x7 font. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"

typedef struct canvas {
    uint8_t *rgb;
    int w, h;
} canvas;

static void put(canvas *c, int x, int y, const uint8_t col[3])
{
    if (x < 0 || y < 0 || x >= c->w || y >= c->h) return;
    memcpy(c->rgb + 3 * ((size_t)y * (size_t)c->w + (size_t)x), col, 3);
}

static void rect(canvas *c, int x0, int y0, int x1, int y1, const uint8_t col[3])
{
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) put(c, x, y, col);
}

/* Bresenham, with a square pen of `pen` pixels. */
static void line(canvas *c, int x0, int y0, int x1, int y1, int pen, const uint8_t col[3])
{
    int dx = abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
    int dy = -abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
    int e = dx + dy;
    for (;;) {
        rect(c, x0 - pen / 2, y0 - pen / 2, x0 + (pen - 1) / 2, y0 + (pen - 1) / 2, col);
        if (x0 == x1 && y0 == y1) break;
        int e2 = 2 * e;
        if (e2 >= dy) e += dy, x0 += sx;
        if (e2 <= dx) e += dx, y0 += sy;
    }
}

/* Text at (x, y) = its top-left corner; scale multiplies the 5x7 cells. */
static void text(canvas *c, int x, int y, const char *s, int scale, const uint8_t col[3])
{
    for (; *s; s++, x += 6 * scale) {
        const uint8_t *g = bench_glyph(*s);
        for (int r = 0; r < 7; r++)
            for (int b = 0; b < 5; b++)
                if (g[r] & (0x10 >> b))
                    rect(c, x + b * scale, y + r * scale, x + b * scale + scale - 1,
                         y + r * scale + scale - 1, col);
    }
}

static int text_width(const char *s, int scale) { return (int)strlen(s) * 6 * scale - scale; }

/* A tick step of 1, 2 or 5 times a power of ten giving about 5 ticks. */
static double nice_step(double range)
{
    if (!(range > 0.0)) return 1.0;
    double raw = range / 5.0, p = pow(10.0, floor(log10(raw)));
    double f = raw / p;
    return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * p;
}

static void fmt(char *buf, size_t size, double v, double step)
{
    if (fabs(v) < step * 1e-6) v = 0.0;
    int decimals = step >= 1.0 ? 0 : (int)ceil(-log10(step) - 1e-9);
    snprintf(buf, size, "%.*f", decimals, v);
}

tt_status bench_plot_png(tt_context *ctx, const char *path, const char *title, const char *xlabel,
                         const char *ylabel, const bench_series *series, size_t count,
                         uint32_t width, uint32_t height)
{
    static const uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0},
                         grid[3] = {225, 225, 225}, grey[3] = {90, 90, 90};
    if (width < 200 || height < 150) return TT_ERR_INVALID_ARGUMENT;
    canvas c = {malloc((size_t)width * height * 3), (int)width, (int)height};
    if (!c.rgb) return TT_ERR_OUT_OF_MEMORY;
    memset(c.rgb, 255, (size_t)width * height * 3);

    /* data ranges: y always from 0, so curves compare by height */
    double xmin = INFINITY, xmax = -INFINITY, ymax = 0.0;
    for (size_t s = 0; s < count; s++)
        for (size_t i = 0; i < series[s].n; i++) {
            if (!isfinite(series[s].x[i]) || !isfinite(series[s].y[i])) continue;
            xmin = fmin(xmin, series[s].x[i]);
            xmax = fmax(xmax, series[s].x[i]);
            ymax = fmax(ymax, series[s].y[i]);
        }
    if (!(xmin <= xmax)) xmin = 0.0, xmax = 1.0;
    if (xmax == xmin) xmin -= 0.5, xmax += 0.5;
    if (!(ymax > 0.0)) ymax = 1.0;
    double xstep = nice_step(xmax - xmin), ystep = nice_step(ymax);
    double y_top = ceil(ymax * 1.05 / ystep) * ystep;

    const int left = 70, right = 20, top = 40, bottom = 50;
    const int pw = c.w - left - right, ph = c.h - top - bottom;
#define PX(v) (left + (int)lround(((v)-xmin) / (xmax - xmin) * (pw - 1)))
#define PY(v) (top + ph - 1 - (int)lround((v) / y_top * (ph - 1)))
    char buf[64];
    for (double v = 0.0; v <= y_top + ystep * 1e-6; v += ystep) {
        int y = PY(v);
        line(&c, left, y, left + pw - 1, y, 1, grid);
        fmt(buf, sizeof buf, v, ystep);
        text(&c, left - 6 - text_width(buf, 1), y - 3, buf, 1, black);
    }
    for (double v = ceil(xmin / xstep) * xstep; v <= xmax + xstep * 1e-6; v += xstep) {
        int x = PX(v);
        line(&c, x, top, x, top + ph - 1, 1, grid);
        fmt(buf, sizeof buf, v, xstep);
        text(&c, x - text_width(buf, 1) / 2, top + ph + 6, buf, 1, black);
    }
    line(&c, left, top, left, top + ph - 1, 1, black);
    line(&c, left, top + ph - 1, left + pw - 1, top + ph - 1, 1, black);
    line(&c, left + pw - 1, top, left + pw - 1, top + ph - 1, 1, black);
    line(&c, left, top, left + pw - 1, top, 1, black);

    for (size_t s = 0; s < count; s++) {
        const bench_series *sr = &series[s];
        int have = 0, px = 0, py = 0;
        for (size_t i = 0; i < sr->n; i++) {
            if (!isfinite(sr->x[i]) || !isfinite(sr->y[i])) {
                have = 0; /* a gap: a run that failed */
                continue;
            }
            int x = PX(sr->x[i]), y = PY(sr->y[i]);
            if (have) line(&c, px, py, x, y, 2, sr->rgb);
            rect(&c, x - 2, y - 2, x + 2, y + 2, sr->rgb);
            have = 1, px = x, py = y;
        }
    }
#undef PX
#undef PY
    /* legend, top right inside the frame */
    int lw = 0;
    for (size_t s = 0; s < count; s++) {
        int w = text_width(series[s].label, 1);
        if (w > lw) lw = w;
    }
    int lx = left + pw - lw - 40, ly = top + 8;
    rect(&c, lx - 6, ly - 6, left + pw - 8, ly + (int)count * 14, white);
    for (size_t s = 0; s < count; s++, ly += 14) {
        line(&c, lx, ly + 3, lx + 18, ly + 3, 2, series[s].rgb);
        text(&c, lx + 24, ly, series[s].label, 1, black);
    }
    text(&c, (c.w - text_width(title, 2)) / 2, 10, title, 2, black);
    text(&c, left + (pw - text_width(xlabel, 1)) / 2, top + ph + 24, xlabel, 1, grey);
    text(&c, 6, top - 14, ylabel, 1, grey);

    tt_status st = tt_write_png(ctx, path, c.rgb, width, height);
    free(c.rgb);
    return st;
}
