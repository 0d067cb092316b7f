/* Allocation failures: building (every builder) and checking a kd-tree with
 * an allocator that fails the n-th allocation, for every n until the build
 * succeeds, returns TT_ERR_OUT_OF_MEMORY and leaves no block behind. */
#include <stdlib.h>
#include <string.h>

#include "kd_scenes.h"
#include "kd_testing.h"

typedef struct failing {
    long live, count, fail_at; /* fail_at < 0: never */
} failing;

static void *f_alloc(void *user, size_t size)
{
    failing *f = user;
    if (f->fail_at >= 0 && f->count >= f->fail_at) return NULL;
    void *p = malloc(size ? size : 1);
    if (p) f->count++, f->live++;
    return p;
}

static void *f_realloc(void *user, void *ptr, size_t size)
{
    failing *f = user;
    if (!ptr) return f_alloc(user, size);
    if (f->fail_at >= 0 && f->count >= f->fail_at) return NULL;
    void *p = realloc(ptr, size ? size : 1);
    if (p) f->count++;
    return p;
}

static void f_free(void *user, void *ptr)
{
    failing *f = user;
    if (ptr) f->live--;
    free(ptr);
}

int main(void)
{
    failing f = {0, 0, -1};
    tt_context_options co;
    tt_context_options_default(&co);
    co.allocator.alloc = f_alloc;
    co.allocator.realloc = f_realloc;
    co.allocator.free = f_free;
    co.allocator.user = &f;
    tt_context *ctx = NULL;
    REQUIRE_OK(ctx, tt_context_create(&co, &ctx));
    /* A small soup, and one big enough that the O(N log N) builder's nodes
     * near the root get blocks of their own (beyond its reusable buffers);
     * not the O(N log^2 N) builder on it (it allocates per node: thousands
     * of builds). The binned builder's parallel path (its stacks growing)
     * is tests/alloc's "binned parallel". */
    const int sizes[] = {120, 3000};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        tt_scene *scene = kd_scene_soup(ctx, sizes[si], 31);
        const long base = f.live;
        for (int builder = TT_KD_NLOGN; builder <= TT_KD_BINNED; builder++) {
            if (si > 0 && builder == TT_KD_NLOG2N) continue;
            tt_build_options o;
            tt_build_options_default(&o);
            o.accel = "kdtree";
            o.kdtree.builder = (tt_kd_builder)builder;
            o.kdtree.dmin = 1;
            int built = 0;
            for (long n = 0; n < 100000 && !built; n++) {
                f.count = 0;
                f.fail_at = n;
                tt_accel *a = NULL;
                tt_status st = tt_accel_build(ctx, scene, &o, &a);
                if (st == TT_OK) {
                    /* The check allocates too. */
                    tt_status cs = tt_accel_check(a);
                    CHECK(cs == TT_OK || cs == TT_ERR_OUT_OF_MEMORY);
                    f.fail_at = -1;
                    CHECK_OK(ctx, tt_accel_check(a));
                    tt_accel_destroy(a);
                    built = 1;
                } else {
                    CHECK_MSG(st == TT_ERR_OUT_OF_MEMORY && a == NULL,
                              "%d triangles, builder %d, failing allocation %ld: status %d (%s)",
                              sizes[si], builder, n, (int)st,
                              tt_context_last_error(ctx));
                }
                CHECK_MSG(f.live == base,
                          "%d triangles, builder %d, failing allocation %ld: %ld blocks leaked",
                          sizes[si], builder, n, f.live - base);
            }
            CHECK(built);
        }
        f.fail_at = -1;
        tt_scene_destroy(scene);
    }
    tt_context_destroy(ctx);
    return tt_test_finish();
}
