/* The per-ISA fast kernels (tt_kd_cpu_kernels: AVX2 and AVX-512 test
 * leaves eight triangles at a time from the leaf blocks of kd_blocks.h)
 * return bit for bit what the scalar kernels return: the same triangle, t, u and v of every closest hit, the
 * same occlusion and the same end node, for every traversal, on primary
 * and shadow rays of the shared views and on random and vertex-aimed rays
 * of scenes with big leaves (identical and coplanar triangles: zero edge
 * functions, ties at equal t, degenerate triangles). Agreement with
 * bruteforce itself is test_views.c's and test_rays.c's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "kd_scenes.h"
#include "kd_testing.h"

/* The largest leaf of tree t: the scenes must have leaves of several
 * triangles (several lanes of a block, ties between them), or this test
 * could hardly fail. */
static uint32_t biggest_leaf(const tt_kdtree *t)
{
    uint32_t most = 0;
    for (uint32_t i = 0; i < t->node_slots; i++) {
        const tt_kd_node n = t->nodes[i];
        /* Extension slots hold aug[] indices; only real nodes count. */
        if (i > 0 && !tt_kd_is_leaf(t->nodes[i - 1].bits) && tt_kd_is_aug(t->nodes[i - 1].bits))
            continue;
        if (tt_kd_is_leaf(n.bits) && tt_kd_leaf_count(n.bits) > most) most = tt_kd_leaf_count(n.bits);
    }
    return most;
}

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Traces rays[0..n) through kernels k and the scalar ones, every
 * traversal; returns how many answers differ. */
static size_t differ(const tt_kdtree *t, const tt_kd_kernels *k, const tt_kd_kernels *s,
                     const tt_ray *rays, const uint32_t *hints, size_t n)
{
    size_t bad = 0;
    /* k walks the view a build for its ISA gives it: with leaf blocks
     * (kd_blocks.h) for the AVX2 / AVX-512 kernels. */
    const tt_kd_view *kv = k->blocks ? &t->block_view : &t->view;
    CHECK_MSG(!k->blocks || kv->blocks, "no leaf blocks for a kernel that reads them");
    for (int tr = TT_KD_HTR; tr <= TT_KD_SEQ; tr++)
        for (size_t i = 0; i < n; i++) {
            tt_wray w;
            tt_hit a, b;
            uint32_t ea, eb, oa, ob;
            tt_wray_init(&w, rays[i].org, rays[i].dir, rays[i].tmin, rays[i].tmax);
            k->intersect(kv, tr, &w, hints[i], &a, &ea);
            s->intersect(&t->view, tr, &w, hints[i], &b, &eb);
            int ok = a.prim == b.prim && same_bits(a.t, b.t) && same_bits(a.u, b.u) &&
                     same_bits(a.v, b.v) && ea == eb;
            const int occ_a = k->occluded(kv, tr, &w, hints[i], TT_INVALID_ID, &oa);
            const int occ_b = s->occluded(&t->view, tr, &w, hints[i], TT_INVALID_ID, &ob);
            ok = ok && occ_a == occ_b && oa == ob;
            if (!ok && bad++ < 5)
                fprintf(stderr, "%s ray %zu: prim %u/%u t %.9g/%.9g occluded %d/%d\n",
                        kd_traversal_names[tr], i, a.prim, b.prim, a.t, b.t, occ_a, occ_b);
        }
    return bad;
}

/* Every ISA against scalar on n rays of tree `a`. */
static void against_scalar(const tt_accel *a, const char *what, const tt_ray *rays,
                           const uint32_t *hints, size_t n)
{
    const size_t tris = tt_scene_triangle_count(a->scene);
    const tt_kd_kernels s = tt_kd_cpu_kernels(TT_ISA_SCALAR, tris);
    tt_isa isas[TT_ISA_AVX512 + 1];
    const size_t n_isas = kd_isas(isas);
    for (size_t i = 0; i < n_isas; i++) {
        tt_accel *on = kd_isa_view(a, isas[i]);
        const tt_kdtree *ti = tt_kdtree_of(on);
        size_t bad = differ(ti, &ti->fast, &s, rays, hints, n);
        kd_isa_view_free(on);
        CHECK_MSG(bad == 0, "%s, isa %s: %zu of %zu answers (rays x 4 traversals) differ from scalar",
                  what, tt_isa_name(isas[i]), bad, 4 * n);
    }
}

