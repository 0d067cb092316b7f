/* Table D (dynamic scenes): the Embree side (bench_dynamic_embree.c) behind
 * an interface of its own, so the frame loop (bench_dynamic.c) needs no
 * Embree header; every call is a no-op (create gives NULL) without Embree. */
#ifndef TT_CLI_BENCH_DYNAMIC_H
#define TT_CLI_BENCH_DYNAMIC_H

#include <stddef.h>

#include "treetrace/treetrace.h"

double bench_now(void); /* bench_progress.c */

typedef struct bench_emb bench_emb;
/* quality: 0 REFIT, 1 LOW, 2 MEDIUM; rays traced on `threads` threads. */
bench_emb *bench_emb_create(int quality, int threads);
/* The one mesh's triangles (9 floats each): new, or new positions. */
int bench_emb_set(bench_emb *e, const float *tri, size_t n);
/* Growth: one more mesh in the scene. */
int bench_emb_add_object(bench_emb *e, const float *tri, size_t n);
/* rtcCommitScene's seconds. */
double bench_emb_commit(bench_emb *e);
void bench_emb_trace(bench_emb *e, const tt_ray *rays, size_t n, const tt_ray *shadow, size_t m,
                     double *primary_s, double *shadow_s);
/* Bytes Embree's device holds (its memory monitor). */
long long bench_emb_memory(const bench_emb *e);
void bench_emb_destroy(bench_emb *e);

#endif
