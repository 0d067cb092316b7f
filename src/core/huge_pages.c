/* madvise and MADV_HUGEPAGE are outside POSIX: glibc shows them with
 * _DEFAULT_SOURCE. */
#define _DEFAULT_SOURCE 1
#include "core/huge_pages.h"

#include <stdint.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

void tt_advise_huge_pages(void *ptr, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t huge = (uintptr_t)2 << 20;
    if (!ptr || bytes < 2 * huge) return;
    const uintptr_t lo = ((uintptr_t)ptr + huge - 1) & ~(huge - 1);
    const uintptr_t hi = ((uintptr_t)ptr + bytes) & ~(huge - 1);
    if (hi > lo) (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)ptr;
    (void)bytes;
#endif
}
