/* tt_scene_load(_memory): one code path, the whole file in memory, the
 * format chosen by content ("ply" on the first line) unless the caller names
 * it. */
#include <string.h>

#include "io/file.h"
#include "io/parsers.h"

static int looks_like_ply(const char *data, size_t size)
{
    return (size >= 4 && memcmp(data, "ply\n", 4) == 0) ||
           (size >= 5 && memcmp(data, "ply\r\n", 5) == 0);
}

tt_status tt_scene_load_memory(tt_context *ctx, const char *name, const char *format,
                               const void *data, size_t size, tt_scene **out)
{
    if (!out) return TT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if (!name) name = "<memory>";
    if (!data && size)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "%s: NULL data with a nonzero size", name);
    const char *bytes = data ? (const char *)data : "";
    int ply;
    if (!format) ply = looks_like_ply(bytes, size);
    else if (strcmp(format, "ply") == 0) ply = 1;
    else if (strcmp(format, "obj") == 0) ply = 0;
    else
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: unknown format \"%s\" (expected \"obj\", \"ply\" or NULL)", name, format);
    if (size == 0) return tt_error(ctx, TT_ERR_PARSE, "%s: the file is empty", name);
    return ply ? tt_ply_parse(ctx, name, bytes, size, out) : tt_obj_parse(ctx, name, bytes, size, out);
}

tt_status tt_scene_load(tt_context *ctx, const char *path, tt_scene **out)
{
    if (!out) return TT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!ctx) return TT_ERR_INVALID_ARGUMENT;
    if (!path) return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_scene_load: NULL path");
    char *data;
    size_t size;
    tt_status st = tt_read_file(ctx, path, &data, &size);
    if (st) return st;
    st = tt_scene_load_memory(ctx, path, NULL, data, size, out);
    tt_free(ctx, data);
    return st;
}
