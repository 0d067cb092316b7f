/* Helpers shared by the R-tree test programs (header only). */
#ifndef TT_TEST_RTREE_H
#define TT_TEST_RTREE_H

#include <stdio.h>
#include <string.h>

#include "check.h"

static const char *const rt_strategy_names[] = {"min-volume", "min-surface", "min-overlap",
                                                 "rstar", "rstar-surface"};
static const char *const rt_traversal_names[] = {"auto", "stackless", "ordered", "stack"};

typedef struct rt_mm {
    int m, M;
} rt_mm;

static const rt_mm rt_mm_list[] = {{2, 4}, {2, 6}, {3, 8}, {4, 16}};
#define RT_MM_COUNT ((int)(sizeof rt_mm_list / sizeof rt_mm_list[0]))

/* Feldmann's R-tree (insertion, the complete layout), which these programs
 * test strategy by strategy; the engine's bulk loaders and compact layout
 * have test_rtree_bulk* and test_rtree_compact*. */
static tt_build_options rt_options(int strategy, int traversal, int m, int M)
{
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = "rtree";
    o.rtree.build = TT_RTREE_BUILD_INSERT;
    o.rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
    o.rtree.strategy = (tt_rtree_strategy)strategy;
    o.rtree.traversal = (tt_rtree_traversal)traversal;
    o.rtree.m = m;
    o.rtree.M = M;
    return o;
}

/* A short description of an R-tree configuration for failure messages. */
static const char *rt_describe(const tt_build_options *o)
{
    static char buf[160];
    snprintf(buf, sizeof buf, "%s m=%d M=%d reinsert=%d(%s) split=%s traversal=%s",
             rt_strategy_names[o->rtree.strategy], o->rtree.m, o->rtree.M, o->rtree.reinsert,
             o->rtree.reinsert_far ? "far" : "close",
             o->rtree.split == TT_RTREE_SPLIT_QUADRATIC ? "quadratic" : "rstar",
             rt_traversal_names[o->rtree.traversal]);
    return buf;
}

/* For the tests that corrupt a built tree: the check must refuse it with
 * TT_ERR_INVARIANT and a message naming `what`. */
static inline void expect_broken(tt_context *ctx, const tt_accel *a, const char *what)
{
    tt_status st = tt_accel_check(a);
    CHECK_MSG(st == TT_ERR_INVARIANT, "corruption '%s' not detected", what);
    CHECK_MSG(strstr(tt_context_last_error(ctx), what) != NULL, "message \"%s\" lacks \"%s\"",
              tt_context_last_error(ctx), what);
}

/* Builds and checks every invariant; returns NULL (a failure recorded) if
 * either fails. */
static tt_accel *rt_build_checked(tt_context *ctx, const tt_scene *scene,
                                  const tt_build_options *o)
{
    tt_accel *a = NULL;
    tt_status st = tt_accel_build(ctx, scene, o, &a);
    CHECK_MSG(st == TT_OK, "build %s: %s", rt_describe(o), tt_context_last_error(ctx));
    if (st != TT_OK) return NULL;
    st = tt_accel_check(a);
    CHECK_MSG(st == TT_OK, "check %s: %s", rt_describe(o), tt_context_last_error(ctx));
    if (st != TT_OK) {
        tt_accel_destroy(a);
        return NULL;
    }
    return a;
}

#endif
