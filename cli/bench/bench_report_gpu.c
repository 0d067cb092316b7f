/* The report's GPU section (--device gpu): Feldmann's GPU rows of Tables
 * 1-3 with ours beside them, the kd-tree traversals of Havran & Bittner's
 * Table 1 on the GPU, and every GPU run with its upload time, Mrays/s and
 * the CPU's time for the same configuration. */
#include "bench/bench_report.h"

static const tt_rtree_strategy strategies[5] = {TT_RTREE_MIN_VOLUME, TT_RTREE_MIN_SURFACE,
                                                TT_RTREE_MIN_OVERLAP, TT_RTREE_RSTAR,
                                                TT_RTREE_RSTAR_SURFACE};

static const bench_result *gpu_rtree(const bench_report *rp, size_t s, size_t v,
                                     tt_rtree_strategy st, int reinsert, tt_rtree_traversal t)
{
    return bench_report_find_on(rp, s, v, rp->o->rtree_size, bench_rtree_build(st, reinsert, t),
                                BENCH_PRIMARY_SHADOW, TT_DEVICE_GPU);
}

static void paper_cell(FILE *f, double v)
{
    char buf[32];
    if (v < 0.0) {
        fputs(" - |", f);
        return;
    }
    bench_format_seconds(buf, sizeof buf, v);
    fprintf(f, " %s |", buf);
}

static void gpu_table1(const bench_report *rp)
{
    FILE *f = rp->f;
    fprintf(f, "### GPU: %s\n\n", bench_table_title(BENCH_F1));
    fprintf(f, "As Table 1 above, on the GPU, with the ordered traversal (the paper's GPU rows) "
               "and the stackless one.\n\n");
    fprintf(f, "| scene | view | | minVolume | minSurface | minOverlap | R*-tree | R*-treeSrfc "
               "|\n|---|---|---|---|---|---|---|---|\n");
    for (size_t s = 0; s < rp->s->count; s++) {
        const bench_scene *sc = &rp->s->items[s];
        for (size_t v = 0; v < sc->view_count; v++) {
            fprintf(f, "| %s | %s | GPU ordered |", sc->name, sc->views[v].name);
            for (int i = 0; i < 5; i++)
                bench_cell_time(f, gpu_rtree(rp, s, v, strategies[i], 1, TT_RTREE_ORDERED));
            fprintf(f, "\n| | | GPU stackless |");
            for (int i = 0; i < 5; i++)
                bench_cell_time(f, gpu_rtree(rp, s, v, strategies[i], 1, TT_RTREE_STACKLESS));
            fprintf(f, "\n");
        }
        const char *p = bench_feldmann_scene(sc->name);
        if (!p) continue;
        fprintf(f, "| %s | | paper GPU |", p);
        for (int i = 0; i < 5; i++)
            paper_cell(f, bench_feldmann_gpu_value(1, p, bench_strategy_name(strategies[i])));
        fprintf(f, "\n");
    }
    fprintf(f, "\n");
}

static void gpu_table2(const bench_report *rp)
{
    FILE *f = rp->f;
    fprintf(f, "### GPU: %s\n\n", bench_table_title(BENCH_F2));
    fprintf(f, "R*-treeSrfc on the GPU with the ordered traversal, with and without forced "
               "reinsert.\n\n");
    fprintf(f, "| scene | view | with reinsert | without | without / with | paper with | paper "
               "without | paper without / with |\n|---|---|---|---|---|---|---|---|\n");
    for (size_t s = 0; s < rp->s->count; s++) {
        const bench_scene *sc = &rp->s->items[s];
        const char *p = bench_feldmann_scene(sc->name);
        double pw = bench_feldmann_gpu_value(1, p, "R*-treeSrfc");
        double pn = bench_feldmann_gpu_value(2, p, "no reinsert");
        for (size_t v = 0; v < sc->view_count; v++) {
            const bench_result *with =
                gpu_rtree(rp, s, v, TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_ORDERED);
            const bench_result *without =
                gpu_rtree(rp, s, v, TT_RTREE_RSTAR_SURFACE, 0, TT_RTREE_ORDERED);
            fprintf(f, "| %s | %s |", sc->name, sc->views[v].name);
            bench_cell_time(f, with);
            bench_cell_time(f, without);
            bench_cell_ratio(f, without, with);
            paper_cell(f, pw);
            paper_cell(f, pn);
            if (pw > 0.0 && pn > 0.0)
                fprintf(f, " %.2f |\n", pn / pw);
            else
                fprintf(f, " - |\n");
        }
    }
    fprintf(f, "\n");
}

