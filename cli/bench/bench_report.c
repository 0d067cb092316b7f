/* report.md: the machine and the settings, agreement with Embree, then
 * every table of the two papers with our numbers and the papers' beside
 * them (bench_report_feldmann.c, bench_report_havran.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_report.h"
#include "bench/bench_yard.h"

int bench_result_ok(const bench_result *r) { return r && r->ok; }

const bench_result *bench_report_find_on(const bench_report *rp, size_t scene, size_t view,
                                         bench_size size, tt_build_options build, bench_rays rays,
                                         tt_device device)
{
    bench_run key;
    memset(&key, 0, sizeof key);
    key.scene = scene;
    key.view = view;
    key.size = size;
    key.build = build;
    key.rays = rays;
    key.device = device;
    const bench_run *run = bench_matrix_find(rp->m, &key);
    return run ? &rp->r->items[run - rp->m->runs] : NULL;
}

const bench_result *bench_report_find(const bench_report *rp, size_t scene, size_t view,
                                      bench_size size, tt_build_options build, bench_rays rays)
{
    return bench_report_find_on(rp, scene, view, size, build, rays, TT_DEVICE_CPU);
}

static int why_not(FILE *f, const bench_result *r)
{
    if (!r) {
        fputs(" - |", f);
        return 1;
    }
    if (!r->ok) {
        fputs(strcmp(r->error, "not in this build") == 0 ? " n/a |" : " error |", f);
        return 1;
    }
    return 0;
}

void bench_format_seconds(char *buf, size_t size, double s)
{
    /* three significant digits below a second, so tiny frames do not all
     * read 0.000; two decimals above */
    if (s >= 100.0)
        snprintf(buf, size, "%.0f s", s);
    else if (s >= 1.0)
        snprintf(buf, size, "%.2f s", s);
    else
        snprintf(buf, size, "%#.3g s", s);
}

static void seconds_cell(FILE *f, double s)
{
    char buf[32];
    bench_format_seconds(buf, sizeof buf, s);
    fprintf(f, " %s |", buf);
}

void bench_cell_time(FILE *f, const bench_result *r)
{
    if (!why_not(f, r)) seconds_cell(f, bench_time_s(r));
}

void bench_cell_build(FILE *f, const bench_result *r)
{
    if (!why_not(f, r)) seconds_cell(f, r->build_s);
}

void bench_cell_vs_embree(FILE *f, const bench_result *r)
{
    if (bench_result_ok(r) && bench_result_ok(r->embree) && bench_time_s(r->embree) > 0.0)
        fprintf(f, " %.2fx |", bench_time_s(r) / bench_time_s(r->embree));
    else
        fputs(" - |", f);
}

void bench_cell_ratio(FILE *f, const bench_result *a, const bench_result *b)
{
    if (bench_result_ok(a) && bench_result_ok(b) && bench_time_s(b) > 0.0)
        fprintf(f, " %.2f |", bench_time_s(a) / bench_time_s(b));
    else
        fputs(" - |", f);
}

void bench_cell_num(FILE *f, double v, const char *fmt)
{
    if (isnan(v)) {
        fputs(" - |", f);
        return;
    }
    fputc(' ', f);
    fprintf(f, fmt, v);
    fputs(" |", f);
}

void bench_cell_paper(FILE *f, double v)
{
    if (v < 0.0)
        fputs(" - |", f);
    else
        fprintf(f, " %.2f s |", v);
}

