/* Prints a fingerprint of the R-trees built by insertion (--build insert) on
 * a scene: a 64-bit FNV-1a hash of each tree in depth-first order (levels,
 * counts, entry boxes, triangle ids), its node count and height, and the
 * thread CPU time of the insertions, for every node-selection strategy with
 * and without forced reinsert in Feldmann's configuration (m 2, M 4), and in
 * the M 16 configurations (the library's default insert options and the one
 * matching Boost.Geometry's rstar<16,4>), the quadratic split and close
 * reinsert once each.
 *
 * Why: making insertion faster must build the very same trees (the papers'
 * tables depend on them). Run it before and after a change and compare the
 * lines without the times:
 *   treetrace_rtree_fingerprint SCENE... | cut -d' ' -f1-8
 *
 * The build makes it (target treetrace_rtree_fingerprint). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtree_insert_run.h"

static int run(tt_context *ctx, const char *name, const float *box, uint32_t T,
               const tt_rtree_options *o, const char *label)
{
    rir_result r;
    if (rir_build(ctx, box, T, o, &r) != 0) {
        fprintf(stderr, "%s %s: %s\n", name, label, tt_context_last_error(ctx));
        return 1;
    }
    printf("%s %s %s reinsert%d hash %016llx nodes %u height %d cpu_ms %.1f\n", name, label,
           rir_strategy_name(o->strategy), o->reinsert, (unsigned long long)r.hash, r.nodes,
           r.height, 1e3 * r.cpu_s);
    fflush(stdout);
    return 0;
}

int main(int argc, char **argv)
{
    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = 1;
    tt_context *ctx = NULL;
    if (tt_context_create(&co, &ctx) != TT_OK) return 1;
    int rc = 0;
    for (int a = 1; a < argc; a++) {
        tt_scene *scene = NULL;
        const char *name = NULL;
        uint32_t T = 0;
        float *box = rir_load(ctx, argv[a], &scene, &name, &T);
        if (!box) {
            rc = 1;
            continue;
        }
        tt_build_options bo;
        tt_build_options_default(&bo);
        tt_rtree_options o = bo.rtree;
        o.build = TT_RTREE_BUILD_INSERT;
        for (int s = TT_RTREE_MIN_VOLUME; s <= TT_RTREE_RRSTAR; s++)
            for (int re = 0; re <= 1; re++) {
                o.strategy = (tt_rtree_strategy)s;
                o.reinsert = re;
                o.m = 2;
                o.M = 4;
                rc |= run(ctx, name, box, T, &o, "m2M4");
                if (!re) continue;
                o.M = 16;
                rc |= run(ctx, name, box, T, &o, "m2M16");
                o.m = 4;
                rc |= run(ctx, name, box, T, &o, "m4M16");
            }
        o = bo.rtree;
        o.build = TT_RTREE_BUILD_INSERT;
        o.split = TT_RTREE_SPLIT_QUADRATIC;
        rc |= run(ctx, name, box, T, &o, "quadratic");
        o.split = TT_RTREE_SPLIT_RSTAR;
        o.reinsert_far = 0;
        rc |= run(ctx, name, box, T, &o, "close");
        free(box);
        tt_scene_destroy(scene);
    }
    tt_context_destroy(ctx);
    return rc;
}
