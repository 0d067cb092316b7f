/* The benchmark's matrix: for every selected table, the runs it needs
 * (scene x view x structure x build options x traversal x ray kind), plus
 * the Embree run each is compared with. A run needed by several tables is
 * made once; its table bits say where it is reported. The engine table (E)
 * has no runs here: it times batch calls, not renders (bench_yard.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"

static int same_rtree(const tt_rtree_options *a, const tt_rtree_options *b)
{
    return a->build == b->build && a->layout == b->layout && a->strategy == b->strategy &&
           a->m == b->m && a->M == b->M &&
           a->reinsert == b->reinsert && a->reinsert_fraction == b->reinsert_fraction &&
           a->reinsert_far == b->reinsert_far && a->split == b->split &&
           a->traversal == b->traversal;
}

static int same_kdtree(const tt_kdtree_options *a, const tt_kdtree_options *b)
{
    return a->builder == b->builder && a->dmin == b->dmin &&
           a->cost_traversal == b->cost_traversal && a->cost_intersect == b->cost_intersect &&
           a->empty_bonus == b->empty_bonus && a->max_depth == b->max_depth &&
           a->traversal == b->traversal && a->shadow_caster_hint == b->shadow_caster_hint;
}

/* The traversal is part of the build options (the public API has no way to
 * switch it on a built structure), so two traversals are two builds. */
int bench_same_build(const tt_build_options *a, const tt_build_options *b)
{
    if (strcmp(a->accel, b->accel) != 0 || a->isa != b->isa) return 0;
    if (strcmp(a->accel, "rtree") == 0) return same_rtree(&a->rtree, &b->rtree);
    if (strcmp(a->accel, "kdtree") == 0) return same_kdtree(&a->kdtree, &b->kdtree);
    if (strcmp(a->accel, "embree") == 0) return a->embree.quality == b->embree.quality;
    return 1; /* bruteforce: no options */
}

static int same_run(const bench_run *a, const bench_run *b)
{
    return a->scene == b->scene && a->view == b->view && a->size.width == b->size.width &&
           a->size.height == b->size.height && a->rays == b->rays && a->device == b->device &&
           bench_same_build(&a->build, &b->build);
}

const bench_run *bench_matrix_find(const bench_matrix *m, const bench_run *r)
{
    for (size_t i = 0; i < m->count; i++)
        if (same_run(&m->runs[i], r)) return &m->runs[i];
    return NULL;
}

static int add(bench_matrix *m, const bench_run *r)
{
    for (size_t i = 0; i < m->count; i++) {
        if (same_run(&m->runs[i], r)) {
            m->runs[i].tables |= r->tables;
            m->runs[i].heatmap |= r->heatmap;
            return 0;
        }
    }
    if (m->count == m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 64;
        bench_run *grown = realloc(m->runs, cap * sizeof *grown);
        if (!grown) return -1;
        m->runs = grown;
        m->cap = cap;
    }
    m->runs[m->count++] = *r;
    return 0;
}

tt_build_options bench_rtree_build(tt_rtree_strategy s, int reinsert, tt_rtree_traversal t)
{
    tt_build_options b;
    tt_build_options_default(&b);
    b.accel = "rtree";
    /* Feldmann's configuration, whatever the library's default engine is:
     * built by insertion, packed into the complete level-order layout. */
    b.rtree.build = TT_RTREE_BUILD_INSERT;
    b.rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
    b.rtree.m = 2;
    b.rtree.M = 4;
    b.rtree.strategy = s;
    b.rtree.reinsert = reinsert;
    b.rtree.traversal = t;
    return b;
}

/* dmin < 0: no sparse boxes (what HTR and SEQ need, as in the paper's N_B = 0). */
tt_build_options bench_kdtree_build(tt_kd_builder builder, int dmin, tt_kd_traversal t)
{
    tt_build_options b;
    tt_build_options_default(&b);
    b.accel = "kdtree";
    /* The SAH constants the papers' tables were reproduced with (the
     * library's default C_I is 0.2 since the gather-free leaf test). */
    b.kdtree.cost_traversal = 1.0f;
    b.kdtree.cost_intersect = 1.5f;
    b.kdtree.empty_bonus = 0.2f;
    b.kdtree.builder = builder;
    b.kdtree.dmin = dmin;
    b.kdtree.traversal = t;
    return b;
}

