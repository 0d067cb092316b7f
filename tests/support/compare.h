/* Ray-by-ray comparison of a structure against a reference (bruteforce).
 * Every structure but Embree shares the library's watertight triangle test,
 * so two hits agree when both miss, or they are on the same triangle with
 * bit-identical t, u and v, or on different triangles (a shared edge or a
 * tie) with t within TT_TEST_EDGE_REL relative. Embree (its own triangle
 * test) is held to the conventions' rule of ../shared/scenes/README.md: t
 * within 1e-4 relative. For shadow rays, the same occlusion. Both the fast
 * and the counting variant of the structure under test are traced and
 * checked. */
#ifndef TT_TEST_COMPARE_H
#define TT_TEST_COMPARE_H

#include "treetrace/treetrace.h"

/* Different triangles, same library kernel: the two planes through a shared
 * edge meet at the hit point, so the two t values differ only by the
 * rounding of the watertight test. Measured over the whole suite (every
 * view and random comparison, conference included; TT_TEST_EDGE_LOG=1
 * prints the largest seen): 6.8e-8 relative, one ulp, the rest exact ties.
 * The conventions' 1e-4 accepts 0.15 units at conference's distances
 * (t ~ 1500), room for a structure that skipped a nearer triangle; 1e-6 is
 * 100 times tighter and still 15 times the largest difference seen. */
#define TT_TEST_EDGE_REL 1e-6f
/* A structure with its own triangle test (Embree): the conventions' rule. */
#define TT_TEST_FOREIGN_REL 1e-4f

/* The library-kernel rule above (t, u and v bit-identical on the same
 * triangle). */
int tt_test_hits_agree(const tt_hit *a, const tt_hit *b);
/* The same for callers that have no u, v (t bit-identical on the same
 * triangle). */
int tt_test_hits_agree_t(const tt_hit *a, const tt_hit *b);
/* Embree's rule: t within TT_TEST_FOREIGN_REL relative, whichever triangle. */
int tt_test_hits_agree_foreign(const tt_hit *a, const tt_hit *b);

/* Every pixel of a w x h image of the view: primary then shadow rays, the
 * structure under test started from tt_accel_locate(eye) and its shadow
 * rays from the primary ray's end node. Returns the number of disagreeing
 * rays (printing the first few). */
size_t tt_test_compare_view(const tt_scene *scene, const tt_accel *test, const tt_accel *ref,
                            const tt_camera *camera, uint32_t width, uint32_t height);

/* The same for several structures at once, tracing the reference only once
 * a ray (bruteforce on a big scene dominates the cost otherwise). Returns
 * the total number of disagreeing rays over all structures. */
size_t tt_test_compare_view_multi(const tt_scene *scene, const tt_accel *const *tests, size_t n_tests,
                                  const tt_accel *ref, const tt_camera *camera, uint32_t width,
                                  uint32_t height);

/* n random rays with a fixed seed: origins inside and outside the scene box,
 * directions random, axis-parallel and with zero components; closest hit on
 * [0, inf) and occlusion on a random finite interval. */
size_t tt_test_compare_random(const tt_scene *scene, const tt_accel *test, const tt_accel *ref,
                              uint32_t n, uint32_t seed);

/* n rays with tiny direction components (zero, or a subnormal or small
 * float down to where the reciprocal is infinite), from origins inside the
 * scene box:
 * - a quarter have every component tiny, the largest below TT_RAY_DIR_MIN
 *   (2^-80): test and reference must both refuse them, fast and counting
 *   calls, closest hit and occlusion. (Before the contract refused them, a
 *   SIMD box test fusing the subtraction and the multiply by the reciprocal
 *   met 0 * inf = NaN on every axis, and the R-tree's and the wide BVH's
 *   AVX2 kernels followed an unused child's invalid reference; the kd-tree
 *   lost hits, its plane crossings clamped.)
 * - the others get one component just above the limit (2^-80 .. 2^-73),
 *   hits at t ~ 1e23: closest hit and occlusion against the reference. */
size_t tt_test_compare_tiny_dirs(const tt_scene *scene, const tt_accel *test, const tt_accel *ref,
                                 uint32_t n, uint32_t seed);

/* 1 when both structures refuse ray r with TT_ERR_INVALID_ARGUMENT (the ray
 * contract's too-short direction), through intersect and occluded, and the
 * test structure through its counting calls too; 0 when any call traced it. */
int tt_test_refused(const tt_accel *test, const tt_accel *ref, const tt_ray *r);

/* Rays given by the caller, closest hit and occlusion. */
size_t tt_test_compare_rays(const tt_accel *test, const tt_accel *ref, const tt_ray *rays,
                            size_t n);

#endif
