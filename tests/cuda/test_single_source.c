/* The single-source property of the GPU tracer, checked on the CPU (no GPU
 * or CUDA needed): this file compiles the kernels' per-pixel code
 * (src/cuda/gpu_pixel_*.h: camera ray, traversal, shadow ray) as C exactly
 * as nvcc compiles it for the device, i.e. with the scalar node test
 * (TT_NO_SIMD; the static assertion below proves it was taken), and checks
 * on shared views, pixel by pixel and for both statistics variants:
 *  - against bruteforce, per the agreement rule of the conventions (closest
 *    hit of the primary ray; occlusion of the shadow ray built from it);
 *  - against the library's own CPU path (SIMD node test where there is one,
 *    through tt_intersect1_ex / tt_occluded1_ex with the renderer's hints):
 *    the same triangle, bit-identical t, the same occlusion and the same
 *    per-ray counts, so the GPU's code takes the same decisions;
 *  - the auto traversal's choice per ray origin (inside / outside / on the
 *    root box) against tt_accel_locate.
 * The R-tree in both layouts (the compact one with its stackless walk, the
 * GPU's traversal for it). */
#define TT_NO_SIMD 1

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "accel/accel.h"
#include "accel/kdtree/kd_tree.h"
#include "accel/rtree/rtree.h"
#include "check.h"
#include "compare.h"
#include "render/camera.h"

#define TT_STATS 0
#include "accel/stats_variant.h"
#include "cuda/gpu_pixel_kdtree.h"
#include "cuda/gpu_pixel_rtree.h"
#undef TT_STATS
#define TT_STATS 1
#include "accel/stats_variant.h"
#include "cuda/gpu_pixel_kdtree.h"
#include "cuda/gpu_pixel_rtree.h"
#undef TT_STATS

/* The scalar lanes hold only the ray pointer; the SSE ones hold vectors. */
_Static_assert(sizeof(tt_rt_lanes) == sizeof(const tt_wray *),
               "TT_NO_SIMD must select the scalar node test, the one the GPU runs");

#define MAX_REPORTS 5

static int stats_equal(const tt_ray_stats *a, const tt_ray_stats *b)
{
    return a->rays == b->rays && a->nodes == b->nodes && a->interior == b->interior &&
           a->leaves == b->leaves && a->boxes == b->boxes && a->triangles == b->triangles;
}

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* One view's frame as the renderer sets it up. */
typedef struct view_frame {
    tt_context *ctx;
    const tt_scene *scene;
    tt_camera cam;
    tt_camera_basis basis;
    float eps;
    uint32_t w, h;
    const tt_accel *bf;
    /* bruteforce per pixel, traced once per view: the primary hit, and the
     * occlusion of the shadow ray built from the hit in shadow_from */
    tt_hit *bf_hit;
    tt_hit *shadow_from;
    int *bf_occluded;
} view_frame;

/* Bruteforce's closest hit of pixel (x, y)'s ray r. */
static tt_hit bf_primary(const view_frame *v, uint32_t x, uint32_t y, const tt_ray *r)
{
    tt_hit *h = &v->bf_hit[(size_t)y * v->w + x];
    if (h->u < 0.0f) REQUIRE_OK(v->ctx, tt_intersect1(v->bf, r, h));
    return *h;
}

/* Bruteforce's occlusion of shadow ray s, built from primary hit `from`. */
static int bf_shadow(const view_frame *v, uint32_t x, uint32_t y, const tt_hit *from,
                     const tt_ray *s)
{
    const size_t i = (size_t)y * v->w + x;
    tt_hit *f = &v->shadow_from[i];
    if (f->prim != from->prim || !same_bits(f->t, from->t)) {
        REQUIRE_OK(v->ctx, tt_occluded1(v->bf, s, &v->bf_occluded[i]));
        *f = *from;
    }
    return v->bf_occluded[i];
}

