/* The ray contract of treetrace.h (tt_ray), checked in one place for the
 * single-ray calls and the batches, so both reject the same rays with the
 * same words. */
#ifndef TT_ACCEL_RAY_CHECK_H
#define TT_ACCEL_RAY_CHECK_H

#include <stddef.h>

#include "treetrace/treetrace.h"

/* TT_OK for a ray the contract accepts; otherwise TT_ERR_INVALID_ARGUMENT
 * and, when why is not NULL, the cause in why (at most size bytes). Writes
 * nothing shared: safe to call from many threads. */
tt_status tt_ray_check(const float org[3], const float dir[3], float tmin, float tmax,
                       char *why, size_t size);

#endif
