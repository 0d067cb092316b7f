/* Short rays ending on a triangle much wider than they are long: every
 * structure x every ISA against bruteforce, single rays and packets.
 *
 * The watertight test's t errs by about the vertices' distance from the
 * origin times 2^-24 (its translated coordinates), not by a fraction of t.
 * A shadow ray from a point 0.016 units in front of a wall of Sibenik found
 * its hit 2.3e-5 (relative) before the plane of the wall's flat box, and
 * the box test's relative margin (2^-16 of the entry) culled that box: the
 * scalar and SSE 4.2 R-tree and the R-tree's packets missed the wall that
 * bruteforce and the FMA kernels (whose box test had an absolute pad) hit.
 * The box tests now all carry that pad (tt_rt_planes.pad, pk_rays.pad).
 *
 * Rays: the shadow rays of sibenik:main (64 x 64), each ending exactly at,
 * one float past and one float short of its first occluder, and the ray
 * found by test_packets. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/isa.h"
#include "check.h"
#include "compare.h"

#define SIZE 64

/* The shadow rays of the view whose closest hit (tmax = inf) is found,
 * three per occluder: tmax at the hit's t, one float above and one below. */
static tt_ray *ending_rays(const tt_scene *scene, const tt_accel *ref, const tt_camera *cam,
                           size_t *n_out)
{
    const size_t n = (size_t)SIZE * SIZE;
    tt_ray *primary = malloc(n * sizeof *primary);
    tt_ray *out = malloc((3 * n + 1) * sizeof *out);
    if (!primary || !out || tt_camera_rays(cam, SIZE, SIZE, primary) != TT_OK) exit(1);
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        tt_hit h;
        tt_ray s;
        tt_intersect1(ref, &primary[i], &h);
        if (h.prim == TT_INVALID_ID || !tt_shadow_ray(scene, cam, &primary[i], &h, &s)) continue;
        s.tmax = INFINITY;
        tt_intersect1(ref, &s, &h);
        if (h.prim == TT_INVALID_ID) continue;
        const float ends[3] = {h.t, nextafterf(h.t, INFINITY), nextafterf(h.t, 0.0f)};
        for (int e = 0; e < 3; e++) {
            out[k] = s;
            out[k++].tmax = ends[e];
        }
    }
    /* the ray of the report (test_packets, sibenik:main): a hit at t =
     * 0x1.09c72cp-6 on triangle 13403, tmax one float above it */
    const tt_ray found = {{-0x1.f9f538p+0f, -0x1.0f07fcp+1f, -0x1.f34e6cp+1f},
                          0.0f,
                          {0x1.50f34ep-2f, 0x1.5efc08p-1f, 0x1.4c854cp-1f},
                          0x1.09c72ep-6f};
    out[k++] = found;
    free(primary);
    *n_out = k;
    return out;
}

/* The structure's single rays and packets against bruteforce's answers
 * (want, want_occ: traced once for all structures, bruteforce being the
 * slow part under the sanitizers). */
static void check_structure(const tt_accel *a, const tt_hit *want, const uint8_t *want_occ,
                            const tt_ray *rays, size_t n, const char *what)
{
    tt_hit *got = malloc(n * sizeof *got);
    uint8_t *occ = malloc(n);
    if (!got || !occ) exit(1);
    size_t bad = 0;
    for (size_t i = 0; i < n; i++) {
        tt_hit h;
        int o = 0;
        const int o_ref = want_occ[i];
        tt_intersect1(a, &rays[i], &h);
        tt_occluded1(a, &rays[i], &o);
        if (!tt_test_hits_agree(&h, &want[i]) || o != o_ref) {
            if (bad < 3)
                fprintf(stderr, "  %s ray %zu: prim %u t %a, bruteforce prim %u t %a; occluded %d %d\n",
                        what, i, h.prim, (double)h.t, want[i].prim, (double)want[i].t, o, o_ref);
            bad++;
        }
    }
    CHECK_MSG(bad == 0, "%s: %zu of %zu single rays disagree with bruteforce", what, bad, n);
    /* the batch with packets forced on: runs of shadow rays */
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    bo.packets = TT_PACKETS_ON;
    CHECK(tt_intersect(a, rays, n, got, NULL, &bo) == TT_OK);
    CHECK(tt_occluded(a, rays, n, occ, NULL, &bo) == TT_OK);
    bad = 0;
    for (size_t i = 0; i < n; i++)
        if (!tt_test_hits_agree(&got[i], &want[i]) || occ[i] != want_occ[i]) bad++;
    CHECK_MSG(bad == 0, "%s: %zu of %zu rays in packets disagree with bruteforce", what, bad, n);
    free(got);
    free(occ);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *scene = tt_test_load_scene(ctx, "sibenik.obj");
    tt_camera cam;
    tt_test_view(ctx, "sibenik:main", &cam);
    tt_accel *ref = tt_test_build_default(ctx, scene, "bruteforce");
    size_t n = 0;
    tt_ray *rays = ending_rays(scene, ref, &cam, &n);
    CHECK_MSG(n > (size_t)SIZE * SIZE, "%zu rays ending on their occluder", n);
    tt_hit *want = malloc(n * sizeof *want);
    uint8_t *want_occ = malloc(n);
    if (!want || !want_occ) exit(1);
    for (size_t i = 0; i < n; i++) {
        int o = 0;
        tt_intersect1(ref, &rays[i], &want[i]);
        tt_occluded1(ref, &rays[i], &o);
        want_occ[i] = (uint8_t)o;
    }
    static const char *names[] = {"rtree", "wbvh", "kdtree"};
    for (size_t s = 0; s < sizeof names / sizeof names[0]; s++) {
        if (!tt_test_has_accel(names[s])) continue;
        for (int isa = TT_ISA_FIRST; isa <= TT_ISA_LAST; isa++) {
            if (!tt_test_isa_runs((tt_isa)isa)) continue;
            tt_accel *a = tt_test_build_isa(ctx, scene, names[s], (tt_isa)isa);
            char what[64];
            snprintf(what, sizeof what, "%s %s", names[s], tt_isa_name((tt_isa)isa));
            check_structure(a, want, want_occ, rays, n, what);
            tt_accel_destroy(a);
        }
    }
    free(rays);
    free(want);
    free(want_occ);
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