static void gpu_table3(const bench_report *rp)
{
    FILE *f = rp->f;
    fprintf(f, "### GPU: %s\n\n", bench_table_title(BENCH_F3));
    fprintf(f, "R*-treeSrfc with forced reinsert, primary + shadow rays at %ux%u on the GPU, "
               "with the CPU's times from Table 3 above.\n\n",
               rp->o->rtree_size.width, rp->o->rtree_size.height);
    fprintf(f, "| scene | view | GPU stackless | GPU ordered | CPU stackless | CPU ordered | "
               "CPU / GPU stackless | paper GPU stackless | paper GPU ordered |\n"
               "|---|---|---|---|---|---|---|---|---|\n");
    for (size_t s = 0; s < rp->s->count; s++) {
        const bench_scene *sc = &rp->s->items[s];
        const char *p = bench_feldmann_scene(sc->name);
        for (size_t v = 0; v < sc->view_count; v++) {
            const bench_result *gs =
                gpu_rtree(rp, s, v, TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_STACKLESS);
            const bench_result *cs = bench_report_find(
                rp, s, v, rp->o->rtree_size,
                bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_STACKLESS),
                BENCH_PRIMARY_SHADOW);
            fprintf(f, "| %s | %s |", sc->name, sc->views[v].name);
            bench_cell_time(f, gs);
            bench_cell_time(f, gpu_rtree(rp, s, v, TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_ORDERED));
            bench_cell_time(f, cs);
            bench_cell_time(f, bench_report_find(
                                   rp, s, v, rp->o->rtree_size,
                                   bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_ORDERED),
                                   BENCH_PRIMARY_SHADOW));
            bench_cell_ratio(f, cs, gs);
            paper_cell(f, bench_feldmann_gpu_value(3, p, "stackless"));
            paper_cell(f, bench_feldmann_gpu_value(3, p, "ordered"));
            fprintf(f, "\n");
        }
    }
    fprintf(f, "\n");
}

static void gpu_havran(const bench_report *rp)
{
    FILE *f = rp->f;
    const tt_build_options htr = bench_kdtree_build(TT_KD_NLOGN, -1, TT_KD_HTR);
    const tt_build_options sltr = bench_kdtree_build(TT_KD_NLOGN, TT_KD_DMIN_BOXES, TT_KD_SLTR);
    fprintf(f, "### GPU: %s\n\n", bench_table_title(BENCH_H1));
    fprintf(f, "HTR (a small fixed stack per thread) and SLTR (no stack; sparse boxes every "
               "%d levels) on the GPU, primary rays at %ux%u, with the CPU's times. The paper "
               "designed SLTR for GPUs but measured it on a CPU only.\n\n",
               TT_KD_DMIN_BOXES, rp->o->kd_size.width, rp->o->kd_size.height);
    fprintf(f, "| scene | view | GPU HTR | GPU SLTR | SLTR / HTR | CPU HTR | CPU SLTR |\n"
               "|---|---|---|---|---|---|---|\n");
    for (size_t s = 0; s < rp->s->count; s++) {
        const bench_scene *sc = &rp->s->items[s];
        for (size_t v = 0; v < sc->view_count; v++) {
            const bench_result *gh =
                bench_report_find_on(rp, s, v, rp->o->kd_size, htr, BENCH_PRIMARY, TT_DEVICE_GPU);
            const bench_result *gs =
                bench_report_find_on(rp, s, v, rp->o->kd_size, sltr, BENCH_PRIMARY, TT_DEVICE_GPU);
            fprintf(f, "| %s | %s |", sc->name, sc->views[v].name);
            bench_cell_time(f, gh);
            bench_cell_time(f, gs);
            bench_cell_ratio(f, gs, gh);
            bench_cell_time(f, bench_report_find(rp, s, v, rp->o->kd_size, htr, BENCH_PRIMARY));
            bench_cell_time(f, bench_report_find(rp, s, v, rp->o->kd_size, sltr, BENCH_PRIMARY));
            fprintf(f, "\n");
        }
    }
    fprintf(f, "\n");
}

