/* The ray contract of treetrace.h (tt_ray), checked in one place for the
 * single-ray calls and the batches, so both reject the same rays with the
 * same words. */
#ifndef TT_ACCEL_RAY_CHECK_H
#define TT_ACCEL_RAY_CHECK_H

#include <stddef.h>

#include "treetrace/treetrace.h"

/* The shortest direction the contract accepts: its largest component must be
 * at least 2^-80 (about 8.3e-25) in magnitude. Below it the arithmetic leaves
 * float range: the kd-tree's plane crossings use 1/d, which tt_safe_inv
 * clamps below 1e-30, and the watertight test's T = U * Az * (1 / d_kz)
 * overflows for scenes of a few hundred units near 1e-31, so no structure,
 * bruteforce included, could give the exact answer. The rays are refused
 * with a message instead of traced to silent misses; scaling a direction by
 * any factor only scales t. */
#define TT_RAY_DIR_MIN 0x1p-80f

/* TT_OK for a ray the contract accepts; otherwise TT_ERR_INVALID_ARGUMENT
 * and, when why is not NULL, the cause in why (at most size bytes). Writes
 * nothing shared: safe to call from many threads. */
tt_status tt_ray_check(const float org[3], const float dir[3], float tmin, float tmax,
                       char *why, size_t size);

#endif
