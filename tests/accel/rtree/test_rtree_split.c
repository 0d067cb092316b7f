/* Early split clipping (tt_rtree_options.split_budget): the default build
 * over split references answers every ray like bruteforce (single rays,
 * random rays, and packets against single rays, bit for bit), passes the
 * check, keeps its references through save and load, and is rebuilt, not
 * updated in place, when its scene changes. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "compare.h"
#include "reference.h"
#include "rtree_test.h"

static tt_build_options split_options(float budget)
{
    /* the default engine: SAH loader, compact layout, M resolved */
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, TT_RTREE_AUTO, 2, 0);
    o.rtree.build = TT_RTREE_BUILD_SAH;
    o.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
    o.rtree.split_budget = budget;
    return o;
}

static double stat_of(const tt_accel *a, const char *key)
{
    return tt_test_stat(a, key);
}

/* Packets forced on against packets off over the view's primary rays. */
static size_t packets_agree(const tt_accel *a, const tt_camera *cam, uint32_t size)
{
    const size_t n = (size_t)size * size;
    tt_ray *rays = malloc(n * sizeof *rays);
    tt_hit *h1 = malloc(n * sizeof *h1), *h2 = malloc(n * sizeof *h2);
    uint8_t *o1 = malloc(n), *o2 = malloc(n);
    size_t bad = 0;
    tt_camera_rays(cam, size, size, rays);
    tt_batch_options on, off;
    tt_batch_options_default(&on);
    tt_batch_options_default(&off);
    on.packets = TT_PACKETS_ON;
    on.image_width = size;
    off.packets = TT_PACKETS_OFF;
    CHECK(tt_intersect(a, rays, n, h1, NULL, &on) == TT_OK);
    CHECK(tt_intersect(a, rays, n, h2, NULL, &off) == TT_OK);
    CHECK(tt_occluded(a, rays, n, o1, NULL, &on) == TT_OK);
    CHECK(tt_occluded(a, rays, n, o2, NULL, &off) == TT_OK);
    for (size_t i = 0; i < n; i++)
        bad += !tt_test_hits_agree(&h1[i], &h2[i]) || h1[i].prim != h2[i].prim || o1[i] != o2[i];
    free(rays), free(h1), free(h2), free(o1), free(o2);
    return bad;
}

static void view(tt_context *ctx, const char *file, const char *name, uint32_t size)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, name, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    tt_test_reference *ref = tt_test_reference_view(scene, bf, &cam, size, size);
    static const float budgets[] = {0.25f, 4.0f};
    for (int b = 0; b < 2; b++) {
        tt_build_options o = split_options(budgets[b]);
        tt_accel *a = rt_build_checked(ctx, scene, &o);
        if (!a) continue;
        const double refs = stat_of(a, "references"), tris = stat_of(a, "triangles");
        CHECK_MSG(refs <= tris * (1.0 + budgets[b]) + 0.5, "%s: %g references for %g triangles",
                  name, refs, tris);
        size_t bad = tt_test_compare_view_reference(a, ref);
        CHECK_MSG(bad == 0, "%s, split budget %g: %zu rays disagree", name, (double)budgets[b],
                  bad);
        bad = tt_test_compare_random(scene, a, bf, 500, 17u + (uint32_t)b);
        CHECK_MSG(bad == 0, "%s, split budget %g: %zu random rays disagree", name,
                  (double)budgets[b], bad);
        bad = packets_agree(a, &cam, 32);
        CHECK_MSG(bad == 0, "%s, split budget %g: %zu packet rays differ from single rays", name,
                  (double)budgets[b], bad);
        CHECK_MSG(refs == tris || !tt_accel_updates_in_place(a),
                  "%s: a tree with split references claims in-place updates", name);
        tt_accel_destroy(a);
    }
    tt_test_reference_destroy(ref);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

/* Save and load keep the references (and the check's rules for them); an
 * edit is answered by a rebuild. */
static void save_load_update(tt_context *ctx)
{
    tt_scene *scene = tt_test_load_scene(ctx, "sibenik.obj");
    tt_build_options o = split_options(0.5f);
    tt_accel *a = rt_build_checked(ctx, scene, &o);
    if (!a) {
        tt_scene_destroy(scene);
        return;
    }
    CHECK(stat_of(a, "references") > stat_of(a, "triangles"));
    CHECK(!tt_accel_updates_in_place(a));
    char path[256];
    snprintf(path, sizeof path, "/tmp/tt_rtree_split_%d.tta", (int)getpid());
    CHECK(tt_accel_save(a, path, "sibenik") == TT_OK);
    tt_accel *l = NULL;
    tt_status st = tt_accel_load(ctx, scene, path, TT_ISA_AUTO, &l);
    CHECK_MSG(st == TT_OK, "load: %s", tt_context_last_error(ctx));
    if (st == TT_OK) {
        CHECK_MSG(tt_accel_check(l) == TT_OK, "check of the loaded tree: %s",
                  tt_context_last_error(ctx));
        tt_build_options lo;
        CHECK(tt_accel_options(l, &lo) == TT_OK && lo.rtree.split_budget == 0.5f);
        CHECK(tt_test_compare_random(scene, l, a, 2000, 5) == 0);
        tt_accel_destroy(l);
    }
    remove(path);
    /* move a triangle: the update rebuilds, and the new tree is right */
    float v[9];
    tt_scene_triangle(scene, 7, v);
    for (int k = 0; k < 9; k += 3) v[k + 1] += 0.5f;
    const uint32_t id = 7;
    CHECK(tt_scene_set_triangles(scene, &id, v, 1) == TT_OK);
    CHECK_MSG(tt_accel_update(a) == TT_OK, "update: %s", tt_context_last_error(ctx));
    CHECK_MSG(tt_accel_check(a) == TT_OK, "check after update: %s", tt_context_last_error(ctx));
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    CHECK(tt_test_compare_random(scene, a, bf, 500, 9) == 0);
    tt_accel_destroy(bf);
    tt_accel_destroy(a);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    view(ctx, "cornell_box.obj", "cornell:main", 32);
    view(ctx, "bun_zipper.ply", "bunny:main", 24);
    view(ctx, "sibenik.obj", "sibenik:main", 24);
    view(ctx, "conference.ply", "conference:main", 16);
    save_load_update(ctx);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
