/* Reading a whole input file into memory, with errors that name it. */
#ifndef TT_IO_FILE_H
#define TT_IO_FILE_H

#include <stddef.h>

#include "core/context.h"

/* *data (allocated with ctx, one extra NUL byte past *size so it is never a
 * zero-size allocation) holds the file's bytes. TT_ERR_IO naming the path and
 * the system's reason when it cannot be opened or read. */
tt_status tt_read_file(tt_context *ctx, const char *path, char **data, size_t *size);

#endif