tt_build_options bench_named_build(const char *accel)
{
    tt_build_options b;
    tt_build_options_default(&b);
    b.accel = accel;
    return b;
}

typedef struct ctx {
    bench_matrix *m;
    size_t scene, view;
    int fail;
} ctx;

static void run(ctx *c, bench_size size, tt_build_options b, bench_rays rays, unsigned tables,
                int heatmap)
{
    bench_run r;
    memset(&r, 0, sizeof r);
    r.scene = c->scene;
    r.view = c->view;
    r.size = size;
    r.build = b;
    r.rays = rays;
    r.tables = tables;
    r.heatmap = heatmap;
    if (add(c->m, &r)) c->fail = 1;
    /* the Embree run it is compared with (same scene, view, size, rays) */
    r.build = bench_named_build("embree");
    r.heatmap = 0;
    if (add(c->m, &r)) c->fail = 1;
}

static void feldmann(ctx *c, const bench_options *o)
{
    const bench_size sz = o->rtree_size;
    const unsigned t = o->tables;
    if (t & BENCH_F1) {
        const tt_rtree_strategy all[] = {TT_RTREE_MIN_VOLUME, TT_RTREE_MIN_SURFACE,
                                         TT_RTREE_MIN_OVERLAP, TT_RTREE_RSTAR,
                                         TT_RTREE_RSTAR_SURFACE};
        for (size_t i = 0; i < 5; i++)
            run(c, sz, bench_rtree_build(all[i], 1, TT_RTREE_STACKLESS), BENCH_PRIMARY_SHADOW,
                BENCH_F1, 0);
    }
    if (t & BENCH_F2) {
        /* the table gives the change against Table 1's R*-treeSrfc */
        run(c, sz, bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 0, TT_RTREE_STACKLESS),
            BENCH_PRIMARY_SHADOW, BENCH_F2, 0);
        run(c, sz, bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_STACKLESS),
            BENCH_PRIMARY_SHADOW, BENCH_F2, 0);
    }
    if (t & BENCH_F3) {
        const tt_rtree_traversal all[] = {TT_RTREE_STACKLESS, TT_RTREE_ORDERED, TT_RTREE_STACK};
        for (size_t i = 0; i < 3; i++)
            run(c, sz, bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, all[i]), BENCH_PRIMARY_SHADOW,
                BENCH_F3, o->heatmaps);
    }
    if (t & BENCH_F4) {
        /* the paper's kd-tree: O(n log^2 n) SAH build, stack traversal, no boxes */
        for (int rays = 0; rays < 2; rays++) {
            run(c, sz, bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_STACK),
                (bench_rays)rays, BENCH_F4, 0);
            run(c, sz, bench_kdtree_build(TT_KD_NLOG2N, -1, TT_KD_HTR), (bench_rays)rays, BENCH_F4,
                0);
        }
    }
    if (t & BENCH_F5) {
        run(c, sz, bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_STACKLESS),
            BENCH_PRIMARY_SHADOW, BENCH_F5, 0);
        run(c, sz, bench_kdtree_build(TT_KD_NLOG2N, -1, TT_KD_HTR), BENCH_PRIMARY_SHADOW, BENCH_F5,
            0);
        /* the O(n log n) build the paper cites from Wald & Havran, for comparison */
        run(c, o->kd_size, bench_kdtree_build(TT_KD_NLOGN, -1, TT_KD_HTR), BENCH_PRIMARY, BENCH_F5,
            0);
    }
}

