/* The compact layout ray by ray against bruteforce: every traversal (auto,
 * stack, ordered = the near-to-far stack traversal; stackless) x every ISA
 * this CPU runs x M in {4, 5, 6, 8, 16} (5 and 6 exercise the padded SoA
 * rows), on the shared views (the big scenes subsampled: a small image of
 * the view) and on random rays, plus other insertion strategies and
 * reinsert off. Closest hit and occlusion, fast and counting variants
 * (compare.h, reference.h). */
#include "compare.h"
#include "core/isa.h"
#include "reference.h"
#include "rtree_test.h"

static const rt_mm compact_mm[] = {{2, 4}, {2, 5}, {3, 6}, {3, 8}, {4, 16}};
#define COMPACT_MM_COUNT ((int)(sizeof compact_mm / sizeof compact_mm[0]))

static tt_build_options compact_options(int traversal, int m, int M, tt_isa isa)
{
    tt_build_options o = rt_options(TT_RTREE_RSTAR_SURFACE, traversal, m, M);
    o.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
    o.isa = isa;
    return o;
}

static const char *describe(const tt_build_options *o)
{
    static char buf[256];
    snprintf(buf, sizeof buf, "compact %s isa=%s", rt_describe(o), tt_isa_name(o->isa));
    return buf;
}

/* One configuration against the kept reference (and random rays when
 * scene and bf are given). */
static void one(tt_context *ctx, const tt_scene *scene, const tt_accel *bf,
                const tt_test_reference *ref, const char *view, const tt_build_options *o)
{
    tt_accel *a = rt_build_checked(ctx, scene, o);
    if (!a) return;
    CHECK_MSG(tt_accel_isa(a) == o->isa, "%s: runs on %s", describe(o),
              tt_isa_name(tt_accel_isa(a)));
    size_t bad = tt_test_compare_view_reference(a, ref);
    CHECK_MSG(bad == 0, "%s, %s: %zu rays disagree", view, describe(o), bad);
    if (bf) {
        bad = tt_test_compare_random(scene, a, bf, 2000, 77u + (uint32_t)o->rtree.M);
        CHECK_MSG(bad == 0, "%s, %s: %zu random rays disagree", view, describe(o), bad);
        bad = tt_test_compare_tiny_dirs(scene, a, bf, 300, 5u + (uint32_t)o->rtree.M);
        CHECK_MSG(bad == 0, "%s, %s: %zu tiny-direction rays disagree", view, describe(o), bad);
    }
    tt_accel_destroy(a);
}

static void view(tt_context *ctx, const char *file, const char *view_name, uint32_t size,
                 int random)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view_name, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    tt_test_reference *ref = tt_test_reference_view(scene, bf, &cam, size, size);
    for (int k = 0; k < COMPACT_MM_COUNT; k++) {
        const int m = compact_mm[k].m, M = compact_mm[k].M;
        /* the stack traversal (and its aliases) on every ISA */
        for (int isa = TT_ISA_FIRST; isa <= TT_ISA_LAST; isa++) {
            if (!tt_test_isa_runs((tt_isa)isa)) continue;
            tt_build_options o = compact_options(TT_RTREE_STACK, m, M, (tt_isa)isa);
            one(ctx, scene, random ? bf : NULL, ref, view_name, &o);
        }
        tt_build_options o = compact_options(TT_RTREE_AUTO, m, M, tt_isa_best());
        one(ctx, scene, NULL, ref, view_name, &o);
        o = compact_options(TT_RTREE_ORDERED, m, M, TT_ISA_SCALAR);
        one(ctx, scene, NULL, ref, view_name, &o);
        o = compact_options(TT_RTREE_STACKLESS, m, M, TT_ISA_SCALAR);
        one(ctx, scene, random ? bf : NULL, ref, view_name, &o);
    }
    /* other trees: each insertion strategy, reinsert off, quadratic split */
    for (int s = TT_RTREE_MIN_VOLUME; s <= TT_RTREE_RSTAR; s++) {
        tt_build_options o = compact_options(s % 2 ? TT_RTREE_STACK : TT_RTREE_STACKLESS, 3, 8,
                                             tt_isa_best());
        o.rtree.strategy = (tt_rtree_strategy)s;
        o.rtree.reinsert = s % 2;
        o.rtree.split = s == TT_RTREE_MIN_OVERLAP ? TT_RTREE_SPLIT_QUADRATIC : TT_RTREE_SPLIT_RSTAR;
        one(ctx, scene, NULL, ref, view_name, &o);
    }
    tt_test_reference_destroy(ref);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    view(ctx, "bun_zipper_res4.ply", "bunny_res4:main", 64, 1);
    view(ctx, "cornell_box.obj", "cornell:main", 48, 1);
    view(ctx, "bun_zipper.ply", "bunny:main", 48, 0);
    view(ctx, "sibenik.obj", "sibenik:main", 32, 0);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
