/* libFuzzer target: the views.tsv parser on arbitrary bytes. The view looked
 * up is the one named by the input's second line (its first two fields), so
 * that accepted views are reached, and then a name that is absent (see
 * fuzz_common.h for what is checked). */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_views(data, size);
    return 0;
}
