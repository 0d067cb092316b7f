/* PNG output: tt_write_png round trips, tt_write_file round trips, the
 * heatmap's colour scale (dark blue .. dark red, saturating at 255) and its
 * colour bar with tick marks, and errors that name the file. Files are read
 * back with libpng's own reader. */
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "io/heatmap.h"

static char dir[64];

static const char *tmp(const char *name)
{
    static char path[4][256];
    static int slot;
    char *p = path[slot++ & 3];
    snprintf(p, sizeof path[0], "%s/%s", dir, name);
    return p;
}

/* Reads an RGB PNG; NULL if it is not one. */
static uint8_t *read_png(const char *path, uint32_t *w, uint32_t *h)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path)) return NULL;
    img.format = PNG_FORMAT_RGB;
    uint8_t *buf = malloc(PNG_IMAGE_SIZE(img));
    if (!png_image_finish_read(&img, NULL, buf, 0, NULL)) {
        free(buf);
        return NULL;
    }
    *w = img.width;
    *h = img.height;
    return buf;
}

static void test_png_round_trip(tt_context *ctx)
{
    const uint32_t w = 17, h = 9;
    uint8_t rgb[17 * 9 * 3];
    uint32_t x = 12345;
    for (size_t i = 0; i < sizeof rgb; i++) {
        x = x * 1103515245u + 12345u;
        rgb[i] = (uint8_t)(x >> 24);
    }
    CHECK_OK(ctx, tt_write_png(ctx, tmp("a.png"), rgb, w, h));
    uint32_t rw = 0, rh = 0;
    uint8_t *back = read_png(tmp("a.png"), &rw, &rh);
    CHECK(back && rw == w && rh == h);
    CHECK(back && memcmp(back, rgb, sizeof rgb) == 0);
    free(back);

    /* errors name the file */
    const char *bad = "/nonexistent-dir-of-treetrace/x.png";
    CHECK(tt_write_png(ctx, bad, rgb, w, h) == TT_ERR_IO);
    CHECK(strstr(tt_context_last_error(ctx), bad) != NULL);
    CHECK(tt_write_png(ctx, dir, rgb, w, h) == TT_ERR_IO); /* a folder */
    CHECK(strstr(tt_context_last_error(ctx), dir) != NULL);
    CHECK(tt_write_png(ctx, tmp("b.png"), rgb, 0, h) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_write_png(ctx, tmp("b.png"), NULL, w, h) == TT_ERR_INVALID_ARGUMENT);
    CHECK(access(tmp("b.png"), F_OK) != 0);
}

static void test_file_round_trip(tt_context *ctx)
{
    const char data[] = "0123456789abcdef";
    CHECK_OK(ctx, tt_write_file(ctx, tmp("f.bin"), data, 16));
    FILE *fp = fopen(tmp("f.bin"), "rb");
    char back[32] = {0};
    size_t n = fp ? fread(back, 1, sizeof back, fp) : 0;
    if (fp) fclose(fp);
    CHECK(n == 16 && memcmp(back, data, 16) == 0);
    /* an empty write still makes the file (it replaces an older one) */
    fp = fopen(tmp("empty.bin"), "wb");
    if (fp) fputs("old content", fp), fclose(fp);
    CHECK_OK(ctx, tt_write_file(ctx, tmp("empty.bin"), NULL, 0));
    fp = fopen(tmp("empty.bin"), "rb");
    CHECK_MSG(fp != NULL, "tt_write_file(n = 0) did not create %s", tmp("empty.bin"));
    if (fp) {
        CHECK_MSG(fgetc(fp) == EOF, "tt_write_file(n = 0) left content in %s", tmp("empty.bin"));
        fclose(fp);
    }
    const char *bad = "/nonexistent-dir-of-treetrace/x.hits";
    CHECK(tt_write_file(ctx, bad, data, 16) == TT_ERR_IO);
    CHECK(strstr(tt_context_last_error(ctx), bad) != NULL);
}

