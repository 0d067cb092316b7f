/* The kd-tree's options and interface: invalid options are refused with a
 * message naming the option; the statistics describe the built tree;
 * locate returns the deepest augmented node holding the point; end hints
 * name a box around the hit; the shadow-caster hint keeps occlusion exact. */
#include <math.h>
#include <string.h>

#include "compare.h"
#include "kd_scenes.h"
#include "kd_testing.h"

static tt_context *ctx;

static void refused(const tt_scene *scene, const tt_build_options *o, const char *name)
{
    tt_accel *a = NULL;
    tt_status st = tt_accel_build(ctx, scene, o, &a);
    CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT && a == NULL, "%s accepted", name);
    CHECK_MSG(strstr(tt_context_last_error(ctx), name) != NULL, "message '%s' does not name %s",
              tt_context_last_error(ctx), name);
}

static void validation(const tt_scene *scene)
{
    tt_build_options d, o;
    tt_build_options_default(&d);
    d.accel = "kdtree";
    o = d, o.kdtree.builder = (tt_kd_builder)7, refused(scene, &o, "builder");
    o = d, o.kdtree.cost_traversal = 0.0f, refused(scene, &o, "cost_traversal");
    o = d, o.kdtree.cost_traversal = NAN, refused(scene, &o, "cost_traversal");
    o = d, o.kdtree.cost_intersect = -1.0f, refused(scene, &o, "cost_intersect");
    o = d, o.kdtree.empty_bonus = 1.0f, refused(scene, &o, "empty_bonus");
    o = d, o.kdtree.empty_bonus = -0.1f, refused(scene, &o, "empty_bonus");
    o = d, o.kdtree.max_depth = -1, refused(scene, &o, "max_depth");
    o = d, o.kdtree.max_depth = TT_KD_MAX_DEPTH + 1, refused(scene, &o, "max_depth");
    o = d, o.kdtree.traversal = (tt_kd_traversal)4, refused(scene, &o, "traversal");
    o = d, o.kdtree.shadow_caster_hint = 2, refused(scene, &o, "shadow_caster_hint");
    o = d, o.kdtree.shadow_caster_hint = 1, o.kdtree.traversal = TT_KD_HTR,
    refused(scene, &o, "shadow_caster_hint");
    /* An explicit depth limit is obeyed. */
    o = d, o.kdtree.max_depth = 5;
    tt_accel *a = NULL;
    CHECK_OK(ctx, tt_accel_build(ctx, scene, &o, &a));
    if (a) {
        CHECK(tt_kdtree_of(a)->depth_max <= 5 && tt_kdtree_of(a)->max_depth == 5);
        CHECK_OK(ctx, tt_accel_check(a));
        tt_accel_destroy(a);
    }
}

typedef struct stats {
    double n_b, m_kd, nodes, interior, leaves, empty, depth_max, depth_mean, refs_per_tri, sah;
    int seen;
} stats;

static void collect(void *user, const char *key, double v)
{
    stats *s = user;
    s->seen++;
    if (!strcmp(key, "N_B")) s->n_b = v;
    else if (!strcmp(key, "M_KD")) s->m_kd = v;
    else if (!strcmp(key, "nodes")) s->nodes = v;
    else if (!strcmp(key, "interior")) s->interior = v;
    else if (!strcmp(key, "leaves")) s->leaves = v;
    else if (!strcmp(key, "empty_leaves")) s->empty = v;
    else if (!strcmp(key, "depth_max")) s->depth_max = v;
    else if (!strcmp(key, "depth_mean")) s->depth_mean = v;
    else if (!strcmp(key, "refs_per_triangle")) s->refs_per_tri = v;
    else if (!strcmp(key, "sah_cost")) s->sah = v;
    else s->seen--;
}

static void statistics(const tt_scene *scene)
{
    const int dmins[] = {1, 2, 4, -1};
    double prev_nb = 1e30;
    for (int i = 0; i < 4; i++) {
        tt_accel *a = kd_build_with(ctx, scene, TT_KD_NLOGN, dmins[i], TT_KD_HTR);
        const tt_kdtree *t = tt_kdtree_of(a);
        stats s = {0};
        CHECK_OK(ctx, tt_accel_statistics(a, collect, &s));
        CHECK(s.seen == 10);
        CHECK(s.n_b == t->aug_count);
        /* M_KD is the papers' measure, the tree; the accel's memory adds
         * the engine's leaf blocks (kd_blocks.h) where its kernels use them. */
        CHECK(s.m_kd == (double)tt_kdtree_memory(t) && s.m_kd > 0);
        CHECK(tt_accel_memory_bytes(a) == tt_kdtree_memory(t) + tt_kdtree_blocks_memory(t));
        CHECK(s.nodes == s.interior + s.leaves && s.leaves == s.interior + 1);
        CHECK(s.empty < s.leaves && s.depth_mean <= s.depth_max && s.depth_max <= t->max_depth);
        CHECK(s.refs_per_tri >= 1.0 && s.sah > 0.0);
        /* d_min 1: every interior node has a box; none: only the root. */
        if (dmins[i] == 1) CHECK(s.n_b == s.interior);
        if (dmins[i] < 0) CHECK(s.n_b == 1);
        CHECK(s.n_b < prev_nb);
        prev_nb = s.n_b;
        tt_accel_destroy(a);
    }
}

/* Depth of an augmented node: the length of its parent chain. */
static int aug_depth(const tt_kdtree *t, uint32_t a)
{
    int d = 0;
    while (t->aug[a].parent != TT_KD_NO_PARENT) a = t->aug[a].parent, d++;
    return d;
}

