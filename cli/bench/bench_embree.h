/* Embree 3 as its users run it, for the engine table (bench_yard.h): a scene
 * built from the same triangles (default scene flags or ROBUST, medium build
 * quality) and tight OpenMP loops of Embree's own calls over our ray arrays.
 * Not the library's wrapper (src/accel/embree), which re-checks every hit
 * and stays for the ray-by-ray agreement tests: this is the timing
 * reference. Implemented in cli/bench/embree/, compiled only when CMake
 * finds Embree (TT_HAVE_EMBREE). */
#ifndef TT_CLI_BENCH_EMBREE_H
#define TT_CLI_BENCH_EMBREE_H

#include <stddef.h>
#include <stdint.h>

#include "treetrace/treetrace.h"

typedef struct bench_embree bench_embree;

/* Builds Embree's BVH of the scene's triangles (indexed like the scene) on
 * `threads` threads (0: Embree's default): robust 0 = Embree's default scene
 * flags, 1 = RTC_SCENE_FLAG_ROBUST; medium build quality. *build_s is the
 * time of rtcCommitScene; *memory_bytes what Embree's memory monitor counts
 * live after it (the BVH and Embree's copy of the vertices and indices).
 * NULL on failure with the reason in err. */
bench_embree *bench_embree_build(const tt_scene *scene, int robust, int threads, double *build_s,
                                 size_t *memory_bytes, char *err, size_t err_size);
void bench_embree_destroy(bench_embree *e);
/* "Embree 3.13.5" */
void bench_embree_version(char *buf, size_t size);

/* The closest hits of a width x height image's row-major rays, threads
 * taking 16 x 16 tiles: packet 1 = rtcIntersect1 ray by ray; 8 or 16 =
 * rtcIntersect8 / rtcIntersect16 on 4 x 2 / 4 x 4 pixels with the coherent
 * flag. hits get prim (TT_INVALID_ID on a miss), t, u, v. */
void bench_embree_intersect(const bench_embree *e, int packet, const tt_ray *rays, uint32_t width,
                            uint32_t height, tt_hit *hits, int threads);
/* occluded[i] = 1 or 0 for rays[i]: packet 1 = rtcOccluded1; 8 or 16 =
 * rtcOccluded8/16 on consecutive rays with the coherent flag. */
void bench_embree_occluded(const bench_embree *e, int packet, const tt_ray *rays, size_t n,
                           uint8_t *occluded, int threads);

#endif