static void machine(const bench_report *rp)
{
    FILE *f = rp->f;
    bench_machine mc;
    bench_machine_read(&mc);
    const char *embree = "not in this build";
    char ev[64];
    for (size_t i = 0; i < rp->r->count; i++) {
        const bench_result *r = &rp->r->items[i];
        const char *p = r->ok ? strstr(r->accel_stats.all, "embree_version=") : NULL;
        if (p) {
            long v = strtol(p + 15, NULL, 10); /* e.g. 31305 = 3.13.5 */
            snprintf(ev, sizeof ev, "Embree %ld.%ld.%ld", v / 10000, v / 100 % 100, v % 100);
            embree = ev;
            break;
        }
    }
    if (rp->r->engine && strncmp(embree, "not", 3) == 0) embree = rp->r->engine->embree_version;
    fprintf(f, "## Machine and settings\n\n");
    fprintf(f, "| | |\n|---|---|\n");
    fprintf(f, "| CPU | %s |\n", mc.cpu);
    fprintf(f, "| logical CPUs online | %d |\n", mc.cores);
    fprintf(f, "| render threads | %d |\n", rp->r->threads);
    fprintf(f, "| compiler | %s |\n", mc.compiler);
    fprintf(f, "| date | %s |\n", mc.date);
    fprintf(f,
            "| reference | %s through the library's wrapper (robust scene, "
            "rtcIntersect1/rtcOccluded1, high build quality) for the papers' tables; the "
            "engine table has its own (Embree's own loops, default flags, medium quality) |\n",
            embree);
    fprintf(f, "| mode | %s |\n", rp->o->quick ? "--quick (reduced matrix)" : "full");
    fprintf(f, "| image sizes | Feldmann tables %ux%u, Havran & Bittner tables %ux%u |\n",
            rp->o->rtree_size.width, rp->o->rtree_size.height, rp->o->kd_size.width,
            rp->o->kd_size.height);
    if (rp->m->count)
        fprintf(f,
            "| timed passes | up to %d after a warm-up, fewer when one pass exceeds %.3g s / "
            "%d; medians reported |\n",
            rp->o->repeat, rp->o->budget_s, rp->o->repeat);
    fprintf(f, "| scenes folder | %s |\n", rp->s->dir);
    fprintf(f, "| benchmark wall time | %.1f s |\n\n", rp->r->total_s);
    fprintf(f, "Scenes:");
    for (size_t i = 0; i < rp->s->count; i++) {
        const bench_scene *s = &rp->s->items[i];
        fprintf(f, "%s %s (%ld triangles; views", i ? ";" : "", s->name, s->triangles);
        for (size_t v = 0; v < s->view_count; v++) fprintf(f, " %s", s->views[v].name);
        fprintf(f, ")");
    }
    fprintf(f, ".\n\n");
    for (size_t i = 0; i < rp->r->skipped_count; i++) fprintf(f, "- %s\n", rp->r->skipped[i]);
    if (rp->r->skipped_count) fprintf(f, "\n");
    if (rp->m->count)
        fprintf(f,
            "Times are the median of the timed passes, in seconds per frame; *x Embree* is our "
            "time over Embree's for the same scene, view, size and rays, measured in this run. "
            "Per-ray statistics come from the counting pass (Embree cannot be instrumented, so it "
            "has none). The papers' numbers are for other machines (Feldmann: i7-4820K, 8 "
            "threads; Havran & Bittner: Athlon 64 X2, one core) and, for Havran & Bittner, other "
            "scenes: compare the shape (ratios between columns), not the absolute values.\n\n");
}

/* One line per structure and traversal: how many pixels of all its runs
 * agree with Embree's hit buffers (the conventions' rule). */
static void agreement(const bench_report *rp)
{
    FILE *f = rp->f;
    if (!rp->m->count) return; /* the engine table checks its own answers */
    fprintf(f, "## Agreement with Embree\n\n");
    fprintf(f, "Hit buffers compared pixel by pixel with Embree's (same triangle, or t within "
               "1e-4 relative, and the same shadow flag). Embree's triangle test is not "
               "watertight in our sense (it accepts hits within an ulp outside an edge), so the "
               "pixels that disagree are retraced with bruteforce, the ground truth: the last "
               "columns say on how many of them the structure matches bruteforce (then Embree "
               "was off, not the structure).\n\n");
    fprintf(f, "| structure | traversal | runs | pixels agreeing | of | agreement | worst run | "
               "disagreeing pixels retraced | of those, equal to bruteforce |\n");
    fprintf(f, "|---|---|---|---|---|---|---|---|---|\n");
    const bench_matrix *m = rp->m;
    char *seen = calloc(m->count ? m->count : 1, 1);
    if (!seen) return;
    size_t rows = 0;
    for (size_t i = 0; i < m->count; i++) {
        if (seen[i] || !rp->r->items[i].compared_pixels) continue;
        rows++;
        const char *acc = m->runs[i].build.accel, *tr = bench_traversal_name(&m->runs[i].build);
        const tt_device dev = m->runs[i].device;
        uint64_t agree = 0, total = 0, retraced = 0, ours_right = 0;
        size_t runs = 0;
        double worst = 2.0;
        size_t worst_i = i;
        for (size_t j = i; j < m->count; j++) {
            const bench_result *r = &rp->r->items[j];
            if (!r->compared_pixels || strcmp(m->runs[j].build.accel, acc) != 0 ||
                strcmp(bench_traversal_name(&m->runs[j].build), tr) != 0 ||
                m->runs[j].device != dev)
                continue;
            seen[j] = 1;
            agree += r->agree_pixels;
            total += r->compared_pixels;
            retraced += r->arbitrated_pixels;
            ours_right += r->ours_match_bruteforce;
            runs++;
            double frac = (double)r->agree_pixels / (double)r->compared_pixels;
            if (frac < worst) worst = frac, worst_i = j;
        }
        const bench_run *w = &m->runs[worst_i];
        char opts[160];
        bench_options_string(&w->build, opts, sizeof opts);
        fprintf(
            f,
            "| %s | %s%s | %zu | %llu | %llu | %.4f%% | %.4f%%: %s:%s %ux%u %s, %s | %llu | %llu |\n",
            acc, tr, dev == TT_DEVICE_GPU ? " (GPU)" : "", runs, (unsigned long long)agree, (unsigned long long)total,
            100.0 * (double)agree / (double)total, 100.0 * worst, rp->s->items[w->scene].name,
            rp->s->items[w->scene].views[w->view].name, w->size.width, w->size.height,
            bench_rays_name(w->rays), opts, (unsigned long long)retraced,
            (unsigned long long)ours_right);
    }
    free(seen);
    if (!rows) fprintf(f, "| (none: no structure but Embree ran) | | | | | | | | |\n");
    fprintf(f, "\n");
}

