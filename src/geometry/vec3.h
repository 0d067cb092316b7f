/* Small 3-vector helpers on float[3]-like structs, shared CPU/GPU. */
#ifndef TT_GEOMETRY_VEC3_H
#define TT_GEOMETRY_VEC3_H

#include <math.h>

#include "geometry/hd.h"

typedef struct tt_vec3 {
    float x, y, z;
} tt_vec3;

TT_HD tt_vec3 tt_v3(float x, float y, float z)
{
    tt_vec3 r = {x, y, z};
    return r;
}
TT_HD tt_vec3 tt_v3_load(const float *p) { return tt_v3(p[0], p[1], p[2]); }
TT_HD tt_vec3 tt_v3_add(tt_vec3 a, tt_vec3 b) { return tt_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
TT_HD tt_vec3 tt_v3_sub(tt_vec3 a, tt_vec3 b) { return tt_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
TT_HD tt_vec3 tt_v3_scale(tt_vec3 a, float s) { return tt_v3(a.x * s, a.y * s, a.z * s); }
TT_HD float tt_v3_dot(tt_vec3 a, tt_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
TT_HD tt_vec3 tt_v3_cross(tt_vec3 a, tt_vec3 b)
{
    return tt_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
TT_HD float tt_v3_length(tt_vec3 a) { return sqrtf(tt_v3_dot(a, a)); }
TT_HD tt_vec3 tt_v3_normalize(tt_vec3 a)
{
    float l = tt_v3_length(a);
    return l > 0.0f ? tt_v3_scale(a, 1.0f / l) : a;
}
TT_HD float tt_v3_get(tt_vec3 a, int axis) { return axis == 0 ? a.x : (axis == 1 ? a.y : a.z); }

#endif
