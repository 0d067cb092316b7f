/* The R-tree's insertion build (rtree/build/) driven directly, for the
 * insertion tools: tools/rtree_fingerprint.c (the same trees before and after
 * a change) and tools/rtree_boost_bench.cpp (speed against Boost.Geometry).
 * Plain C with a C++-safe interface. */
#ifndef TT_TOOLS_RTREE_INSERT_RUN_H
#define TT_TOOLS_RTREE_INSERT_RUN_H

#include <stdint.h>

#include "treetrace/treetrace.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rir_result {
    double cpu_s;    /* thread CPU time of the insertions alone            */
    uint64_t hash;   /* FNV-1a over the tree in depth-first order          */
    uint32_t nodes;  /* nodes in the tree                                  */
    int height;      /* levels (1: the root is a leaf)                      */
} rir_result;

/* The triangles' boxes (6 floats each: lo xyz, hi xyz) of a scene, computed
 * as the R-tree's build computes them; free() the result. NULL on error. */
float *rir_boxes(const tt_scene *scene, uint32_t *count);

/* Loads the scene at path (*scene; tt_scene_destroy it) and returns its
 * boxes as rir_boxes does, *name the path's file name. On error says why on
 * stderr, naming the file, and returns NULL. */
float *rir_load(tt_context *ctx, const char *path, tt_scene **scene, const char **name,
                uint32_t *count);

/* Builds the pointer tree by inserting the boxes in id order with options o
 * (M = 0 is resolved as the library does), times it and fingerprints it.
 * Returns 0 on success. */
int rir_build(tt_context *ctx, const float *box, uint32_t count, const tt_rtree_options *o,
              rir_result *out);

/* The public build's "sah_cost" statistic for options o (compact layout),
 * or -1 on error. */
double rir_sah(tt_context *ctx, const tt_scene *scene, const tt_rtree_options *o);

/* Thread CPU time in seconds. */
double rir_thread_cpu(void);

const char *rir_strategy_name(tt_rtree_strategy s);

#ifdef __cplusplus
}
#endif

#endif
