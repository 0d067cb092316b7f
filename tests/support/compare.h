/* Ray-by-ray comparison of a structure against a reference (bruteforce), per
 * the agreement rule of ../shared/scenes/README.md: both miss, or the same
 * triangle, or t within 1e-4 relative (a shared edge); and, for shadow rays,
 * the same occlusion. Both the fast and the counting variant of the
 * structure under test are traced and checked. */
#ifndef TT_TEST_COMPARE_H
#define TT_TEST_COMPARE_H

#include "treetrace/treetrace.h"

int tt_test_hits_agree(const tt_hit *a, const tt_hit *b);

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

/* Rays given by the caller, closest hit and occlusion. */
size_t tt_test_compare_rays(const tt_accel *test, const tt_accel *ref, const tt_ray *rays,
                            size_t n);

#endif
