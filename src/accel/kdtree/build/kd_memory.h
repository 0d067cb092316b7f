/* Advice to the kernel about the builders' large buffers. */
#ifndef TT_ACCEL_KDTREE_KD_MEMORY_H
#define TT_ACCEL_KDTREE_KD_MEMORY_H

#include <stddef.h>

/* Asks for transparent huge pages on the 2 MiB-aligned part of [p, p +
 * bytes): a build writes its big lists and leaf blocks once into fresh
 * memory, and taking that memory 4 KiB page fault by page fault was a
 * seventh of a build's time (more in a virtual machine, where every fault
 * exits to the hypervisor). Only advice: a kernel without THP, or a
 * region too small to hold an aligned huge page, is left as it is; the
 * contents and the allocator's ownership do not change. */
void kd_advise_huge(void *p, size_t bytes);

#endif
