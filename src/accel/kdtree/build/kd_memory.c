/* Advice to the kernel about the builders' large buffers (kd_memory.h). */
/* MADV_HUGEPAGE is Linux's, outside POSIX. */
#define _DEFAULT_SOURCE
#include "accel/kdtree/build/kd_memory.h"

#include <stdint.h>
#include <sys/mman.h>

void kd_advise_huge(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
    const uintptr_t huge = (uintptr_t)2 << 20;
    const uintptr_t lo = ((uintptr_t)p + huge - 1) & ~(huge - 1);
    const uintptr_t hi = ((uintptr_t)p + bytes) & ~(huge - 1);
    /* The advice may be refused (no THP in this kernel): nothing to do
     * then, the memory works as before. */
    if (p && hi > lo) (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}