/* Every GPU run, with the copies and the CPU's time for the same run. */
static void gpu_all_runs(const bench_report *rp)
{
    FILE *f = rp->f;
    fprintf(f, "### Every GPU run\n\n");
    fprintf(f, "| scene | view | size | structure | traversal | options | rays | upload | "
               "trace (median) | Mrays/s | CPU trace | CPU / GPU |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < rp->m->count; i++) {
        const bench_run *run = &rp->m->runs[i];
        if (run->device != TT_DEVICE_GPU) continue;
        const bench_result *r = &rp->r->items[i];
        const bench_scene *sc = &rp->s->items[run->scene];
        char opts[160], up[32];
        bench_options_string(&run->build, opts, sizeof opts);
        fprintf(f, "| %s | %s | %ux%u | %s | %s | %s | %s |", sc->name, sc->views[run->view].name,
                run->size.width, run->size.height, run->build.accel,
                bench_traversal_name(&run->build), opts, bench_rays_name(run->rays));
        if (bench_result_ok(r)) {
            bench_format_seconds(up, sizeof up, r->summary.upload_s);
            fprintf(f, " %s |", up);
        } else {
            fputs(" - |", f);
        }
        bench_cell_time(f, r);
        if (bench_result_ok(r))
            fprintf(f, " %.1f |", bench_mrays(r));
        else
            fputs(" - |", f);
        bench_run cpu = *run;
        cpu.device = TT_DEVICE_CPU;
        const bench_run *c = bench_matrix_find(rp->m, &cpu);
        const bench_result *cr = c ? &rp->r->items[c - rp->m->runs] : NULL;
        bench_cell_time(f, cr);
        bench_cell_ratio(f, cr, r);
        fprintf(f, "\n");
    }
    fprintf(f, "\n");
}

void bench_report_gpu(const bench_report *rp)
{
    const char *name = NULL;
    size_t runs = 0;
    for (size_t i = 0; i < rp->m->count; i++) {
        if (rp->m->runs[i].device != TT_DEVICE_GPU) continue;
        runs++;
        if (!name && rp->r->items[i].ok) name = rp->r->items[i].summary.device_name;
    }
    if (!runs) return;
    FILE *f = rp->f;
    fprintf(f, "## GPU (CUDA)\n\n");
    fprintf(f,
            "Device: %s. One thread per ray, 128 threads per block, the structure in linear "
            "device memory read through the read-only data cache, its shape in constant "
            "memory; the traversals are the CPU's code compiled for the GPU. Times are CUDA "
            "event times of the kernels, medians of the timed passes: primary rays are "
            "generated on the GPU inside them; the copies to and from the device are not in "
            "them (*upload* is the structure's and the triangles' copy, once per render). "
            "Agreement with Embree is in the table above, rows marked (GPU). The paper's GPU "
            "was a GeForce GTX 780.\n\n",
            name ? name : "(no GPU run succeeded)");
    unsigned t = rp->o->tables;
    if (t & BENCH_F1) gpu_table1(rp);
    if (t & BENCH_F2) gpu_table2(rp);
    if (t & BENCH_F3) gpu_table3(rp);
    if (t & BENCH_H1) gpu_havran(rp);
    gpu_all_runs(rp);
}
