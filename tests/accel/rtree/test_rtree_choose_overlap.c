/* The overlap criterion's kernels (rtree_choose_overlap.h): every ISA's
 * kernel gives the baseline's keys to the bit on random nodes of 1 .. M + 1
 * entries (overlapping, disjoint, touching and flat boxes), and an insertion
 * build with each kernel gives the very same pointer tree. */
#include <stdlib.h>
#include <string.h>

#include "accel/rtree/build/rtree_build.h"
#include "accel/rtree/build/rtree_choose_overlap.h"
#include "accel/rtree/rtree_box.h"
#include "io/scene.h"
#include "rtree_test.h"

static uint32_t rng = 12345u;
static float rnd(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) * (1.0f / 16777216.0f);
}

/* a coordinate on a coarse grid half the time, so boxes touch and tie */
static float coord(void)
{
    float x = rnd() * 4.0f;
    return rnd() < 0.5f ? (float)(int)x : x;
}

static const struct {
    tt_isa isa;
    rt_overlap_keys_fn fn;
} kernels[] = {
    {TT_ISA_SCALAR, rt_overlap_keys_sse2},
#if defined(TT_HAVE_X86_KERNELS)
    {TT_ISA_AVX2, rt_overlap_keys_avx2},
    {TT_ISA_AVX512, rt_overlap_keys_avx512},
#endif
};
#define KERNELS (sizeof kernels / sizeof kernels[0])

static void test_keys(void)
{
    enum { CAP = (TT_RT_MAX_M + 1 + 3) & ~3 };
    float s[6 * CAP];
    for (int round = 0; round < 4000; round++) {
        const int cnt = 1 + round % (TT_RT_MAX_M + 1);
        for (int i = 0; i < CAP; i++) {
            float lo[3], hi[3];
            for (int k = 0; k < 3; k++) {
                float a = coord(), w = rnd() < 0.2f ? 0.0f : rnd() * 2.0f;
                lo[k] = a;
                hi[k] = a + w;
            }
            for (int k = 0; k < 3; k++) {
                s[k * CAP + i] = lo[k];
                s[(k + 3) * CAP + i] = hi[k];
            }
        }
        float e[6];
        for (int k = 0; k < 3; k++) {
            e[k] = coord();
            e[k + 3] = e[k] + (rnd() < 0.2f ? 0.0f : rnd());
        }
        rt_overlap_keys ref, got;
        kernels[0].fn(s, CAP, cnt, e, &ref);
        for (size_t q = 1; q < KERNELS; q++) {
            if (!tt_test_isa_runs(kernels[q].isa)) continue;
            kernels[q].fn(s, CAP, cnt, e, &got);
            int same = 1;
            for (int i = 0; i < cnt; i++)
                same &= !memcmp(&ref.dov[i], &got.dov[i], sizeof(float)) &&
                        !memcmp(&ref.dvol[i], &got.dvol[i], sizeof(float)) &&
                        !memcmp(&ref.vol[i], &got.vol[i], sizeof(float)) &&
                        !memcmp(&ref.darea[i], &got.darea[i], sizeof(float)) &&
                        !memcmp(&ref.area[i], &got.area[i], sizeof(float));
            CHECK_MSG(same, "%s kernel: keys differ from the baseline (round %d, %d entries)",
                      tt_isa_name(kernels[q].isa), round, cnt);
        }
    }
}

/* Node n of a and b holds the same entries (live ones only: the pool's
 * unused child slots are never written). */
static int same_node(const rt_builder *a, const rt_builder *b, uint32_t n)
{
    const rt_node_hdr *x = &a->hdr[n], *y = &b->hdr[n];
    if (x->parent != y->parent || x->slot != y->slot || x->count != y->count ||
        x->level != y->level)
        return 0;
    for (int i = 0; i < x->count; i++) {
        float ea[6], eb[6];
        rt_soa_get(rt_node_box(a, n), a->cap, i, ea);
        rt_soa_get(rt_node_box(b, n), b->cap, i, eb);
        if (memcmp(ea, eb, sizeof ea) || rt_node_child(a, n)[i] != rt_node_child(b, n)[i])
            return 0;
    }
    return 1;
}

/* The same pool, node by node, from a build with each kernel. */
static void test_same_tree(tt_context *ctx, const tt_scene *scene)
{
    const uint32_t T = (uint32_t)scene->triangle_count;
    float *box = malloc((size_t)T * 6 * sizeof *box);
    REQUIRE_OK(ctx, box ? TT_OK : TT_ERR_OUT_OF_MEMORY);
    for (uint32_t i = 0; i < T; i++)
        for (int k = 0; k < 3; k++) {
            const float *v = scene->tri + 9 * (size_t)i;
            box[6 * i + k] = fminf(fminf(v[k], v[3 + k]), v[6 + k]);
            box[6 * i + k + 3] = fmaxf(fmaxf(v[k], v[3 + k]), v[6 + k]);
        }
    const tt_rtree_strategy strategies[] = {TT_RTREE_MIN_OVERLAP, TT_RTREE_RSTAR_SURFACE};
    for (size_t si = 0; si < 2; si++) {
        tt_build_options o = rt_options((int)strategies[si], TT_RTREE_AUTO, 2, 16);
        rt_builder ref;
        REQUIRE_OK(ctx, rt_builder_init(&ref, ctx, &o.rtree, box, T));
        ref.overlap_keys = kernels[0].fn;
        for (uint32_t i = 0; i < T; i++) REQUIRE_OK(ctx, rt_builder_insert_triangle(&ref, i));
        for (size_t q = 1; q < KERNELS; q++) {
            if (!tt_test_isa_runs(kernels[q].isa)) continue;
            rt_builder b;
            REQUIRE_OK(ctx, rt_builder_init(&b, ctx, &o.rtree, box, T));
            b.overlap_keys = kernels[q].fn;
            for (uint32_t i = 0; i < T; i++) REQUIRE_OK(ctx, rt_builder_insert_triangle(&b, i));
            int same = b.node_count == ref.node_count && b.root == ref.root;
            for (uint32_t n = 0; same && n < b.node_count; n++) same = same_node(&ref, &b, n);
            CHECK_MSG(same, "%s kernel, %s: not the baseline kernel's tree",
                      tt_isa_name(kernels[q].isa), rt_strategy_names[strategies[si]]);
            rt_builder_free(&b);
        }
        rt_builder_free(&ref);
    }
    free(box);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    test_keys();
    tt_scene *bunny4 = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
    test_same_tree(ctx, bunny4);
    /* and the public build with this CPU's kernel passes tt_accel_check */
    tt_build_options o = rt_options(TT_RTREE_MIN_OVERLAP, TT_RTREE_AUTO, 2, 16);
    tt_accel_destroy(rt_build_checked(ctx, bunny4, &o));
    tt_scene_destroy(bunny4);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
