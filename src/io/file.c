#include "io/file.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

tt_status tt_read_file(tt_context *ctx, const char *path, char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return tt_error(ctx, TT_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    /* The size from fstat is only a first guess (the file may be a pipe or
     * change while read); reading goes on until EOF, growing as needed. */
    struct stat sb;
    size_t cap = 1 << 16;
    if (fstat(fileno(f), &sb) == 0 && S_ISDIR(sb.st_mode)) {
        fclose(f);
        return tt_error(ctx, TT_ERR_IO, "%s: cannot read: is a directory", path);
    }
    if (fstat(fileno(f), &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > 0 &&
        (unsigned long long)sb.st_size < (unsigned long long)SIZE_MAX - 1)
        cap = (size_t)sb.st_size + 1;
    char *buf = tt_alloc(ctx, cap);
    size_t n = 0;
    tt_status st = TT_OK;
    if (!buf) {
        st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory for %zu bytes", path, cap);
        goto done;
    }
    for (;;) {
        if (n == cap) {
            size_t new_cap = cap > SIZE_MAX / 2 ? SIZE_MAX : cap * 2;
            char *p = new_cap > cap ? tt_realloc(ctx, buf, new_cap) : NULL;
            if (!p) {
                st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory after %zu bytes", path, n);
                goto done;
            }
            buf = p;
            cap = new_cap;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0) {
            if (ferror(f)) {
                st = tt_error(ctx, TT_ERR_IO, "%s: read error after %zu bytes: %s", path, n,
                              strerror(errno));
                goto done;
            }
            break; /* EOF */
        }
    }
    if (n == cap) { /* room for the terminating NUL */
        char *p = cap < SIZE_MAX ? tt_realloc(ctx, buf, cap + 1) : NULL;
        if (!p) {
            st = tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "%s: out of memory after %zu bytes", path, n);
            goto done;
        }
        buf = p;
    }
    buf[n] = '\0';
done:
    fclose(f);
    if (st != TT_OK) {
        tt_free(ctx, buf);
        return st;
    }
    *data = buf;
    *size = n;
    return TT_OK;
}
