/* The keys of the overlap criterion (rtree_choose_overlap.c) for every
 * entry of a node, computed by one kernel per ISA: the baseline SSE2 one in
 * rtree_choose_overlap.c, wider ones in rtree_choose_overlap_avx2.c and
 * _avx512.c. Every kernel adds the overlap terms of an entry in the same
 * order (siblings ascending) with the same operations, so all give the same
 * keys to the bit and the builder the same tree. */
#ifndef TT_ACCEL_RTREE_CHOOSE_OVERLAP_H
#define TT_ACCEL_RTREE_CHOOSE_OVERLAP_H

#include "accel/rtree/build/rtree_build.h"

/* Room for whole 16-lane stores past the last entry. */
#define RT_OVERLAP_LANES (TT_RT_CAP + 15)

typedef struct rt_overlap_keys {
    float dov[RT_OVERLAP_LANES];   /* overlap enlargement                 */
    float dvol[RT_OVERLAP_LANES];  /* volume enlargement                  */
    float vol[RT_OVERLAP_LANES];   /* volume                              */
    float darea[RT_OVERLAP_LANES]; /* surface enlargement (factor 2 kept) */
    float area[RT_OVERLAP_LANES];  /* surface area (factor 2 kept)        */
} rt_overlap_keys;

/* Keys of entries 0 .. cnt - 1 of the SoA bounds s (six rows of cap floats)
 * for box e. Reads no bound past entry cnt - 1 of the last row. */
typedef void (*rt_overlap_keys_fn)(const float *s, int cap, int cnt, const float e[6],
                                   struct rt_overlap_keys *k);

void rt_overlap_keys_sse2(const float *s, int cap, int cnt, const float e[6], rt_overlap_keys *k);
#if defined(TT_HAVE_X86_KERNELS)
void rt_overlap_keys_avx2(const float *s, int cap, int cnt, const float e[6], rt_overlap_keys *k);
void rt_overlap_keys_avx512(const float *s, int cap, int cnt, const float e[6],
                            rt_overlap_keys *k);
#endif

/* The best kernel this CPU runs. */
rt_overlap_keys_fn rt_overlap_keys_best(void);

#endif
