/* tt_ray_box, the shared slab test: ordinary hits and misses, and the exact
 * treatment of rays parallel to a slab. A ray lying exactly in any face plane
 * of a (closed) box, with either sign of the zero direction component,
 * touches the box and must be kept; a ray one ulp outside that plane must be
 * dropped; a ray strictly inside the slab is unconstrained by it. (The finite
 * 1e30 stand-in for 1/0 once culled rays in the upper face plane for +0 and
 * the lower one for -0.) */
#include <math.h>

#include "check.h"
#include "geometry/aabb.h"

static float box_t(const float *org, const float *dir, const float *lo, const float *hi,
                   float tmax)
{
    tt_wray r;
    tt_wray_init(&r, org, dir, 0.0f, tmax);
    return tt_ray_box(&r, lo, hi, tmax);
}

/* Entry at distance d, lowered by at most the relative 2^-16 the test
 * applies (and never raised). */
static int entry_is(float t, float d) { return t <= d && t >= d - fabsf(d) * (1.0f / 32768.0f); }

static void test_plain(void)
{
    const float lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    const float o[3] = {0.5f, 0.5f, -2}, up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
    CHECK(entry_is(box_t(o, up, lo, hi, INFINITY), 2.0f));
    CHECK(box_t(o, down, lo, hi, INFINITY) == INFINITY);
    CHECK(box_t(o, up, lo, hi, 1.5f) == INFINITY); /* box beyond tmax */
    const float in[3] = {0.5f, 0.5f, 0.5f};
    CHECK(box_t(in, down, lo, hi, INFINITY) == 0.0f); /* origin inside: entry tmin */
    const float side[3] = {2, 0.5f, -2}, diag[3] = {-1, 0, 1};
    CHECK(entry_is(box_t(side, diag, lo, hi, INFINITY), 2.0f));
    /* behind the origin, found with a negative tmin: the far distance is
     * widened away from 0, so a flat box at t = -1.5 is kept */
    {
        const float flo[3] = {0, 0, 0.5f}, fhi[3] = {1, 1, 0.5f}, o2[3] = {0.5f, 0.5f, 2};
        tt_wray r;
        tt_wray_init(&r, o2, up, -10.0f, INFINITY);
        CHECK(entry_is(tt_ray_box(&r, flo, fhi, INFINITY), -1.5f));
        tt_wray_init(&r, o2, up, -1.0f, INFINITY);
        CHECK(tt_ray_box(&r, flo, fhi, INFINITY) == INFINITY); /* tmin after it */
    }
    const float miss[3] = {5, 0.5f, -2}; /* passes x = 1 at t = 4, z = 2 */
    CHECK(box_t(miss, diag, lo, hi, INFINITY) == INFINITY);
}

/* For every axis k, both faces of the box on k, both signs of zero for
 * dir[k], and every travel axis j != k in both directions: a ray lying in
 * the face plane, starting 2 before the box on j, the third axis at the
 * box's middle (or on its faces too: an edge line), enters at distance 2.
 * The same ray one ulp outside the plane misses, one ulp inside hits. */
static void face_planes(const float *lo, const float *hi, const char *what)
{
    for (int k = 0; k < 3; k++)
        for (int face = 0; face < 2; face++)
            for (int zs = 0; zs < 2; zs++)
                for (int j = 0; j < 3; j++)
                    for (int js = 0; js < 2; js++)
                        for (int third = 0; third < 3; third++) {
                            if (j == k) continue;
                            const int m = 3 - j - k;
                            float org[3], dir[3];
                            const float plane = face ? hi[k] : lo[k];
                            org[k] = plane;
                            dir[k] = zs ? -0.0f : 0.0f;
                            org[j] = js ? hi[j] + 2.0f : lo[j] - 2.0f;
                            dir[j] = js ? -1.0f : 1.0f;
                            /* middle of the third axis, or its lower / upper face */
                            org[m] = third == 0 ? 0.5f * (lo[m] + hi[m]) : third == 1 ? lo[m] : hi[m];
                            dir[m] = 0.0f;
                            const float t = box_t(org, dir, lo, hi, INFINITY);
                            CHECK_MSG(entry_is(t, 2.0f),
                                      "%s: ray in the %s face plane of axis %d, dir[%d] = %s0, "
                                      "travelling %s%d, third axis %d: got %g, want 2",
                                      what, face ? "upper" : "lower", k, k, zs ? "-" : "+",
                                      js ? "-" : "+", j, third, (double)t);
                            /* the hit must respect tmax: 2.5 keeps it, 1.5 drops it */
                            CHECK(entry_is(box_t(org, dir, lo, hi, 2.5f), 2.0f));
                            CHECK(box_t(org, dir, lo, hi, 1.5f) == INFINITY);
                            /* one ulp outside the face: parallel and outside, a miss */
                            org[k] = nextafterf(plane, face ? INFINITY : -INFINITY);
                            CHECK_MSG(box_t(org, dir, lo, hi, INFINITY) == INFINITY,
                                      "%s: ray just outside the %s face of axis %d hits",
                                      what, face ? "upper" : "lower", k);
                            /* one ulp inside (where the box is not flat): a hit */
                            if (lo[k] < hi[k]) {
                                org[k] = nextafterf(plane, face ? -INFINITY : INFINITY);
                                CHECK(entry_is(box_t(org, dir, lo, hi, INFINITY), 2.0f));
                            }
                        }
}

/* The origin on a face plane with the ray running along that face, starting
 * inside the box's extent on every other axis: entry tmin (0). */
static void inside_on_face(const float *lo, const float *hi)
{
    for (int k = 0; k < 3; k++)
        for (int face = 0; face < 2; face++)
            for (int zs = 0; zs < 2; zs++) {
                float org[3], dir[3];
                for (int i = 0; i < 3; i++) {
                    org[i] = 0.5f * (lo[i] + hi[i]);
                    dir[i] = i == (k + 1) % 3 ? 1.0f : 0.0f;
                }
                org[k] = face ? hi[k] : lo[k];
                dir[k] = zs ? -0.0f : 0.0f;
                CHECK(box_t(org, dir, lo, hi, INFINITY) == 0.0f);
            }
}

int main(void)
{
    test_plain();
    /* the brief's repro: box [0,1]^3, origin (1, 0.5, -1), direction +z */
    {
        const float lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
        const float o[3] = {1, 0.5f, -1}, d[3] = {0, 0, 1};
        CHECK(entry_is(box_t(o, d, lo, hi, INFINITY), 1.0f));
    }
    const float cube_lo[3] = {0, 0, 0}, cube_hi[3] = {1, 1, 1};
    const float odd_lo[3] = {-3.25f, 0.125f, 7}, odd_hi[3] = {-1, 9.5f, 7.75f};
    const float flat_lo[3] = {0, 0, 0.5f}, flat_hi[3] = {1, 1, 0.5f}; /* zero thickness in z */
    const float line_lo[3] = {2, -1, 3}, line_hi[3] = {2, 1, 3};      /* a segment */
    face_planes(cube_lo, cube_hi, "unit cube");
    face_planes(odd_lo, odd_hi, "offset box");
    face_planes(flat_lo, flat_hi, "flat box");
    face_planes(line_lo, line_hi, "segment box");
    inside_on_face(cube_lo, cube_hi);
    inside_on_face(odd_lo, odd_hi);
    return tt_test_finish();
}