static void heatmaps(const bench_report *rp)
{
    FILE *f = rp->f;
    int any = 0;
    for (size_t i = 0; i < rp->m->count && !any; i++)
        any = rp->m->runs[i].heatmap && rp->r->items[i].ok;
    if (!any) return;
    fprintf(f, "## Heatmaps\n\n");
    fprintf(f, "Nodes visited per primary ray (dark blue 0 .. dark red 255 or more), from the "
               "counting pass, per scene, view and traversal, in `heatmaps/`:\n\n");
    for (size_t i = 0; i < rp->m->count; i++) {
        const bench_run *run = &rp->m->runs[i];
        if (!run->heatmap || !rp->r->items[i].ok) continue;
        const bench_scene *s = &rp->s->items[run->scene];
        char extra[32] = "";
        if (strcmp(run->build.accel, "kdtree") == 0 && run->build.kdtree.dmin >= 0)
            snprintf(extra, sizeof extra, "-dmin%d", run->build.kdtree.dmin);
        fprintf(f,
                "- %s:%s %s %s%s: [heatmaps/%s-%s-%s-%s%s-%ux%u.png]"
                "(heatmaps/%s-%s-%s-%s%s-%ux%u.png)\n",
                s->name, s->views[run->view].name, run->build.accel,
                bench_traversal_name(&run->build), extra, s->name, s->views[run->view].name,
                run->build.accel, bench_traversal_name(&run->build), extra, run->size.width,
                run->size.height, s->name, s->views[run->view].name, run->build.accel,
                bench_traversal_name(&run->build), extra, run->size.width, run->size.height);
    }
    fprintf(f, "\n");
}

/* Where the figures are: every figure (PDF + PNG) and the points any of
 * them lacks with why, in figures.md, which treetrace.plots writes. */
static void figures(const bench_report *rp)
{
    FILE *f = rp->f;
    fprintf(f, "## Figures\n\n");
    if (bench_figures_python()) {
        fprintf(f, "Drawn from the CSVs with matplotlib by `python3 -m treetrace.plots` (PDF for "
                   "papers, PNG): every figure, and every point a figure lacks with the reason, in "
                   "[figures.md](figures.md).\n");
    } else {
        bench_figures_hint(f, rp->out_dir);
        fprintf(f, ".\n");
    }
}

int bench_write_report(tt_context *ctx, const char *out_dir, const bench_options *o,
                       const bench_scene_list *s, const bench_matrix *m, const bench_results *r,
                       FILE *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/report.md", out_dir);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(err, "treetrace bench: cannot write %s\n", path);
        return -1;
    }
    bench_report rp = {f, ctx, out_dir, o, s, m, r, err};
    fprintf(f, "# treetrace benchmark\n\n");
    fprintf(f, "Reproduction of the tables of Feldmann, *Accelerated Ray Tracing using R-Trees* "
               "(2015) and Havran & Bittner, *Stackless Ray Traversal for kD-Trees with Sparse "
               "Boxes* (2007), with Embree as the reference. Every figure is also in "
               "`results.csv`%s.\n\n",
            r->engine ? " (the engine table's in `engine.csv`)" : "");
    machine(&rp);
    agreement(&rp);
    bench_report_feldmann(&rp);
    bench_report_havran(&rp);
    bench_report_engine(&rp);
    bench_report_gpu(&rp);
    heatmaps(&rp);
    figures(&rp);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        fprintf(err, "treetrace bench: error writing %s\n", path);
        return -1;
    }
    return 0;
}
