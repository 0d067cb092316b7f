/* Prints a fingerprint of the kd-trees built on a scene: a 64-bit FNV-1a
 * hash of the node array, the references and the sparse boxes (plus their
 * counts), for each builder and option set below, at 1 and 2 threads.
 *
 * Why: the exact builders must keep building the same tree, node by node,
 * while they are made faster. Building this tool against an older library
 * (its static archive and headers) and against the new one, and comparing
 * the lines, checks that on the real scenes (the tests compare builders
 * with each other, not with an older version of themselves).
 *
 *   treetrace_kd_fingerprint SCENE...   one line per scene, builder, option set, threads
 *
 * The build makes it (target treetrace_kd_fingerprint). Against another
 * checkout's built static library R (a directory with include/, src/ and
 * build/libtreetrace.a), e.g.:
 *   gcc -O2 -std=c11 -IR/include -IR/src tools/kd_fingerprint.c -o fp_old \
 *       R/build/libtreetrace.a R/build/libtreetrace_cuda.a -fopenmp -lpng \
 *       -lembree3 -lm -lpthread -L/usr/local/cuda/lib64 -lcudart
 * (drop the CUDA and Embree libraries where that build has none). */
#include <stdio.h>
#include <string.h>

#include "accel/kdtree/kd_tree.h"
#include "treetrace/treetrace.h"

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; i++) {
        h ^= c[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

typedef struct opt_set {
    const char *name;
    int dmin;
    float ct, ci, empty_bonus;
    int max_depth;
} opt_set;

static const opt_set sets[] = {
    {"default-dmin4", 4, 1.0f, 1.5f, 0.2f, 0},
    {"dmin1-ct2-ci1", 1, 2.0f, 1.0f, 0.0f, 0},
    {"nobox-bonus0.5-depth12", -1, 1.0f, 3.0f, 0.5f, 12},
};

static int run(const char *path, int threads, tt_kd_builder builder, const opt_set *o)
{
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = threads;
    tt_context *ctx = NULL;
    tt_scene *scene = NULL;
    tt_accel *a = NULL;
    if (tt_context_create(&co, &ctx) != TT_OK) return 1;
    int rc = 1;
    if (tt_scene_load(ctx, path, &scene) == TT_OK) {
        tt_build_options bo;
        tt_build_options_default(&bo);
        bo.accel = "kdtree";
        bo.kdtree.builder = builder;
        bo.kdtree.dmin = o->dmin;
        bo.kdtree.cost_traversal = o->ct;
        bo.kdtree.cost_intersect = o->ci;
        bo.kdtree.empty_bonus = o->empty_bonus;
        bo.kdtree.max_depth = o->max_depth;
        if (tt_accel_build(ctx, scene, &bo, &a) == TT_OK) {
            const tt_kdtree *t = tt_kdtree_of(a);
            uint64_t h = 0xcbf29ce484222325ull;
            h = fnv(h, t->nodes, (size_t)t->node_slots * sizeof *t->nodes);
            h = fnv(h, t->refs, t->ref_count * sizeof *t->refs);
            h = fnv(h, t->aug, (size_t)t->aug_count * sizeof *t->aug);
            const char *slash = strrchr(path, '/');
            printf("%s %s %s t%d: nodes %u refs %zu aug %u budget %d hash %016llx\n",
                   slash ? slash + 1 : path, builder == TT_KD_NLOGN ? "nlogn" : "nlog2n", o->name,
                   threads, t->node_slots, t->ref_count, t->aug_count, t->ref_budget_hit,
                   (unsigned long long)h);
            rc = 0;
        }
    }
    if (rc) fprintf(stderr, "%s: %s\n", path, tt_context_last_error(ctx));
    tt_accel_destroy(a);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return rc;
}

int main(int argc, char **argv)
{
    int rc = 0;
    for (int i = 1; i < argc; i++)
        for (size_t s = 0; s < sizeof sets / sizeof sets[0]; s++)
            for (int threads = 1; threads <= 2; threads++) {
                rc |= run(argv[i], threads, TT_KD_NLOGN, &sets[s]);
                /* The slow exact builder once, at one thread: the same tree. */
                if (threads == 1 && s == 0) rc |= run(argv[i], 1, TT_KD_NLOG2N, &sets[s]);
            }
    return rc;
}
