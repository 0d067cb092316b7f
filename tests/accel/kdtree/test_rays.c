/* Adversarial rays against bruteforce, every traversal at several d_min:
 * random rays (tt_test_compare_random), and rays built from the tree's own
 * split planes: origins exactly on split planes, rays lying in a split
 * plane (zero direction component), axis-parallel rays lying in one or two
 * split planes, rays from vertices (origins on up to three split planes)
 * and through points where two split planes cross; each with tmax infinite
 * and finite. Then arbitrary start hints (any node, whether or not it holds
 * the origin, and invalid ones) must not change any answer.
 *
 * Rays aimed at a vertex (which lies on up to three split planes) or at a
 * point where two split planes cross pass an edge or corner of the tree at
 * nearly (not exactly) equal computed crossing distances. Every traversal
 * must get those right too: the stack ones (htr, btr) widen crossings by a
 * rounding band, the stackless ones (sltr, seq) search the cells around
 * each entry point within that band. All four get the same rays, with
 * the fast kernels of every ISA this CPU runs. */
#include <math.h>
#include <stdlib.h>

#include "compare.h"
#include "kd_scenes.h"
#include "kd_testing.h"

#define MAX_PLANES 8192

static void random_dir(uint32_t *x, float d[3])
{
    do {
        for (int k = 0; k < 3; k++) d[k] = 2.0f * kd_unit(x) - 1.0f;
    } while (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f);
}

static float in_range(uint32_t *x, float lo, float hi) { return lo + (hi - lo) * kd_unit(x); }