/* Primary rays of a view from the eye's node, and the shadow rays of their
 * hits from the node each primary ray ended in, as the renderer traces. */
static void view_rays(tt_context *ctx, const char *file, const char *view, uint32_t w, uint32_t h)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_accel *a = kd_build_with(ctx, scene, TT_KD_NLOGN, 4, TT_KD_BTR);
    CHECK_MSG(biggest_leaf(tt_kdtree_of(a)) >= 4, "%s: no leaf of 4 or more triangles", file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    const size_t n = (size_t)w * h;
    tt_ray *rays = malloc(2 * n * sizeof *rays);
    uint32_t *hints = malloc(2 * n * sizeof *hints);
    if (!rays || !hints) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    const uint32_t eye = tt_accel_locate(a, cam.eye);
    size_t m = n;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const size_t i = (size_t)y * w + x;
            tt_hit hit;
            tt_trace_args args = {eye, TT_INVALID_ID, NULL};
            REQUIRE_OK(ctx, tt_camera_ray(&cam, w, h, x, y, &rays[i]));
            hints[i] = eye;
            REQUIRE_OK(ctx, tt_intersect1_ex(a, &rays[i], &hit, &args));
            if (hit.prim != TT_INVALID_ID && tt_shadow_ray(scene, &cam, &rays[i], &hit, &rays[m]))
                hints[m++] = args.end_hint;
        }
    against_scalar(a, view, rays, hints, m);
    free(rays);
    free(hints);
    tt_accel_destroy(a);
    tt_scene_destroy(scene);
}

/* Random rays, and rays aimed at vertices (zero edge functions: the lanes
 * the scalar test recomputes in double precision), with and without a
 * start hint, on a scene of big leaves. */
static void scene_rays(tt_context *ctx, tt_scene *scene, const char *what, uint32_t n)
{
    tt_accel *a = kd_build_with(ctx, scene, TT_KD_NLOGN, 2, TT_KD_HTR);
    CHECK_MSG(biggest_leaf(tt_kdtree_of(a)) >= 8, "%s: no leaf of 8 or more triangles", what);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    tt_ray *rays = malloc(n * sizeof *rays);
    uint32_t *hints = malloc(n * sizeof *hints);
    if (!rays || !hints) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    const size_t tris = tt_scene_triangle_count(scene);
    uint32_t x = 17u;
    for (uint32_t i = 0; i < n; i++) {
        tt_ray *r = &rays[i];
        float tri[9];
        tt_scene_triangle(scene, kd_rand(&x) % tris, tri);
        for (int k = 0; k < 3; k++) {
            const float e = hi[k] - lo[k] > 0.0f ? hi[k] - lo[k] : 1.0f;
            r->org[k] = lo[k] - 0.5f * e + 2.0f * e * kd_unit(&x);
        }
        const float *target = tri + 3 * (kd_rand(&x) % 3);
        if (i % 3 == 2) /* inside the triangle instead of at a vertex */
            for (int k = 0; k < 3; k++) r->dir[k] = (tri[k] + tri[3 + k] + tri[6 + k]) / 3.0f;
        else
            for (int k = 0; k < 3; k++) r->dir[k] = target[k];
        for (int k = 0; k < 3; k++) r->dir[k] -= r->org[k];
        if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) r->dir[2] = 1.0f;
        r->tmin = 0.0f;
        r->tmax = i % 4 == 3 ? 0.5f : INFINITY;
        hints[i] = i % 2 ? tt_accel_locate(a, r->org) : TT_INVALID_ID;
    }
    against_scalar(a, what, rays, hints, n);
    free(rays);
    free(hints);
    tt_accel_destroy(a);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *s = kd_scene_coplanar(ctx, 80, 3);
    scene_rays(ctx, s, "coplanar", 3000);
    tt_scene_destroy(s);
    s = kd_scene_identical(ctx, 24);
    scene_rays(ctx, s, "identical", 2000);
    tt_scene_destroy(s);
    s = kd_scene_soup(ctx, 3000, 9);
    scene_rays(ctx, s, "soup", 3000);
    tt_scene_destroy(s);
    view_rays(ctx, "bun_zipper.ply", "bunny:main", 96, 96);
    view_rays(ctx, "sibenik.obj", "sibenik:main", 64, 64);
    view_rays(ctx, "conference.ply", "conference:main", 64, 48);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