static void havran(ctx *c, const bench_options *o, int default_dmin)
{
    const bench_size sz = o->kd_size;
    const unsigned t = o->tables;
    if (t & BENCH_H1) {
        /* HTR and SEQ use no boxes (N_B = 0 in the paper); BTR and SLTR the
         * library's default d_min */
        run(c, sz, bench_kdtree_build(TT_KD_NLOGN, -1, TT_KD_HTR), BENCH_PRIMARY, BENCH_H1,
            o->heatmaps);
        run(c, sz, bench_kdtree_build(TT_KD_NLOGN, default_dmin, TT_KD_BTR), BENCH_PRIMARY,
            BENCH_H1, o->heatmaps);
        run(c, sz, bench_kdtree_build(TT_KD_NLOGN, default_dmin, TT_KD_SLTR), BENCH_PRIMARY,
            BENCH_H1, o->heatmaps);
        run(c, sz, bench_kdtree_build(TT_KD_NLOGN, -1, TT_KD_SEQ), BENCH_PRIMARY, BENCH_H1,
            o->heatmaps);
    }
    if (t & BENCH_H3) {
        /* HTR and SEQ without boxes: Figure 3's constant lines, all four traversals */
        run(c, sz, bench_kdtree_build(TT_KD_NLOGN, -1, TT_KD_HTR), BENCH_PRIMARY, BENCH_H3, 0);
        run(c, sz, bench_kdtree_build(TT_KD_NLOGN, -1, TT_KD_SEQ), BENCH_PRIMARY, BENCH_H3, 0);
        for (int i = 0; i < o->dmin_count; i++) {
            run(c, sz, bench_kdtree_build(TT_KD_NLOGN, o->dmins[i], TT_KD_BTR), BENCH_PRIMARY,
                BENCH_H3, 0);
            run(c, sz, bench_kdtree_build(TT_KD_NLOGN, o->dmins[i], TT_KD_SLTR), BENCH_PRIMARY,
                BENCH_H3, 0);
        }
    }
}

int bench_gpu_traces(const tt_build_options *b)
{
    if (strcmp(b->accel, "rtree") == 0)
        return b->rtree.layout == TT_RTREE_LAYOUT_COMPLETE && b->rtree.traversal != TT_RTREE_STACK;
    if (strcmp(b->accel, "kdtree") == 0)
        return (b->kdtree.traversal == TT_KD_SLTR || b->kdtree.traversal == TT_KD_HTR) &&
               !b->kdtree.shadow_caster_hint;
    return 0;
}

/* --device gpu: the GPU copies of the runs made so far (their Embree runs
 * exist already: the CPU's, the reference for both). */
static int add_gpu_runs(bench_matrix *m)
{
    const size_t cpu_runs = m->count;
    for (size_t i = 0; i < cpu_runs; i++) {
        bench_run r = m->runs[i]; /* a copy: add() may move the array */
        if (!bench_gpu_traces(&r.build)) continue;
        r.device = TT_DEVICE_GPU;
        r.heatmap = 0; /* the counts are the CPU's: one heatmap is enough */
        if (add(m, &r)) return -1;
        if (strcmp(r.build.accel, "rtree") == 0 && (r.tables & (BENCH_F1 | BENCH_F2)) &&
            r.build.rtree.traversal == TT_RTREE_STACKLESS) {
            r.build.rtree.traversal = TT_RTREE_ORDERED;
            if (add(m, &r)) return -1;
        }
    }
    return 0;
}

int bench_matrix_make(const bench_options *o, const bench_scene_list *scenes, bench_matrix *m)
{
    memset(m, 0, sizeof *m);
    tt_build_options def;
    tt_build_options_default(&def);
    ctx c = {m, 0, 0, 0};
    for (c.scene = 0; c.scene < scenes->count; c.scene++) {
        for (c.view = 0; c.view < scenes->items[c.scene].view_count; c.view++) {
            feldmann(&c, o);
            havran(&c, o, TT_KD_DMIN_BOXES);
        }
    }
    if (!c.fail && o->device == TT_DEVICE_GPU && add_gpu_runs(m)) c.fail = 1;
    if (c.fail) {
        bench_matrix_free(m);
        return -1;
    }
    return 0;
}

void bench_matrix_free(bench_matrix *m)
{
    free(m->runs);
    memset(m, 0, sizeof *m);
}
