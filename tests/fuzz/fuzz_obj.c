/* libFuzzer target: the OBJ loader on arbitrary bytes (see fuzz_common.h for
 * what is checked). */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_load("obj", data, size);
    return 0;
}