static int box_holds(const tt_kd_aug *b, const float *p, float slack)
{
    for (int k = 0; k < 3; k++)
        if (!(p[k] >= b->lo[k] - slack && p[k] <= b->hi[k] + slack)) return 0;
    return 1;
}

static void locate(const tt_scene *scene)
{
    tt_accel *a = kd_build_with(ctx, scene, TT_KD_NLOGN, 2, TT_KD_BTR);
    const tt_kdtree *t = tt_kdtree_of(a);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    uint32_t x = 99;
    for (int i = 0; i < 300; i++) {
        float p[3];
        for (int k = 0; k < 3; k++) p[k] = lo[k] + (hi[k] - lo[k]) * kd_unit(&x);
        uint32_t got = tt_accel_locate(a, p);
        int deepest = -1;
        for (uint32_t b = 0; b < t->aug_count; b++)
            if (box_holds(&t->aug[b], p, 0.0f) && aug_depth(t, b) > deepest) deepest = aug_depth(t, b);
        CHECK(got < t->aug_count && box_holds(&t->aug[got], p, 0.0f) && aug_depth(t, got) == deepest);
    }
    float outside[3] = {hi[0] + 1.0f, lo[1], lo[2]};
    CHECK(tt_accel_locate(a, outside) == TT_INVALID_ID);
    tt_accel_destroy(a);
}

/* End hints: btr, sltr and seq name an augmented node whose box holds the
 * hit point (up to rounding); htr uses no boxes and names none. */
static void end_hints(const tt_scene *scene, const char *view)
{
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_accel *a = kd_build_with(ctx, scene, TT_KD_NLOGN, 2, TT_KD_HTR);
    const tt_kdtree *t = tt_kdtree_of(a);
    tt_accel views[4];
    kd_traversal_views(a, views);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    float slack = 1e-4f * (hi[0] - lo[0] + hi[1] - lo[1] + hi[2] - lo[2]);
    for (int tr = 0; tr < 4; tr++) {
        uint32_t eye = tt_accel_locate(&views[tr], cam.eye);
        int good = 1, hits = 0;
        for (uint32_t y = 0; y < 24; y++)
            for (uint32_t xx = 0; xx < 24; xx++) {
                tt_ray r;
                tt_hit h;
                tt_camera_ray(&cam, 24, 24, xx, y, &r);
                tt_trace_args args = {eye, 0, NULL};
                tt_intersect1_ex(&views[tr], &r, &h, &args);
                if (h.prim == TT_INVALID_ID) continue;
                hits++;
                float p[3];
                for (int k = 0; k < 3; k++) p[k] = r.org[k] + h.t * r.dir[k];
                if (tr == TT_KD_HTR) good &= args.end_hint == TT_INVALID_ID;
                else good &= args.end_hint < t->aug_count && box_holds(&t->aug[args.end_hint], p, slack);
            }
        CHECK_MSG(good && hits > 0, "%s: end hints of %s", view, kd_traversal_names[tr]);
    }
    tt_accel_destroy(a);
}

/* The shadow-caster hint: each shadow ray first searches the box of the
 * previous one's caster; occlusion stays exactly bruteforce's. */
static void caster_hint(const tt_scene *scene, const char *view, uint32_t w, uint32_t h)
{
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &o, &ref));
    o.accel = "kdtree";
    o.kdtree.shadow_caster_hint = 1;
    o.kdtree.dmin = 2;
    for (int tr = TT_KD_BTR; tr <= TT_KD_SEQ; tr++) {
        o.kdtree.traversal = (tt_kd_traversal)tr;
        tt_accel *a = NULL;
        REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &o, &a));
        uint32_t eye = tt_accel_locate(a, cam.eye), caster = TT_INVALID_ID;
        size_t bad = 0, occluded = 0, cached = 0;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                tt_ray r, sr;
                tt_hit hit;
                tt_camera_ray(&cam, w, h, x, y, &r);
                tt_trace_args pa = {eye, 0, NULL};
                tt_intersect1_ex(a, &r, &hit, &pa);
                if (!tt_shadow_ray(scene, &cam, &r, &hit, &sr)) continue;
                int o_ref, o_kd;
                tt_occluded1(ref, &sr, &o_ref);
                tt_trace_args sa = {pa.end_hint, caster, NULL};
                cached += caster != TT_INVALID_ID;
                tt_occluded1_ex(a, &sr, &o_kd, &sa);
                bad += o_ref != o_kd;
                occluded += o_kd;
                caster = o_kd ? sa.end_hint : TT_INVALID_ID;
            }
        CHECK_MSG(bad == 0, "%s, %s with the caster hint: %zu shadow rays disagree", view,
                  kd_traversal_names[tr], bad);
        CHECK_MSG(occluded > 0 && cached > 0, "%s: the caster hint was never exercised", view);
        tt_accel_destroy(a);
    }
    tt_accel_destroy(ref);
}

int main(void)
{
    ctx = tt_test_context();
    tt_scene *res4 = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    validation(res4);
    statistics(res4);
    locate(res4);
    end_hints(res4, "bunny_res4:main");
    caster_hint(res4, "bunny_res4:main", 48, 48);
    tt_scene *cornell = tt_test_load_scene(ctx, "cornell_box.obj");
    end_hints(cornell, "cornell:main");
    caster_hint(cornell, "cornell:main", 48, 48);
    tt_scene *blocks = kd_scene_blocks(ctx);
    statistics(blocks);
    locate(blocks);
    tt_scene_destroy(res4);
    tt_scene_destroy(cornell);
    tt_scene_destroy(blocks);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