typedef struct counts {
    size_t bad_ref, bad_cpu, rays;
    const char *what;
} counts;

static void report(counts *c, size_t *bad, uint32_t x, uint32_t y, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

static void report(counts *c, size_t *bad, uint32_t x, uint32_t y, const char *fmt, ...)
{
    if ((*bad)++ >= MAX_REPORTS) return;
    va_list ap;
    fprintf(stderr, "%s, pixel (%u, %u): ", c->what, x, y);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

/* ---------------------------------------------------------------- R-tree */

static void rtree_pixel(const view_frame *v, const tt_accel *accel, uint32_t x, uint32_t y, counts *c)
{
    const rt_tree *t = accel->impl;
    const uint32_t eye_hint = tt_accel_locate(accel, v->cam.eye);
    /* the kernels' code, fast and counting */
    uint32_t prim, prim_s;
    float dist, dist_s;
    tt_ray_stats st_gpu;
    memset(&st_gpu, 0, sizeof st_gpu);
    const int compact = t->layout == TT_RTREE_LAYOUT_COMPACT;
    if (compact) {
        tt_gpu_rtc_primary(&t->compact.c, &v->basis, x, y, &prim, &dist, NULL);
        tt_gpu_rtc_primary_stats(&t->compact.c, &v->basis, x, y, &prim_s, &dist_s, &st_gpu);
    } else {
        tt_gpu_rt_primary(&t->p, (int)eye_hint, &v->basis, x, y, &prim, &dist, NULL);
        tt_gpu_rt_primary_stats(&t->p, (int)eye_hint, &v->basis, x, y, &prim_s, &dist_s,
                                &st_gpu);
    }
    c->rays++;
    /* the library's CPU path and bruteforce on the same ray */
    tt_ray r;
    tt_camera_ray(&v->cam, v->w, v->h, x, y, &r);
    tt_hit h_cpu, h_bf;
    tt_ray_stats st_cpu;
    memset(&st_cpu, 0, sizeof st_cpu);
    tt_trace_args args = {eye_hint, TT_INVALID_ID, &st_cpu};
    REQUIRE_OK(v->ctx, tt_intersect1_ex(accel, &r, &h_cpu, &args));
    h_bf = bf_primary(v, x, y, &r);
    tt_hit h_gpu = {dist, 0.0f, 0.0f, prim};
    if (prim != prim_s || !same_bits(dist, dist_s))
        report(c, &c->bad_cpu, x, y, "fast prim %u t %.9g, counting prim %u t %.9g", prim, dist,
               prim_s, dist_s);
    if (prim != h_cpu.prim || (prim != TT_INVALID_ID && !same_bits(dist, h_cpu.t)) ||
        !stats_equal(&st_gpu, &st_cpu))
        report(c, &c->bad_cpu, x, y,
               "GPU code prim %u t %.9g (%llu boxes), CPU path prim %u t %.9g (%llu boxes)", prim,
               dist, (unsigned long long)st_gpu.boxes, h_cpu.prim, h_cpu.t,
               (unsigned long long)st_cpu.boxes);
    if (!tt_test_hits_agree_t(&h_gpu, &h_bf))
        report(c, &c->bad_ref, x, y, "GPU code prim %u t %.9g, bruteforce prim %u t %.9g", prim,
               dist, h_bf.prim, h_bf.t);
    if (prim == TT_INVALID_ID || !v->cam.has_light) return;

    /* the shadow ray from the kernels' hit */
    const int trav = (int)t->traversal;
    tt_ray_stats sh_gpu, sh_cpu;
    memset(&sh_gpu, 0, sizeof sh_gpu);
    memset(&sh_cpu, 0, sizeof sh_cpu);
    int occ, occ_s;
    if (compact) {
        occ = tt_gpu_rtc_shadow(&t->compact.c, &v->basis, v->scene->tri, v->cam.light, v->eps, x,
                                y, prim, dist, NULL);
        occ_s = tt_gpu_rtc_shadow_stats(&t->compact.c, &v->basis, v->scene->tri, v->cam.light,
                                        v->eps, x, y, prim, dist, &sh_gpu);
    } else {
        occ = tt_gpu_rt_shadow(&t->p, trav, t->root_box, &v->basis, v->scene->tri, v->cam.light,
                               v->eps, x, y, prim, dist, NULL);
        occ_s = tt_gpu_rt_shadow_stats(&t->p, trav, t->root_box, &v->basis, v->scene->tri,
                                       v->cam.light, v->eps, x, y, prim, dist, &sh_gpu);
    }
    c->rays++;
    tt_ray s;
    CHECK(tt_shadow_ray(v->scene, &v->cam, &r, &h_gpu, &s) == 1);
    int occ_cpu = -1, occ_bf = -1;
    tt_trace_args sargs = {TT_INVALID_ID, TT_INVALID_ID, &sh_cpu};
    REQUIRE_OK(v->ctx, tt_occluded1_ex(accel, &s, &occ_cpu, &sargs));
    occ_bf = bf_shadow(v, x, y, &h_gpu, &s);
    if (occ != occ_s || occ != occ_cpu || !stats_equal(&sh_gpu, &sh_cpu))
        report(c, &c->bad_cpu, x, y,
               "shadow: GPU code %d / counting %d (%llu boxes), CPU path %d (%llu boxes)", occ,
               occ_s, (unsigned long long)sh_gpu.boxes, occ_cpu,
               (unsigned long long)sh_cpu.boxes);
    if (occ != occ_bf)
        report(c, &c->bad_ref, x, y, "shadow: GPU code %d, bruteforce %d", occ, occ_bf);
}

/* The auto choice for origins inside, outside and exactly on the root box. */
static void rtree_pick(const tt_accel *accel)
{
    const rt_tree *t = accel->impl;
    const float *b = t->root_box;
    float pts[][3] = {
        {b[0], b[1], b[2]},
        {b[3], b[4], b[5]},
        {0.5f * (b[0] + b[3]), 0.5f * (b[1] + b[4]), 0.5f * (b[2] + b[5])},
        {nextafterf(b[0], -INFINITY), b[1], b[2]},
        {b[0], nextafterf(b[4], INFINITY), b[2]},
        {b[0], b[1], b[5] + 1.0f},
    };
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
        uint32_t want = tt_accel_locate(accel, pts[i]);
        int got = tt_gpu_rt_pick((int)t->traversal, t->root_box, pts[i]);
        CHECK_MSG((uint32_t)got == want, "point %zu: GPU pick %d, tt_accel_locate %u", i, got, want);
    }
}

/* layout: the complete one, or the compact one (M = 8, its stackless
 * traversal: what the GPU runs for it, and the CPU path the same code). */
static void rtree_view(const view_frame *v, tt_rtree_traversal traversal, tt_rtree_layout layout,
                       const char *view)
{
    static const char *const names[] = {"auto", "stackless", "ordered", "stack"};
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = "rtree";
    o.rtree.traversal = traversal;
    o.rtree.layout = layout;
    if (layout == TT_RTREE_LAYOUT_COMPACT) o.rtree.m = 3, o.rtree.M = 8;
    tt_accel *accel = NULL;
    REQUIRE_OK(v->ctx, tt_accel_build(v->ctx, v->scene, &o, &accel));
    char what[128];
    snprintf(what, sizeof what, "%s, rtree %s%s", view, names[traversal],
             layout == TT_RTREE_LAYOUT_COMPACT ? " compact" : "");
    counts c = {0, 0, 0, what};
    for (uint32_t y = 0; y < v->h; y++)
        for (uint32_t x = 0; x < v->w; x++) rtree_pixel(v, accel, x, y, &c);
    CHECK_MSG(c.bad_ref == 0, "%s: %zu of %zu rays disagree with bruteforce", what, c.bad_ref,
              c.rays);
    CHECK_MSG(c.bad_cpu == 0, "%s: %zu of %zu rays differ from the CPU path", what, c.bad_cpu,
              c.rays);
    if (layout == TT_RTREE_LAYOUT_COMPLETE) rtree_pick(accel);
    tt_accel_destroy(accel);
}

/* --------------------------------------------------------------- kd-tree */

static void kd_pixel(const view_frame *v, const tt_accel *accel, uint32_t x, uint32_t y,
                     counts *c)
{
    const tt_kdtree *kd = tt_kdtree_of(accel);
    const int trav = (int)accel->options.kdtree.traversal;
    const uint32_t eye_hint = tt_accel_locate(accel, v->cam.eye);
    uint32_t prim, prim_s, end, end_s;
    float dist, dist_s;
    tt_ray_stats st_gpu;
    memset(&st_gpu, 0, sizeof st_gpu);
    tt_gpu_kd_primary(&kd->view, trav, eye_hint, &v->basis, x, y, &prim, &dist, &end, NULL);
    tt_gpu_kd_primary_stats(&kd->view, trav, eye_hint, &v->basis, x, y, &prim_s, &dist_s, &end_s,
                            &st_gpu);
    c->rays++;
    tt_ray r;
    tt_camera_ray(&v->cam, v->w, v->h, x, y, &r);
    tt_hit h_cpu;
    tt_ray_stats st_cpu;
    memset(&st_cpu, 0, sizeof st_cpu);
    tt_trace_args args = {eye_hint, TT_INVALID_ID, &st_cpu};
    REQUIRE_OK(v->ctx, tt_intersect1_ex(accel, &r, &h_cpu, &args));
    tt_hit h_bf = bf_primary(v, x, y, &r);
    tt_hit h_gpu = {dist, 0.0f, 0.0f, prim};
    if (prim != prim_s || !same_bits(dist, dist_s) || end != end_s)
        report(c, &c->bad_cpu, x, y, "fast prim %u t %.9g end %u, counting prim %u t %.9g end %u",
               prim, dist, end, prim_s, dist_s, end_s);
    if (prim != h_cpu.prim || (prim != TT_INVALID_ID && !same_bits(dist, h_cpu.t)) ||
        end != args.end_hint || !stats_equal(&st_gpu, &st_cpu))
        report(c, &c->bad_cpu, x, y,
               "GPU code prim %u t %.9g end %u (%llu nodes), CPU path prim %u t %.9g end %u "
               "(%llu nodes)",
               prim, dist, end, (unsigned long long)st_gpu.nodes, h_cpu.prim, h_cpu.t,
               args.end_hint, (unsigned long long)st_cpu.nodes);
    if (!tt_test_hits_agree_t(&h_gpu, &h_bf))
        report(c, &c->bad_ref, x, y, "GPU code prim %u t %.9g, bruteforce prim %u t %.9g", prim,
               dist, h_bf.prim, h_bf.t);
    if (prim == TT_INVALID_ID || !v->cam.has_light) return;

    /* the shadow ray, started where the primary ray ended */
    tt_ray_stats sh_gpu, sh_cpu;
    memset(&sh_gpu, 0, sizeof sh_gpu);
    memset(&sh_cpu, 0, sizeof sh_cpu);
    int occ = tt_gpu_kd_shadow(&kd->view, trav, end, &v->basis, v->cam.light, v->eps, x, y, prim,
                               dist, NULL);
    int occ_s = tt_gpu_kd_shadow_stats(&kd->view, trav, end, &v->basis, v->cam.light, v->eps, x,
                                       y, prim, dist, &sh_gpu);
    c->rays++;
    tt_ray s;
    CHECK(tt_shadow_ray(v->scene, &v->cam, &r, &h_gpu, &s) == 1);
    int occ_cpu = -1;
    tt_trace_args sargs = {end, TT_INVALID_ID, &sh_cpu};
    REQUIRE_OK(v->ctx, tt_occluded1_ex(accel, &s, &occ_cpu, &sargs));
    int occ_bf = bf_shadow(v, x, y, &h_gpu, &s);
    if (occ != occ_s || occ != occ_cpu || !stats_equal(&sh_gpu, &sh_cpu))
        report(c, &c->bad_cpu, x, y,
               "shadow: GPU code %d / counting %d (%llu nodes), CPU path %d (%llu nodes)", occ,
               occ_s, (unsigned long long)sh_gpu.nodes, occ_cpu, (unsigned long long)sh_cpu.nodes);
    if (occ != occ_bf)
        report(c, &c->bad_ref, x, y, "shadow: GPU code %d, bruteforce %d", occ, occ_bf);
}

static void kd_view(const view_frame *v, tt_kd_traversal traversal, const char *view)
{
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = "kdtree";
    o.kdtree.traversal = traversal;
    tt_accel *accel = NULL;
    REQUIRE_OK(v->ctx, tt_accel_build(v->ctx, v->scene, &o, &accel));
    char what[128];
    snprintf(what, sizeof what, "%s, kdtree %s", view, traversal == TT_KD_HTR ? "htr" : "sltr");
    counts c = {0, 0, 0, what};
    for (uint32_t y = 0; y < v->h; y++)
        for (uint32_t x = 0; x < v->w; x++) kd_pixel(v, accel, x, y, &c);
    CHECK_MSG(c.bad_ref == 0, "%s: %zu of %zu rays disagree with bruteforce", what, c.bad_ref,
              c.rays);
    CHECK_MSG(c.bad_cpu == 0, "%s: %zu of %zu rays differ from the CPU path", what, c.bad_cpu,
              c.rays);
    tt_accel_destroy(accel);
}

/* ------------------------------------------------------------------ views */

static void check_view(tt_context *ctx, const char *file, const char *view, uint32_t size)
{
    view_frame v;
    v.ctx = ctx;
    v.scene = tt_test_load_scene(ctx, file);
    tt_test_view(ctx, view, &v.cam);
    v.w = v.h = size;
    tt_camera_basis_init(&v.basis, &v.cam, size, size);
    v.eps = 1e-4f * tt_scene_diagonal(v.scene);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *bf = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, v.scene, &bo, &bf));
    v.bf = bf;
    const size_t n = (size_t)size * size;
    v.bf_hit = malloc(n * sizeof *v.bf_hit);
    v.shadow_from = malloc(n * sizeof *v.shadow_from);
    v.bf_occluded = calloc(n, sizeof *v.bf_occluded);
    if (!v.bf_hit || !v.shadow_from || !v.bf_occluded) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    for (size_t i = 0; i < n; i++) {
        v.bf_hit[i].u = -1.0f; /* not traced yet */
        v.shadow_from[i].prim = TT_INVALID_ID;
    }
    rtree_view(&v, TT_RTREE_AUTO, TT_RTREE_LAYOUT_COMPLETE, view);
    rtree_view(&v, TT_RTREE_STACKLESS, TT_RTREE_LAYOUT_COMPLETE, view);
    rtree_view(&v, TT_RTREE_ORDERED, TT_RTREE_LAYOUT_COMPLETE, view);
    rtree_view(&v, TT_RTREE_STACKLESS, TT_RTREE_LAYOUT_COMPACT, view);
    kd_view(&v, TT_KD_SLTR, view);
    kd_view(&v, TT_KD_HTR, view);
    free(v.bf_hit);
    free(v.shadow_from);
    free(v.bf_occluded);
    tt_accel_destroy(bf);
    tt_scene_destroy((tt_scene *)v.scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    check_view(ctx, "bun_zipper_res4.ply", "bunny_res4:main", 32);
    check_view(ctx, "bun_zipper.ply", "bunny:main", 40);
    check_view(ctx, "sibenik.obj", "sibenik:main", 32);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