/* Rays exactly on or through the split planes of tree t. */
static size_t plane_rays(const tt_scene *scene, const tt_kdtree *t, tt_ray *out, size_t n,
                         uint32_t seed, int near_corners)
{
    static kd_plane planes[MAX_PLANES];
    float lo[3], hi[3], e[3];
    tt_scene_bounds(scene, lo, hi);
    for (int k = 0; k < 3; k++) e[k] = hi[k] - lo[k] > 0.0f ? hi[k] - lo[k] : 1.0f;
    size_t np = kd_collect(t, 0, lo, hi, planes, 0, MAX_PLANES);
    size_t nt = tt_scene_triangle_count(scene);
    uint32_t x = seed;
    for (size_t i = 0; i < n; i++) {
        tt_ray *r = &out[i];
        const kd_plane *p = np ? &planes[kd_rand(&x) % np] : NULL;
        const kd_plane *q = np ? &planes[kd_rand(&x) % np] : NULL;
        int kind = (int)(i % 8);
        if (!near_corners && (kind == 5 || kind == 7)) kind = kind == 5 ? 6 : 0;
        if (!p && kind < 5) kind = 6;
        if (kind == 3 || kind == 7) /* need two planes on different axes */
            for (int tries = 0; tries < 50 && q->axis == p->axis; tries++) q = &planes[kd_rand(&x) % np];
        if ((kind == 3 || kind == 7) && q->axis == p->axis) kind = 0;
        float tri[9];
        tt_scene_triangle(scene, nt ? kd_rand(&x) % nt : 0, tri);
        const float *vertex = tri + 3 * (kd_rand(&x) % 3);
        for (int k = 0; k < 3; k++) r->org[k] = p ? in_range(&x, p->lo[k], p->hi[k]) : 0.0f;
        random_dir(&x, r->dir);
        switch (kind) {
        case 0: /* origin on the plane, any direction */
            r->org[p->axis] = p->pos;
            break;
        case 1: /* lying in the plane */
            r->org[p->axis] = p->pos;
            r->dir[p->axis] = 0.0f;
            if (r->dir[(p->axis + 1) % 3] == 0.0f) r->dir[(p->axis + 1) % 3] = 1.0f;
            break;
        case 2: { /* axis-parallel in the plane */
            int along = (p->axis + 1 + (int)(kd_rand(&x) % 2)) % 3;
            r->org[p->axis] = p->pos;
            r->dir[0] = r->dir[1] = r->dir[2] = 0.0f;
            r->dir[along] = (kd_rand(&x) & 1) ? 1.0f : -1.0f;
            break;
        }
        case 3: { /* axis-parallel in two planes, from outside the box */
            int along = 3 - p->axis - q->axis;
            r->org[p->axis] = p->pos;
            r->org[q->axis] = q->pos;
            r->dir[0] = r->dir[1] = r->dir[2] = 0.0f;
            int up = kd_rand(&x) & 1;
            r->dir[along] = up ? 1.0f : -1.0f;
            if (kd_rand(&x) & 1) r->org[along] = up ? lo[along] - 0.25f * e[along] : hi[along] + 0.25f * e[along];
            break;
        }
        case 4: { /* in the plane, from outside the scene box */
            int other = (p->axis + 1 + (int)(kd_rand(&x) % 2)) % 3;
            r->org[p->axis] = p->pos;
            r->org[other] = lo[other] - 0.3f * e[other];
            for (int k = 0; k < 3; k++) r->dir[k] = 0.5f * (lo[k] + hi[k]) - r->org[k];
            r->dir[p->axis] = 0.0f;
            if (r->dir[other] == 0.0f) r->dir[other] = 1.0f;
            break;
        }
        case 5: /* through a vertex */
            for (int k = 0; k < 3; k++) {
                r->org[k] = in_range(&x, lo[k] - e[k], hi[k] + e[k]);
                r->dir[k] = vertex[k] - r->org[k];
            }
            break;
        case 6: /* from a vertex */
            for (int k = 0; k < 3; k++) r->org[k] = vertex[k];
            break;
        case 7: { /* through a point where two split planes cross */
            float target[3];
            for (int k = 0; k < 3; k++) target[k] = in_range(&x, p->lo[k], p->hi[k]);
            target[p->axis] = p->pos;
            target[q->axis] = q->pos;
            for (int k = 0; k < 3; k++) {
                r->org[k] = in_range(&x, lo[k] - e[k], hi[k] + e[k]);
                r->dir[k] = target[k] - r->org[k];
            }
            break;
        }
        }
        if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) r->dir[0] = 1.0f;
        r->tmin = 0.0f;
        r->tmax = (i / 8) % 2 ? in_range(&x, 0.0f, 1.5f) : INFINITY;
    }
    return n;
}

/* Answers must not depend on the start hint, valid or not. */
static size_t hinted(const tt_accel *test, const tt_accel *ref, const tt_ray *rays, size_t n,
                     uint32_t aug_count, uint32_t seed)
{
    size_t bad = 0;
    uint32_t x = seed;
    for (size_t i = 0; i < n; i++) {
        /* Mostly the node holding the origin (a deep start: restarts climb
         * through many boxes), else any node, or none. */
        uint32_t hint = i % 5 == 4   ? TT_INVALID_ID
                        : i % 5 == 3 ? kd_rand(&x) % (aug_count + 3)
                                     : tt_accel_locate(test, rays[i].org);
        tt_hit h_ref, h;
        int o_ref, o;
        tt_ray_stats st = {0};
        tt_trace_args a = {hint, 0, NULL}, b = {hint, 0, &st};
        tt_intersect1(ref, &rays[i], &h_ref);
        tt_occluded1(ref, &rays[i], &o_ref);
        tt_intersect1_ex(test, &rays[i], &h, &a);
        int ok = tt_test_hits_agree(&h_ref, &h);
        tt_intersect1_ex(test, &rays[i], &h, &b);
        ok = ok && tt_test_hits_agree(&h_ref, &h);
        tt_occluded1_ex(test, &rays[i], &o, &a);
        ok = ok && o == o_ref;
        tt_occluded1_ex(test, &rays[i], &o, &b);
        ok = ok && o == o_ref;
        if (!ok && bad++ < 5)
            fprintf(stderr, "%s: ray %zu with hint %u disagrees\n", tt_accel_name(test), i, hint);
    }
    return bad;
}

