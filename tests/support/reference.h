/* A reference (bruteforce) traced once and kept, for comparing many
 * structure variants on the same view without paying the reference again:
 * the same per-pixel checks as tt_test_compare_view (closest hit of the
 * primary ray, fast and counting variants, and the occlusion of the shadow
 * ray built from the reference's primary hit), per the agreement rule. */
#ifndef TT_TEST_REFERENCE_H
#define TT_TEST_REFERENCE_H

#include "treetrace/treetrace.h"

typedef struct tt_test_reference tt_test_reference;

/* Traces every pixel of a w x h image of the view with `ref`. Exits the
 * test (a failure) when out of memory or a call fails. */
tt_test_reference *tt_test_reference_view(const tt_scene *scene, const tt_accel *ref,
                                          const tt_camera *camera, uint32_t width,
                                          uint32_t height);
void tt_test_reference_destroy(tt_test_reference *reference);

/* The structure under test against the kept reference, started from
 * tt_accel_locate(eye) for primary rays and from the primary ray's end hint
 * for shadow rays. Returns the number of disagreeing rays (printing the
 * first few). */
size_t tt_test_compare_view_reference(const tt_accel *test, const tt_test_reference *reference);

#endif
