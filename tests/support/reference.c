#include "reference.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare.h"

#define MAX_REPORTS 5

struct tt_test_reference {
    const tt_scene *scene;
    tt_camera camera;
    uint32_t width, height;
    tt_hit *hit;       /* per pixel, the reference's primary hit          */
    int8_t *occluded;  /* per pixel: -1 no shadow ray, else 0 or 1        */
};

tt_test_reference *tt_test_reference_view(const tt_scene *scene, const tt_accel *ref,
                                          const tt_camera *camera, uint32_t width,
                                          uint32_t height)
{
    tt_test_reference *r = calloc(1, sizeof *r);
    size_t n = (size_t)width * height;
    if (r) {
        r->hit = malloc(n * sizeof *r->hit);
        r->occluded = malloc(n);
    }
    if (!r || !r->hit || !r->occluded) {
        fprintf(stderr, "tt_test_reference_view: out of memory\n");
        exit(1);
    }
    r->scene = scene;
    r->camera = *camera;
    r->width = width;
    r->height = height;
    for (uint32_t y = 0; y < height; y++) {
        for (uint32_t x = 0; x < width; x++) {
            size_t i = (size_t)y * width + x;
            tt_ray ray, shadow;
            int occ = 0;
            if (tt_camera_ray(camera, width, height, x, y, &ray) != TT_OK ||
                tt_intersect1(ref, &ray, &r->hit[i]) != TT_OK) {
                fprintf(stderr, "tt_test_reference_view: the reference failed on pixel %u %u\n",
                        x, y);
                exit(1);
            }
            r->occluded[i] = -1;
            if (tt_shadow_ray(scene, camera, &ray, &r->hit[i], &shadow)) {
                if (tt_occluded1(ref, &shadow, &occ) != TT_OK) {
                    fprintf(stderr, "tt_test_reference_view: the reference failed on a shadow ray\n");
                    exit(1);
                }
                r->occluded[i] = (int8_t)occ;
            }
        }
    }
    return r;
}

void tt_test_reference_destroy(tt_test_reference *r)
{
    if (!r) return;
    free(r->hit);
    free(r->occluded);
    free(r);
}

static void report(size_t *bad, const char *name, const char *kind, uint32_t x, uint32_t y,
                   const char *detail)
{
    if ((*bad)++ < MAX_REPORTS)
        fprintf(stderr, "mismatch (%s, %s) at pixel %u %u: %s\n", name, kind, x, y, detail);
}

size_t tt_test_compare_view_reference(const tt_accel *test, const tt_test_reference *r)
{
    const char *name = tt_accel_name(test);
    size_t bad = 0;
    uint32_t eye_hint = tt_accel_locate(test, r->camera.eye);
    char msg[256];
    for (uint32_t y = 0; y < r->height; y++) {
        for (uint32_t x = 0; x < r->width; x++) {
            size_t i = (size_t)y * r->width + x;
            const tt_hit *h_ref = &r->hit[i];
            tt_ray ray, shadow;
            tt_hit h_fast, h_stats;
            tt_ray_stats st;
            memset(&st, 0, sizeof st);
            tt_trace_args a_fast = {eye_hint, TT_INVALID_ID, NULL};
            tt_trace_args a_stats = {eye_hint, TT_INVALID_ID, &st};
            tt_camera_ray(&r->camera, r->width, r->height, x, y, &ray);
            tt_status e1 = tt_intersect1_ex(test, &ray, &h_fast, &a_fast);
            tt_status e2 = tt_intersect1_ex(test, &ray, &h_stats, &a_stats);
            if (e1 || e2) {
                report(&bad, name, "closest", x, y, "a call failed");
            } else if (!tt_test_hits_agree(h_ref, &h_fast) || !tt_test_hits_agree(h_ref, &h_stats)) {
                snprintf(msg, sizeof msg,
                         "reference prim %u t %.9g, fast prim %u t %.9g, stats prim %u t %.9g",
                         h_ref->prim, h_ref->t, h_fast.prim, h_fast.t, h_stats.prim, h_stats.t);
                report(&bad, name, "closest", x, y, msg);
            } else if (st.rays != 1) {
                report(&bad, name, "closest", x, y, "the counting variant did not count one ray");
            }
            if (r->occluded[i] < 0) continue;
            tt_shadow_ray(r->scene, &r->camera, &ray, h_ref, &shadow);
            int o_fast = -2, o_stats = -3;
            memset(&st, 0, sizeof st);
            tt_trace_args s_fast = {a_fast.end_hint, TT_INVALID_ID, NULL};
            tt_trace_args s_stats = {a_fast.end_hint, TT_INVALID_ID, &st};
            tt_occluded1_ex(test, &shadow, &o_fast, &s_fast);
            tt_occluded1_ex(test, &shadow, &o_stats, &s_stats);
            if (o_fast != r->occluded[i] || o_stats != r->occluded[i]) {
                snprintf(msg, sizeof msg, "reference %d, fast %d, stats %d", r->occluded[i],
                         o_fast, o_stats);
                report(&bad, name, "occluded", x, y, msg);
            }
        }
    }
    if (bad)
        fprintf(stderr, "%s: %zu of %u pixels disagree\n", name, bad, r->width * r->height);
    return bad;
}
