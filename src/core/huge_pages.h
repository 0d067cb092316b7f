/* Transparent huge pages for big arrays walked at random (the in-place
 * R-tree update's node pool and slack layout): with 4 KiB pages nearly
 * every node or region an edit visits is a TLB miss. */
#ifndef TT_CORE_HUGE_PAGES_H
#define TT_CORE_HUGE_PAGES_H

#include <stddef.h>

/* Asks the kernel to back the whole 2 MiB pages inside [ptr, ptr + bytes)
 * with huge pages (Linux madvise MADV_HUGEPAGE, for systems whose
 * transparent huge pages are set to `madvise`). Only advice: elsewhere,
 * below 4 MiB, or when refused it does nothing; contents never change. */
void tt_advise_huge_pages(void *ptr, size_t bytes);

#endif
