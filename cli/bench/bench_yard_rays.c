/* The engine table's ray batches beyond the camera's: the shadow rays of the
 * primary hits (the conventions' rule, tt_shadow_ray) and ambient-occlusion
 * rays, the incoherent batch: from each hit, a few directions drawn with
 * the cosine density about the surface normal (Malley's method: a uniform
 * point on the unit disc lifted to the hemisphere). */
#include <math.h>

#include "bench/bench_yard.h"

size_t yard_shadow_rays(const tt_scene *scene, const tt_camera *cam, const tt_ray *primary,
                        const tt_hit *hits, size_t n, tt_ray *out)
{
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (hits[i].prim != TT_INVALID_ID && tt_shadow_ray(scene, cam, &primary[i], &hits[i], &out[m]))
            m++;
    return m;
}

/* A 64-bit mix (splitmix64's finaliser constants): every (seed, index)
 * gives its own independent-looking numbers, whatever the order or thread
 * the rays are made in. */
static uint64_t mix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* Two numbers in [0, 1) from one 64-bit word (24 bits each: exact floats). */
static void unit2(uint64_t bits, float *a, float *b)
{
    *a = (float)(bits >> 40) * (1.0f / 16777216.0f);
    *b = (float)((bits >> 8) & 0xffffffu) * (1.0f / 16777216.0f);
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static int normalize3(float v[3])
{
    const float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0.0f) || !isfinite(len)) return 0;
    v[0] /= len, v[1] /= len, v[2] /= len;
    return 1;
}

/* Two unit vectors completing the unit normal n to a right-handed frame
 * (the branch-free construction of Duff et al. 2017). */
static void frame(const float n[3], float t[3], float b[3])
{
    const float s = copysignf(1.0f, n[2]);
    const float a = -1.0f / (s + n[2]);
    const float c = n[0] * n[1] * a;
    t[0] = 1.0f + s * n[0] * n[0] * a, t[1] = s * c, t[2] = -s * n[0];
    b[0] = c, b[1] = s + n[1] * n[1] * a, b[2] = -n[1];
}

size_t yard_ao_rays(const tt_scene *scene, const tt_ray *primary, const tt_hit *hits, size_t n,
                    int samples, tt_ray *out)
{
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    const float d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const float diag = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const float eps = 1e-4f * diag, radius = YARD_AO_RADIUS * diag;
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (hits[i].prim == TT_INVALID_ID) continue;
        float v[9];
        if (tt_scene_triangle(scene, hits[i].prim, v) != TT_OK) continue;
        const float e1[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]};
        const float e2[3] = {v[6] - v[0], v[7] - v[1], v[8] - v[2]};
        float nrm[3];
        cross3(e1, e2, nrm);
        if (!normalize3(nrm)) continue; /* a degenerate triangle has no normal */
        const tt_ray *r = &primary[i];
        if (nrm[0] * r->dir[0] + nrm[1] * r->dir[1] + nrm[2] * r->dir[2] > 0.0f)
            nrm[0] = -nrm[0], nrm[1] = -nrm[1], nrm[2] = -nrm[2];
        const float t = hits[i].t;
        float org[3];
        for (int k = 0; k < 3; k++) org[k] = r->org[k] + t * r->dir[k] + nrm[k] * eps;
        float tx[3], bx[3];
        frame(nrm, tx, bx);
        for (int s = 0; s < samples; s++) {
            float u1, u2;
            unit2(mix64(((uint64_t)YARD_AO_SEED << 32) ^ ((uint64_t)i * (uint64_t)samples + (uint64_t)s)),
                  &u1, &u2);
            const float rad = sqrtf(u1), phi = 6.28318530718f * u2;
            const float x = rad * cosf(phi), y = rad * sinf(phi), z = sqrtf(fmaxf(0.0f, 1.0f - u1));
            tt_ray *o = &out[m++];
            for (int k = 0; k < 3; k++) {
                o->org[k] = org[k];
                o->dir[k] = x * tx[k] + y * bx[k] + z * nrm[k];
            }
            o->tmin = 0.0f;
            o->tmax = radius;
        }
    }
    return m;
}
