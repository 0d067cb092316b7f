/* Saving and loading the R-tree (rtree_io.c: the vtable entries), one
 * layout a file: the compact layout (layout/rtc_io.c) or the complete one
 * (layout/rtree_packed_io.c). Loaders validate every index a traversal
 * follows against the arrays' sizes before anything is traced. */
#ifndef TT_ACCEL_RTREE_RTREE_IO_H
#define TT_ACCEL_RTREE_RTREE_IO_H

#include "accel/rtree/rtree.h"
#include "io/accel_file.h"

/* The file's layout ids (tt_af_header.layout) and their record versions:
 * bump a version whenever that layout's records change meaning. */
#define RT_IO_LAYOUT_COMPLETE 1u
#define RT_IO_LAYOUT_COMPACT 2u
#define RT_IO_COMPLETE_VERSION 1u
/* 2: leaf references tagged by bit 31 (rtc_layout.h, issue #17) */
#define RT_IO_COMPACT_VERSION 2u

tt_status rtc_io_save(tt_context *ctx, const rtc_tree *t, tt_af_writer *w);
/* Points t->c at the file's arrays (node_mem, block_mem stay NULL). */
tt_status rtc_io_load(tt_context *ctx, const tt_af_file *f, uint32_t triangles, rtc_tree *t);

tt_status rt_packed_io_save(tt_context *ctx, const rt_tree *t, tt_af_writer *w);
/* Points t->p at the file's arrays (t's owned pointers stay NULL). */
tt_status rt_packed_io_load(tt_context *ctx, const tt_af_file *f, uint32_t triangles, rt_tree *t);

tt_status rtree_io_save(const tt_accel *a, tt_af_writer *w);
tt_status rtree_io_load(tt_accel *a, const tt_af_file *f);
void rtree_io_unload(tt_accel *a);

#endif