static int same(const uint8_t *a, const uint8_t *b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

static void test_colour_scale(void)
{
    uint8_t c[3], prev[3];
    /* Pinned from the scale's definition (jet over count/255, channels
     * 1.5 - |4v - k| clamped, rounded): 0 is (0, 0, 0.5) -> (0, 0, 128),
     * 255 is (0.5, 0, 0) -> (128, 0, 0). At 128, v = 128/255: green 1, and
     * red and blue land on 129.5 and 125.5 exactly, where the float
     * evaluation (v, 4v - 3, 4v - 1 each rounded) decides: 130 and 125. */
    static const struct {
        uint32_t count;
        uint8_t rgb[3];
    } pinned[] = {{0, {0, 0, 128}}, {128, {130, 255, 125}}, {255, {128, 0, 0}}};
    for (size_t i = 0; i < sizeof pinned / sizeof pinned[0]; i++) {
        tt_heat_colour(pinned[i].count, c);
        CHECK_MSG(same(c, pinned[i].rgb), "count %u: (%u, %u, %u), pinned (%u, %u, %u)",
                  pinned[i].count, c[0], c[1], c[2], pinned[i].rgb[0], pinned[i].rgb[1],
                  pinned[i].rgb[2]);
    }
    tt_heat_colour(0, c);
    CHECK(c[0] == 0 && c[1] == 0 && c[2] >= 100 && c[2] <= 160); /* dark blue */
    tt_heat_colour(255, c);
    CHECK(c[0] >= 100 && c[0] <= 160 && c[1] == 0 && c[2] == 0); /* dark red */
    tt_heat_colour(128, c);
    CHECK(c[1] == 255 && c[0] > 100 && c[2] > 100); /* green in the middle */
    uint8_t top[3];
    tt_heat_colour(255, top);
    tt_heat_colour(256, c);
    CHECK(same(c, top));
    tt_heat_colour(UINT32_MAX, c);
    CHECK(same(c, top));
    /* jet: blue falls over the upper range, red rises over the lower, and
     * neighbouring counts get different colours (the scale resolves 1 step
     * somewhere in every stretch of 4) */
    tt_heat_colour(0, prev);
    int distinct = 0;
    for (uint32_t v = 1; v <= 255; v++) {
        tt_heat_colour(v, c);
        if (v >= 96) CHECK(c[2] <= prev[2]);
        if (v <= 160) CHECK(c[0] >= prev[0]);
        distinct += !same(c, prev);
        memcpy(prev, c, 3);
    }
    CHECK(distinct > 200);
}

/* A heatmap of known counts: the image part is the colour scale applied
 * pixel by pixel, the panel has the bar (top 255, bottom 0) and ticks. */
static void check_heatmap(tt_context *ctx, uint32_t w, uint32_t h)
{
    uint32_t *counts = malloc((size_t)w * h * sizeof *counts);
    for (uint32_t i = 0; i < w * h; i++) counts[i] = (i * 7u) % 300u;
    CHECK_OK(ctx, tt_write_heatmap_png(ctx, tmp("heat.png"), counts, w, h));
    uint32_t rw = 0, rh = 0;
    uint8_t *img = read_png(tmp("heat.png"), &rw, &rh);
    CHECK(img != NULL);
    if (!img) {
        free(counts);
        return;
    }
    uint32_t panel = tt_heat_panel_width(h);
    CHECK(panel >= 20);
    CHECK(rw == w + panel && rh == h);
    int bad = 0;
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            uint8_t c[3];
            tt_heat_colour(counts[y * w + x], c);
            bad += !same(c, img + 3 * ((size_t)y * rw + x));
        }
    }
    CHECK_MSG(bad == 0, "%d heatmap pixels differ from the colour scale", bad);
    /* find the bar: the first panel column that holds the top colour */
    uint8_t top[3], bottom[3];
    tt_heat_colour(255, top);
    tt_heat_colour(0, bottom);
    long bar_x = -1;
    for (uint32_t x = w; x < rw && bar_x < 0; x++)
        for (uint32_t y = 0; y < h / 4; y++)
            if (same(img + 3 * ((size_t)y * rw + x), top)) bar_x = x;
    CHECK(bar_x > (long)w);
    if (bar_x > 0) {
        /* down the bar the colour goes from the top of the scale to 0 */
        int top_seen = 0, bottom_seen = 0;
        for (uint32_t y = 0; y < h; y++) {
            const uint8_t *p = img + 3 * ((size_t)y * rw + (uint32_t)bar_x);
            top_seen |= y < h / 4 && same(p, top);
            bottom_seen |= y > 3 * h / 4 && same(p, bottom);
        }
        CHECK(top_seen && bottom_seen);
        /* tick marks: black pixels right of the bar, at several heights */
        static const uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0};
        const uint8_t *row = img + 3 * ((size_t)(h / 2) * rw);
        long right = bar_x; /* the bar's last column, along the middle row */
        while (right + 1 < (long)rw && !same(row + 3 * (right + 1), white) &&
               !same(row + 3 * (right + 1), black))
            right++;
        int tick_rows = 0;
        for (uint32_t y = 0; y < h; y++) {
            const uint8_t *p = img + 3 * ((size_t)y * rw + (size_t)right + 1);
            tick_rows += p[0] == 0 && p[1] == 0 && p[2] == 0;
        }
        CHECK_MSG(tick_rows >= 5, "only %d rows with a tick mark", tick_rows);
    }
    free(img);
    free(counts);
}

static void test_heatmap_errors(tt_context *ctx)
{
    uint32_t counts[4] = {0};
    const char *bad = "/nonexistent-dir-of-treetrace/heat.png";
    CHECK(tt_write_heatmap_png(ctx, bad, counts, 2, 2) == TT_ERR_IO);
    CHECK(strstr(tt_context_last_error(ctx), bad) != NULL);
    CHECK(tt_write_heatmap_png(ctx, tmp("h.png"), NULL, 2, 2) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_write_heatmap_png(ctx, tmp("h.png"), counts, 0, 2) == TT_ERR_INVALID_ARGUMENT);
    /* one pixel still makes a valid file */
    CHECK_OK(ctx, tt_write_heatmap_png(ctx, tmp("one.png"), counts, 1, 1));
    uint32_t w, h;
    uint8_t *img = read_png(tmp("one.png"), &w, &h);
    CHECK(img && h == 1 && w == 1 + tt_heat_panel_width(1));
    free(img);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/tt_heatmap_XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    tt_context *ctx = tt_test_context();
    test_png_round_trip(ctx);
    test_file_round_trip(ctx);
    test_colour_scale();
    check_heatmap(ctx, 40, 30);   /* no room for labels: bar and ticks only */
    check_heatmap(ctx, 64, 256);  /* labels */
    check_heatmap(ctx, 50, 700);  /* glyphs scaled by 3 */
    test_heatmap_errors(ctx);
    tt_context_destroy(ctx);
    const char *files[] = {"a.png", "f.bin", "empty.bin", "heat.png", "one.png"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) remove(tmp(files[i]));
    rmdir(dir);
    return tt_test_finish();
}
