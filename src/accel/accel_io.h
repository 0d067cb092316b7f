/* Section ids of saved structures (io/accel_file.h): the ones every
 * structure shares, and each structure's own range, so that ids never clash
 * and a file's table reads the same whatever wrote it (docs/accel-file.md). */
#ifndef TT_ACCEL_ACCEL_IO_H
#define TT_ACCEL_ACCEL_IO_H

enum {
    TT_AF_SEC_OPTIONS = 1, /* the build options, TT_AF_OPTION_WORDS words */
    TT_AF_SEC_PARAMS = 2,  /* the structure's scalars (doubles)         */
    /* the R-tree's compact layout (rtree/layout/rtc_io.c) */
    TT_AF_SEC_RTC_HEADER = 10,
    TT_AF_SEC_RTC_NODES = 11,
    TT_AF_SEC_RTC_BLOCKS = 12,
    /* the R-tree's complete layout (rtree/layout/rtree_packed_io.c) */
    TT_AF_SEC_RTP_HEADER = 20,
    TT_AF_SEC_RTP_BOX = 21,
    TT_AF_SEC_RTP_COUNT = 22,
    TT_AF_SEC_RTP_LEAF_START = 23,
    TT_AF_SEC_RTP_TRI = 24,
    TT_AF_SEC_RTP_PRIM = 25,
    /* the kd-tree (kdtree/kd_io.c) */
    TT_AF_SEC_KD_NODES = 30,
    TT_AF_SEC_KD_REFS = 31,
    TT_AF_SEC_KD_AUG = 32
};

#endif
