/* The report's Havran & Bittner parts: Table 1 (the four kd-tree traversals
 * with their per-ray counts) and Figure 3 (interior nodes and time against
 * d_min, as a table and the figure treetrace.plots draws), with Embree's time
 * beside ours. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_report.h"

static const bench_result *find_kd(const bench_report *rp, size_t s, size_t v, int dmin,
                                   tt_kd_traversal t)
{
    return bench_report_find(rp, s, v, rp->o->kd_size, bench_kdtree_build(TT_KD_NLOGN, dmin, t),
                             BENCH_PRIMARY);
}

static const bench_result *find_embree(const bench_report *rp, size_t s, size_t v)
{
    return bench_report_find(rp, s, v, rp->o->kd_size, bench_named_build("embree"), BENCH_PRIMARY);
}

static double per_ray(const bench_result *r, int which)
{
    if (!bench_result_ok(r) || !r->summary.has_stats) return NAN;
    const tt_ray_stats *s = &r->summary.primary_stats;
    uint64_t v = which == 0 ? s->triangles : which == 1 ? s->leaves : s->interior;
    return bench_per_ray(v, s->rays);
}

static void table1(const bench_report *rp)
{
    FILE *f = rp->f;
    static const tt_kd_traversal tr[4] = {TT_KD_HTR, TT_KD_BTR, TT_KD_SLTR, TT_KD_SEQ};
    fprintf(f, "### %s\n\n", bench_table_title(BENCH_H1));
    fprintf(f,
            "SAH kd-trees (O(n log n) build) at %ux%u, primary rays only. HTR and SEQ run "
            "on a tree without sparse boxes, BTR and SLTR with boxes every d_min = %d levels "
            "(the library's default for traversals that read boxes). Nodes: the kd-tree's nodes; N_B: sparse boxes; M_KD: the "
            "structure's memory; "
            "r_ITM, N_L, N_I: ray-triangle tests, leaves and interior nodes per ray; T_R: "
            "median time per frame.\n\n",
            rp->o->kd_size.width, rp->o->kd_size.height, TT_KD_DMIN_BOXES);
    fprintf(f, "| scene | view | method | nodes | N_B | M_KD [MB] | r_ITM | N_L | N_I | T_R [s] "
               "| x Embree |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t s = 0; s < rp->s->count; s++) {
        const bench_scene *sc = &rp->s->items[s];
        for (size_t v = 0; v < sc->view_count; v++) {
            for (int i = 0; i < 4; i++) {
                int dmin = (tr[i] == TT_KD_BTR || tr[i] == TT_KD_SLTR) ? TT_KD_DMIN_BOXES : -1;
                const bench_result *r = find_kd(rp, s, v, dmin, tr[i]);
                fprintf(f, "| %s | %s | %s |", sc->name, sc->views[v].name,
                        bench_kd_traversal_name(tr[i]));
                int ok = bench_result_ok(r);
                bench_cell_num(f, ok && r->accel_stats.nodes >= 0 ? r->accel_stats.nodes : NAN, "%.0f");
                bench_cell_num(f, ok && r->accel_stats.boxes >= 0 ? r->accel_stats.boxes : NAN, "%.0f");
                bench_cell_num(f, ok ? (double)r->memory_bytes / 1048576.0 : NAN, "%.2f");
                bench_cell_num(f, per_ray(r, 0), "%.2f");
                bench_cell_num(f, per_ray(r, 1), "%.2f");
                bench_cell_num(f, per_ray(r, 2), "%.2f");
                if (ok)
                    fprintf(f, " %#.3g |", bench_time_s(r));
                else
                    bench_cell_time(f, r);
                bench_cell_vs_embree(f, r);
                fprintf(f, "\n");
            }
            const bench_result *e = find_embree(rp, s, v);
            fprintf(f, "| %s | %s | Embree | - | - |", sc->name, sc->views[v].name);
            bench_cell_num(f, bench_result_ok(e) ? (double)e->memory_bytes / 1048576.0 : NAN, "%.2f");
            fprintf(f, " - | - | - |");
            if (bench_result_ok(e))
                fprintf(f, " %#.3g | 1.00x |\n", bench_time_s(e));
            else
                fprintf(f, " - | - |\n");
        }
    }
    fprintf(f, "\nThe paper's Table 1 (its scenes, 13 viewpoints averaged; N_B in millions of "
               "boxes):\n\n");
    fprintf(f, "| scene | method | N_B [M] | M_KD [MB] | r_ITM | N_L | N_I | T_R [s] |\n"
               "|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < bench_havran_table1_count; i++) {
        const bench_havran_row *h = &bench_havran_table1[i];
        fprintf(f, "| %s | %s | %.3g | %.0f | %.2f | %.2f | %.2f | %.2f |\n", h->scene, h->method,
                h->n_b, h->m_kd, h->r_itm, h->n_l, h->n_i, h->t_r);
    }
    fprintf(f, "\n");
}

/* Figure 3 for one scene and view: a table and a link to its figure. */
static void figure3_view(const bench_report *rp, size_t s, size_t v)
{
    FILE *f = rp->f;
    const bench_scene *sc = &rp->s->items[s];
    const char *vn = sc->views[v].name;
    int n = rp->o->dmin_count;
    double *x = calloc((size_t)n, sizeof *x), *buf = calloc((size_t)n * 8, sizeof *buf);
    if (!x || !buf) {
        free(x);
        free(buf);
        return;
    }
    /* rows: BTR N_I, SLTR N_I, HTR N_I, BTR T, SLTR T, HTR T, Embree T */
    double *ni[3] = {buf, buf + n, buf + 2 * n},
           *tm[4] = {buf + 3 * n, buf + 4 * n, buf + 5 * n, buf + 6 * n};
    const bench_result *htr = find_kd(rp, s, v, -1, TT_KD_HTR);
    const bench_result *emb = find_embree(rp, s, v);
    fprintf(f, "#### %s:%s\n\n", sc->name, vn);
    fprintf(f, "| d_min | BTR N_I | SLTR N_I | BTR T_R [s] | SLTR T_R [s] | BTR N_B |\n"
               "|---|---|---|---|---|---|\n");
    for (int i = 0; i < n; i++) {
        x[i] = rp->o->dmins[i];
        const bench_result *b = find_kd(rp, s, v, rp->o->dmins[i], TT_KD_BTR);
        const bench_result *l = find_kd(rp, s, v, rp->o->dmins[i], TT_KD_SLTR);
        ni[0][i] = per_ray(b, 2);
        ni[1][i] = per_ray(l, 2);
        ni[2][i] = per_ray(htr, 2);
        tm[0][i] = bench_result_ok(b) ? bench_time_s(b) : NAN;
        tm[1][i] = bench_result_ok(l) ? bench_time_s(l) : NAN;
        tm[2][i] = bench_result_ok(htr) ? bench_time_s(htr) : NAN;
        tm[3][i] = bench_result_ok(emb) ? bench_time_s(emb) : NAN;
        fprintf(f, "| %d |", rp->o->dmins[i]);
        bench_cell_num(f, ni[0][i], "%.2f");
        bench_cell_num(f, ni[1][i], "%.2f");
        bench_cell_num(f, tm[0][i], "%#.3g");
        bench_cell_num(f, tm[1][i], "%#.3g");
        bench_cell_num(f, bench_result_ok(b) && b->accel_stats.boxes >= 0 ? b->accel_stats.boxes : NAN,
                 "%.0f");
        fprintf(f, "\n");
    }
    char a[32] = "-", b[32] = "-", c[32] = "-", d[32] = "-", e[32] = "-";
    const bench_result *seq = find_kd(rp, s, v, -1, TT_KD_SEQ);
    if (!isnan(per_ray(htr, 2))) snprintf(a, sizeof a, "%.2f", per_ray(htr, 2));
    if (bench_result_ok(htr)) bench_format_seconds(b, sizeof b, bench_time_s(htr));
    if (bench_result_ok(emb)) bench_format_seconds(c, sizeof c, bench_time_s(emb));
    if (!isnan(per_ray(seq, 2))) snprintf(d, sizeof d, "%.2f", per_ray(seq, 2));
    if (bench_result_ok(seq)) bench_format_seconds(e, sizeof e, bench_time_s(seq));
    fprintf(f, "\nReference lines: HTR without boxes N_I %s, T_R %s; SEQ without boxes N_I %s, "
               "T_R %s; Embree T_R %s.\n\n", a, b, d, e, c);

    /* the figure: drawn from results.csv by python3 -m treetrace.plots */
    if (bench_figures_python())
        fprintf(f, "![%s:%s: interior nodes and time per frame against d_min](fig3-%s-%s.png)\n\n"
                   "Figure: [PDF](fig3-%s-%s.pdf), [PNG](fig3-%s-%s.png).\n\n",
                sc->name, vn, sc->name, vn, sc->name, vn, sc->name, vn);
    free(x);
    free(buf);
}

void bench_report_havran(const bench_report *rp)
{
    unsigned t = rp->o->tables;
    if (!(t & (BENCH_H1 | BENCH_H3))) return;
    fprintf(rp->f, "## Havran & Bittner 2007: kd-trees with sparse boxes\n\n");
    if (t & BENCH_H1) table1(rp);
    if (t & BENCH_H3) {
        fprintf(rp->f, "### %s\n\n", bench_table_title(BENCH_H3));
        fprintf(rp->f,
                "Primary rays at %ux%u; BTR and SLTR on kd-trees with sparse boxes every "
                "d_min levels, HTR and SEQ on one without boxes (constant lines). The paper "
                "gives this figure only as plots for its own scenes; its Table 1 shows "
                "the boxes cutting the interior nodes per ray (BTR 73.67 against HTR's "
                "86.85 on 'arena') while SLTR visits about 1.46x HTR's.\n\n",
                rp->o->kd_size.width, rp->o->kd_size.height);
        for (size_t s = 0; s < rp->s->count; s++)
            for (size_t v = 0; v < rp->s->items[s].view_count; v++) figure3_view(rp, s, v);
    }
}
