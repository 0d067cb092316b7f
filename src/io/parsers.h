/* The file-format parsers behind tt_scene_load(_memory). Each parses a whole
 * in-memory file; `name` (the path, or the caller's name for a buffer)
 * prefixes every error message. */
#ifndef TT_IO_PARSERS_H
#define TT_IO_PARSERS_H

#include <stddef.h>

#include "io/scene.h"

tt_status tt_obj_parse(tt_context *ctx, const char *name, const char *data, size_t size,
                       tt_scene **out);
tt_status tt_ply_parse(tt_context *ctx, const char *name, const char *data, size_t size,
                       tt_scene **out);

/* Quotes at most a few dozen bytes of a token for an error message, with
 * non-printable bytes as '?', into buf (at least 48 bytes). */
const char *tt_quote_token(char *buf, size_t buf_size, const char *s, size_t len);

#endif