static void rays_on(tt_context *ctx, tt_scene *scene, const char *what, uint32_t n_random,
                    uint32_t n_plane)
{
    const int dmins[] = {1, 3, -1};
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));
    tt_ray *rays = malloc(n_plane * sizeof *rays);
    if (!rays) exit(1);
    /* The exact tree, and the binned builder's (other planes, and leaves
     * that may hold triangles only their boxes reach). */
    for (size_t dd = 0; dd < 2 * sizeof dmins / sizeof dmins[0]; dd++) {
        const size_t d = dd % (sizeof dmins / sizeof dmins[0]);
        const int binned = dd >= sizeof dmins / sizeof dmins[0];
        const char *bn = binned ? "binned" : "nlogn";
        tt_accel *kd = kd_build_with(ctx, scene, binned ? TT_KD_BINNED : TT_KD_NLOGN, dmins[d], TT_KD_HTR);
        CHECK_OK(ctx, tt_accel_check(kd));
        const tt_kdtree *t = tt_kdtree_of(kd);
        tt_isa isas[TT_ISA_AVX512 + 1];
        const size_t n_isas = kd_isas(isas);
        for (size_t i = 0; i < n_isas; i++) {
            tt_accel *on = kd_isa_view(kd, isas[i]), views[4];
            const char *isa = tt_isa_name(isas[i]);
            kd_traversal_views(on, views);
            for (int tr = 0; tr < 4; tr++) {
                size_t n = plane_rays(scene, t, rays, n_plane, 7u + (uint32_t)d, 1);
                size_t bad =
                    tt_test_compare_random(scene, &views[tr], ref, n_random, 11u + (uint32_t)d);
                CHECK_MSG(bad == 0, "%s, %s, %s, %s, dmin %d: %zu random rays disagree", what, bn,
                          kd_traversal_names[tr], isa, dmins[d], bad);
                bad = tt_test_compare_tiny_dirs(scene, &views[tr], ref, 100, 13u + (uint32_t)d);
                CHECK_MSG(bad == 0, "%s, %s, %s, %s, dmin %d: %zu tiny-direction rays disagree", what,
                          bn, kd_traversal_names[tr], isa, dmins[d], bad);
                bad = tt_test_compare_rays(&views[tr], ref, rays, n);
                CHECK_MSG(bad == 0, "%s, %s, %s, %s, dmin %d: %zu split-plane rays disagree", what, bn,
                          kd_traversal_names[tr], isa, dmins[d], bad);
                bad = hinted(&views[tr], ref, rays, n, t->aug_count, 5u);
                CHECK_MSG(bad == 0, "%s, %s, %s, %s, dmin %d: %zu hinted rays disagree", what, bn,
                          kd_traversal_names[tr], isa, dmins[d], bad);
            }
            kd_isa_view_free(on);
        }
        tt_accel_destroy(kd);
    }
    free(rays);
    tt_accel_destroy(ref);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *s = kd_scene_blocks(ctx);
    rays_on(ctx, s, "blocks", 1500, 4000);
    tt_scene_destroy(s);
    s = kd_scene_soup(ctx, 400, 3);
    rays_on(ctx, s, "soup", 1500, 3000);
    tt_scene_destroy(s);
    s = kd_scene_coplanar(ctx, 60, 5);
    rays_on(ctx, s, "coplanar", 1000, 2000);
    tt_scene_destroy(s);
    s = tt_test_load_scene(ctx, "cornell_box.obj");
    rays_on(ctx, s, "cornell", 1500, 4000);
    tt_scene_destroy(s);
    s = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    rays_on(ctx, s, "bunny_res4", 1500, 3000);
    tt_scene_destroy(s);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
