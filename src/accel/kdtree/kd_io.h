/* Saving and loading the kd-tree (kd_io.c): its vtable entries. */
#ifndef TT_ACCEL_KDTREE_KD_IO_H
#define TT_ACCEL_KDTREE_KD_IO_H

#include "accel/kdtree/kd_tree.h"
#include "io/accel_file.h"

tt_status kd_io_save(const tt_accel *a, tt_af_writer *w);
tt_status kd_io_load(tt_accel *a, const tt_af_file *f);
void kd_io_unload(tt_accel *a);

#endif
