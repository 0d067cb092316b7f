/* libFuzzer target: the PLY loader (ascii, binary little- and big-endian) on
 * arbitrary bytes (see fuzz_common.h for what is checked). The format is
 * detected from the content, so inputs without the "ply" line also reach the
 * detection and, from there, the OBJ parser. */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_load(fuzz_ply_format(data, size), data, size);
    return 0;
}
