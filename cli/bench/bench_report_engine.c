/* The report's engine table: for every scene and view, each structure's
 * builders and layouts (the library's defaults otherwise) against Embree at
 * medium build quality, as its users build it: throughput of primary and
 * shadow rays apart, build time and memory, each with its ratio to Embree's
 * in the same run. The configurations are bench_engine_configs(). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_report.h"

static double mrays(uint64_t rays, double s) { return s > 0.0 ? (double)rays / s * 1e-6 : NAN; }

/* Always ours over Embree's; the report's text says which way is better. */
static double ratio(double ours, double theirs)
{
    return (isnan(ours) || isnan(theirs) || theirs <= 0.0) ? NAN : ours / theirs;
}

/* The structure's statistic `key` from its ';'-separated key=value list;
 * NaN when it has none (Embree, bruteforce). */
static double stat_of(const bench_result *r, const char *key)
{
    const size_t k = strlen(key);
    for (const char *p = r->accel_stats.all; p && *p;) {
        if (strncmp(p, key, k) == 0 && p[k] == '=') return strtod(p + k + 1, NULL);
        p = strchr(p, ';');
        if (p) p++;
    }
    return NAN;
}

static int is_default(const tt_build_options *b)
{
    tt_build_options d;
    tt_build_options_default(&d);
    d.accel = b->accel;
    /* the defaults as the library resolves them (M = 0, d_min = 0: auto) */
    d.rtree.M = tt_rtree_max_entries(&d.rtree);
    d.kdtree.dmin = tt_kdtree_dmin(&d.kdtree);
    return strcmp(b->accel, "embree") != 0 && bench_same_build(b, &d);
}

static void view_table(const bench_report *rp, size_t s, size_t v)
{
    FILE *f = rp->f;
    const bench_scene *sc = &rp->s->items[s];
    size_t n;
    const bench_engine_config *cf = bench_engine_configs(&n);
    const bench_result *e = bench_report_find(rp, s, v, rp->o->rtree_size, cf[0].build,
                                              BENCH_PRIMARY_SHADOW);
    const int eok = bench_result_ok(e);
    const double ep = eok ? mrays(e->summary.primary_rays, e->summary.primary_s) : NAN;
    const double es = eok ? mrays(e->summary.shadow_rays, e->summary.shadow_s) : NAN;
    const double eb = eok ? e->build_s : NAN, em = eok ? (double)e->memory_bytes : NAN;
    fprintf(f, "#### %s:%s (%zu triangles)\n\n", sc->name, sc->views[v].name,
            eok ? e->triangles : (size_t)0);
    fprintf(f, "| configuration | isa | primary Mrays/s | x Embree | shadow Mrays/s | x Embree | "
               "build [s] | x Embree | memory [MB] | x Embree | SAH cost | nodes / boxes / triangles "
               "per primary ray |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < n; i++) {
        const bench_result *r = bench_report_find(rp, s, v, rp->o->rtree_size, cf[i].build,
                                                  BENCH_PRIMARY_SHADOW);
        fprintf(f, "| %s%s |", cf[i].label, is_default(&cf[i].build) ? " **(default)**" : "");
        if (!bench_result_ok(r)) {
            fprintf(f, " %s | | | | | | | | | | |\n", r ? (r->error[0] ? r->error : "error") : "-");
            continue;
        }
        const double p = mrays(r->summary.primary_rays, r->summary.primary_s);
        const double sh = mrays(r->summary.shadow_rays, r->summary.shadow_s);
        const double mem = (double)r->memory_bytes;
        fprintf(f, " %s |", i ? tt_isa_name(r->isa) : "-");
        bench_cell_num(f, p, "%.2f");
        bench_cell_num(f, i ? ratio(p, ep) : 1.0, "%.2fx");
        bench_cell_num(f, sh, "%.2f");
        bench_cell_num(f, i ? ratio(sh, es) : 1.0, "%.2fx");
        bench_cell_num(f, r->build_s, "%.3f");
        bench_cell_num(f, i ? ratio(r->build_s, eb) : 1.0, "%.2fx");
        bench_cell_num(f, mem / 1048576.0, "%.1f");
        bench_cell_num(f, i ? ratio(mem, em) : 1.0, "%.2fx");
        bench_cell_num(f, stat_of(r, "sah_cost"), "%.1f");
        if (r->summary.has_stats && i) {
            const tt_ray_stats *ps = &r->summary.primary_stats;
            fprintf(f, " %.1f / %.1f / %.1f |\n", bench_per_ray(ps->nodes, ps->rays),
                    bench_per_ray(ps->boxes, ps->rays), bench_per_ray(ps->triangles, ps->rays));
        } else {
            fputs(" - |\n", f);
        }
    }
    fputc('\n', f);
}

void bench_report_engine(const bench_report *rp)
{
    if (!(rp->o->tables & BENCH_E1)) return;
    FILE *f = rp->f;
    fprintf(f, "### %s\n\n", bench_table_title(BENCH_E1));
    fprintf(f,
            "Each structure as a user gets it: the library's default options except for the "
            "builder and layout named, %ux%u, primary + shadow rays, against Embree 3 at medium "
            "build quality (rtcIntersect1/rtcOccluded1, robust mode), all in this run. "
            "Mrays/s: rays over the fastest timed pass of each kind (more is better; x Embree "
            "above 1 is faster than Embree). Build time and memory: ours over Embree's (below 1 "
            "is better). Memory counts everything the structure holds, triangles included; "
            "Embree's is what its memory monitor reports (BVH and its vertex copy). The per-ray "
            "counts come from the counting pass; the timed passes never count. SAH cost: the "
            "structure's own expected-cost figure from `info` (R-tree: C_trav = C_isect = 1, "
            "areas relative to the root's; kd-tree: its builder's SAH with its C_T and C_I), "
            "comparable between the builders of one structure, not across structures.\n\n",
            rp->o->rtree_size.width, rp->o->rtree_size.height);
    for (size_t s = 0; s < rp->s->count; s++)
        for (size_t v = 0; v < rp->s->items[s].view_count; v++) view_table(rp, s, v);
}
