/* Writing files: raw bytes (hit buffers) and 8-bit RGB PNGs through libpng.
 * libpng's memory goes through the context's allocator, and its errors come
 * back as a status and a message naming the file, never as a print. */
#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>

#include "core/context.h"

tt_status tt_write_file(tt_context *ctx, const char *path, const void *data, size_t size)
{
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if (!path || (!data && size))
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_write_file: NULL path or data");
    FILE *fp = fopen(path, "wb");
    if (!fp) return tt_error(ctx, TT_ERR_IO, "%s: cannot open for writing: %s", path, strerror(errno));
    size_t written = size ? fwrite(data, 1, size, fp) : 0;
    int write_errno = errno;
    if (fclose(fp) != 0 && written == size) {
        write_errno = errno;
        written = 0;
    }
    if (written != size) {
        remove(path); /* leave no truncated file behind */
        return tt_error(ctx, TT_ERR_IO, "%s: write failed after %zu of %zu bytes: %s", path,
                        written, size, strerror(write_errno));
    }
    return TT_OK;
}

/* What libpng's callbacks need: the context for memory, a message buffer
 * and the jump back into tt_write_png. */
typedef struct png_state {
    tt_context *ctx;
    char message[256];
} png_state;

static png_voidp png_alloc_cb(png_structp png, png_alloc_size_t size)
{
    png_state *s = png_get_mem_ptr(png);
    return tt_alloc(s->ctx, size);
}

static void png_free_cb(png_structp png, png_voidp ptr)
{
    png_state *s = png_get_mem_ptr(png);
    tt_free(s->ctx, ptr);
}

static void png_error_cb(png_structp png, png_const_charp message)
{
    png_state *s = png_get_error_ptr(png);
    snprintf(s->message, sizeof s->message, "%s", message);
    png_longjmp(png, 1);
}

static void png_warning_cb(png_structp png, png_const_charp message)
{
    (void)png; /* the library never prints; warnings are not failures */
    (void)message;
}

tt_status tt_write_png(tt_context *ctx, const char *path, const uint8_t *rgb, uint32_t width,
                       uint32_t height)
{
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if (!path || !rgb)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_write_png: NULL path or image");
    /* PNG's limit is 2^31 - 1; libpng's default user limit is 10^6. */
    if (width == 0 || height == 0 || width > 1000000u || height > 1000000u)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "%s: cannot write a %ux%u PNG", path, width,
                        height);
    FILE *fp = fopen(path, "wb");
    if (!fp) return tt_error(ctx, TT_ERR_IO, "%s: cannot open for writing: %s", path, strerror(errno));

    png_state state;
    state.ctx = ctx;
    state.message[0] = '\0';
    png_structp png = png_create_write_struct_2(PNG_LIBPNG_VER_STRING, &state, png_error_cb,
                                                png_warning_cb, &state, png_alloc_cb, png_free_cb);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, NULL);
        fclose(fp);
        remove(path);
        return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory for the PNG writer", path);
    }
    /* Nothing that changes after setjmp is read after a longjmp, so no
     * local needs to be volatile. */
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(fp);
        remove(path);
        return tt_error(ctx, TT_ERR_IO, "%s: cannot write PNG: %s", path, state.message);
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (uint32_t y = 0; y < height; y++)
        png_write_row(png, (png_const_bytep)(rgb + (size_t)y * width * 3));
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    int write_failed = ferror(fp);
    if (fclose(fp) != 0) write_failed = 1;
    if (write_failed) {
        int e = errno;
        remove(path);
        return tt_error(ctx, TT_ERR_IO, "%s: write failed: %s", path, strerror(e));
    }
    return TT_OK;
}
