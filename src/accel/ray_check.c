#include "accel/ray_check.h"

#include <math.h>
#include <stdio.h>

tt_status tt_ray_check(const float org[3], const float dir[3], float tmin, float tmax,
                       char *why, size_t size)
{
    const char *cause = NULL;
    for (int i = 0; i < 3; i++)
        if (!isfinite(org[i]) || !isfinite(dir[i])) cause = "ray with a non-finite origin or direction";
    if (!cause && dir[0] == 0.0f && dir[1] == 0.0f && dir[2] == 0.0f)
        cause = "ray with a zero direction";
    if (cause) {
        if (why) snprintf(why, size, "%s", cause);
        return TT_ERR_INVALID_ARGUMENT;
    }
    const float m = fmaxf(fabsf(dir[0]), fmaxf(fabsf(dir[1]), fabsf(dir[2])));
    if (m < TT_RAY_DIR_MIN) {
        if (why)
            snprintf(why, size,
                     "ray with a direction too short to trace (largest component %g, below 2^-80 = "
                     "%g): scale the direction up; t scales down with it",
                     m, TT_RAY_DIR_MIN);
        return TT_ERR_INVALID_ARGUMENT;
    }
    /* t in [tmin, tmax) with 0 <= tmin. Rays start at their origin, as in
     * Embree, whose traversal cannot look behind it; a caller wanting hits
     * behind a point moves the origin back. tmin >= tmax (also +inf) is a
     * legal empty interval. */
    if (isnan(tmin) || isnan(tmax)) {
        if (why) snprintf(why, size, "ray with a NaN interval (tmin %g, tmax %g)", tmin, tmax);
        return TT_ERR_INVALID_ARGUMENT;
    }
    if (tmin < 0.0f) {
        if (why)
            snprintf(why, size,
                     "ray with a negative tmin (%g): rays start at their origin, tmin >= 0", tmin);
        return TT_ERR_INVALID_ARGUMENT;
    }
    return TT_OK;
}
