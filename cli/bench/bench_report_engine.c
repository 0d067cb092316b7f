/* The report's engine table (bench_yard.h): a summary of the default
 * structures' ratios over every view, then per view three tables: single
 * rays against Embree's rtcIntersect1/rtcOccluded1 (default flags and
 * robust), packets against Embree's 8- and 16-wide packets, and builds,
 * memory and agreement. */
#include <math.h>
#include <string.h>

#include "bench/bench_report.h"
#include "bench/bench_yard.h"

static double mrays(uint64_t rays, double s) { return s > 0.0 ? (double)rays / s * 1e-6 : NAN; }
static double over(double a, double b) { return b > 0.0 ? a / b : NAN; }

static double ours_rate(const yard_view *v, size_t c, yard_mode m, int k)
{
    const yard_config *r = &v->configs[c];
    return r->ok ? mrays(v->rays[k], r->best_s[m][k]) : NAN;
}

static double embree_rate(const yard_view *v, yard_side s, int k)
{
    return v->embree.ok ? mrays(v->rays[k], v->embree.best_s[s][k]) : NAN;
}

/* The index of the first default configuration of `accel`, or nc. */
static size_t default_of(const char *accel)
{
    size_t nc;
    const bench_engine_config *cf = bench_engine_configs(&nc);
    for (size_t c = 0; c < nc; c++)
        if (strcmp(cf[c].build.accel, accel) == 0 && bench_engine_is_default(&cf[c].build)) return c;
    return nc;
}

static const char *view_name(const bench_report *rp, const yard_view *v, char *buf, size_t n)
{
    const bench_scene *sc = &rp->s->items[v->scene];
    snprintf(buf, n, "%s:%s", sc->name, sc->views[v->view].name);
    return buf;
}

typedef struct range {
    double lo, hi;
} range;

static void widen(range *r, double x)
{
    if (isnan(x)) return;
    if (isnan(r->lo) || x < r->lo) r->lo = x;
    if (isnan(r->hi) || x > r->hi) r->hi = x;
}

static void range_cell(FILE *f, range r)
{
    if (isnan(r.lo))
        fputs(" - |", f);
    else
        fprintf(f, " %.2f–%.2fx |", r.lo, r.hi);
}

/* Per view and over all views: the default R-tree's and kd-tree's ratios,
 * the figures the issues' targets are stated in. */
static void summary(const bench_report *rp, const bench_yard *y)
{
    FILE *f = rp->f;
    const size_t def[2] = {default_of("rtree"), default_of("kdtree")};
    size_t nc;
    bench_engine_configs(&nc);
    fprintf(f, "Summary, the default structures with packets=auto (ours over Embree; above 1 is "
               "faster):\n\n");
    fprintf(f, "| view | R-tree primary | shadow | AO | primary x p16 | shadow x p16 | kd-tree "
               "primary | shadow | AO | primary x p16 | shadow x p16 |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|\n");
    range all[2][5];
    for (int a = 0; a < 2; a++)
        for (int j = 0; j < 5; j++) all[a][j] = (range){NAN, NAN};
    for (size_t i = 0; i < y->count; i++) {
        const yard_view *v = &y->views[i];
        char name[160];
        fprintf(f, "| %s |", view_name(rp, v, name, sizeof name));
        for (int a = 0; a < 2; a++) {
            double x[5] = {NAN, NAN, NAN, NAN, NAN};
            if (def[a] < nc) {
                for (int k = 0; k < YARD_KINDS; k++)
                    x[k] = over(ours_rate(v, def[a], YARD_AUTO, k), embree_rate(v, YARD_E_SINGLE, k));
                for (int k = 0; k < 2; k++)
                    x[3 + k] = over(ours_rate(v, def[a], YARD_AUTO, k), embree_rate(v, YARD_E_P16, k));
            }
            for (int j = 0; j < 5; j++) {
                bench_cell_num(f, x[j], "%.2fx");
                widen(&all[a][j], x[j]);
            }
        }
        fputc('\n', f);
    }
    fprintf(f, "| **all views** |");
    for (int a = 0; a < 2; a++)
        for (int j = 0; j < 5; j++) range_cell(f, all[a][j]);
    fprintf(f, "\n\n");
}

static void label_cell(FILE *f, const bench_engine_config *cf)
{
    fprintf(f, "| %s%s |", cf->label, bench_engine_is_default(&cf->build) ? " **(default)**" : "");
}

static void single_table(FILE *f, const yard_view *v, const bench_engine_config *cf, size_t nc)
{
    fprintf(f, "| single rays | primary Mrays/s | x Embree | x robust | shadow Mrays/s | x Embree "
               "| x robust | AO Mrays/s | x Embree |\n|---|---|---|---|---|---|---|---|---|\n");
    static const char *const sides[2] = {"Embree rtcIntersect1/rtcOccluded1, default flags",
                                         "Embree, ROBUST flag"};
    for (int s = 0; s < 2; s++) {
        fprintf(f, "| %s |", sides[s]);
        for (int k = 0; k < YARD_KINDS; k++) {
            const double r = embree_rate(v, (yard_side)s, k);
            bench_cell_num(f, r, "%.2f");
            bench_cell_num(f, over(r, embree_rate(v, YARD_E_SINGLE, k)), "%.2fx");
            if (k != YARD_AO) bench_cell_num(f, over(r, embree_rate(v, YARD_E_ROBUST, k)), "%.2fx");
        }
        fputc('\n', f);
    }
    for (size_t c = 0; c < nc; c++) {
        label_cell(f, &cf[c]);
        if (!v->configs[c].ok) {
            fprintf(f, " %s | | | | | | | |\n", v->configs[c].error[0] ? v->configs[c].error : "-");
            continue;
        }
        for (int k = 0; k < YARD_KINDS; k++) {
            const double r = ours_rate(v, c, YARD_AUTO, k);
            bench_cell_num(f, r, "%.2f");
            bench_cell_num(f, over(r, embree_rate(v, YARD_E_SINGLE, k)), "%.2fx");
            if (k != YARD_AO) bench_cell_num(f, over(r, embree_rate(v, YARD_E_ROBUST, k)), "%.2fx");
        }
        fputc('\n', f);
    }
    fputc('\n', f);
}

static void packet_table(FILE *f, const yard_view *v, const bench_engine_config *cf, size_t nc)
{
    fprintf(f, "| packets | mode | primary Mrays/s | x off | x Embree p8 | x Embree p16 | shadow "
               "Mrays/s | x off | x Embree p8 | x Embree p16 | AO Mrays/s | x off |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int s = YARD_E_P8; s <= YARD_E_P16; s++) {
        fprintf(f, "| Embree rtcIntersect%d/rtcOccluded%d, coherent | %s |", s == YARD_E_P8 ? 8 : 16,
                s == YARD_E_P8 ? 8 : 16, s == YARD_E_P8 ? "4x2" : "4x4");
        for (int k = 0; k < 2; k++) {
            bench_cell_num(f, embree_rate(v, (yard_side)s, k), "%.2f");
            fputs(" - |", f);
            bench_cell_num(f, over(embree_rate(v, (yard_side)s, k), embree_rate(v, YARD_E_P8, k)),
                           "%.2fx");
            bench_cell_num(f, over(embree_rate(v, (yard_side)s, k), embree_rate(v, YARD_E_P16, k)),
                           "%.2fx");
        }
        fputs(" - | - |\n", f);
    }
    static const yard_mode order[YARD_MODES] = {YARD_OFF, YARD_ON, YARD_AUTO};
    for (size_t c = 0; c < nc; c++) {
        const yard_config *cfg = &v->configs[c];
        if (!cfg->ok) continue;
        for (int i = 0; i < YARD_MODES; i++) {
            const yard_mode m = order[i];
            if (!yard_measured(cfg, m, YARD_PRIMARY)) continue;
            label_cell(f, &cf[c]);
            if (!cfg->packets_offered)
                fputs(" auto: ray by ray, no packet traversal |", f);
            else
                fprintf(f, " %s%s |", yard_mode_name(m), m == YARD_AUTO ? " (default)" : "");
            for (int k = 0; k < YARD_KINDS; k++) {
                const double r = yard_measured(cfg, m, k) ? ours_rate(v, c, m, k) : NAN;
                bench_cell_num(f, r, "%.2f");
                bench_cell_num(f, yard_measured(cfg, YARD_OFF, k) ? over(r, ours_rate(v, c, YARD_OFF, k)) : NAN,
                               "%.2fx");
                if (k == YARD_AO) continue;
                bench_cell_num(f, over(r, embree_rate(v, YARD_E_P8, k)), "%.2fx");
                bench_cell_num(f, over(r, embree_rate(v, YARD_E_P16, k)), "%.2fx");
            }
            fputc('\n', f);
        }
    }
    fputc('\n', f);
}

static void pct(FILE *f, uint64_t a, uint64_t n)
{
    if (!n)
        fputs(" -", f);
    else
        fprintf(f, " %.4f%%", 100.0 * (double)a / (double)n);
}

static void build_table(FILE *f, const yard_view *v, const bench_engine_config *cf, size_t nc)
{
    fprintf(f, "| builds, memory, answers | isa | build [s] | x Embree | memory [MB] | x Embree | "
               "same as Embree: primary / shadow / AO | = bruteforce (sampled) | = default R-tree "
               "| nodes / triangles per primary ray | per shadow ray | SAH cost |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int s = 0; s < 2 && v->embree.ok; s++) {
        fprintf(f, "| Embree, %s flags, medium quality | - |", s ? "ROBUST" : "default");
        bench_cell_num(f, v->embree.build_s[s], "%.3g");
        bench_cell_num(f, over(v->embree.build_s[s], v->embree.build_s[0]), "%.2fx");
        bench_cell_num(f, (double)v->embree.memory_bytes[s] / 1048576.0, "%.3g");
        bench_cell_num(f, over((double)v->embree.memory_bytes[s], (double)v->embree.memory_bytes[0]),
                       "%.2fx");
        fputs(" - | - | - | - | - | - |\n", f);
    }
    for (size_t c = 0; c < nc; c++) {
        const yard_config *r = &v->configs[c];
        label_cell(f, &cf[c]);
        if (!r->ok) {
            fprintf(f, " %s | | | | | | | | | | |\n", r->error[0] ? r->error : "-");
            continue;
        }
        fprintf(f, " %s |", tt_isa_name(r->isa));
        bench_cell_num(f, r->build_s, "%.3g");
        bench_cell_num(f, v->embree.ok ? over(r->build_s, v->embree.build_s[0]) : NAN, "%.2fx");
        bench_cell_num(f, (double)r->memory_bytes / 1048576.0, "%.3g");
        bench_cell_num(f, v->embree.ok ? over((double)r->memory_bytes,
                                              (double)v->embree.memory_bytes[0])
                                       : NAN,
                       "%.2fx");
        if (v->embree.ok) {
            for (int k = 0; k < YARD_KINDS; k++) {
                pct(f, r->agree_embree[k], v->rays[k]);
                fputs(k + 1 < YARD_KINDS ? " /" : " |", f);
            }
        } else {
            fputs(" - |", f);
        }
        uint64_t checked = 0, equal = 0, same = 0, rays = 0;
        for (int k = 0; k < YARD_KINDS; k++) {
            checked += r->bf_checked[k];
            equal += r->bf_equal[k];
            same += r->same_as_reference[k];
            rays += v->rays[k];
        }
        fprintf(f, " %llu of %llu |", (unsigned long long)equal, (unsigned long long)checked);
        if (same == rays)
            fputs(" all rays |", f);
        else
            fprintf(f, " **NO: %llu rays differ** |", (unsigned long long)(rays - same));
        for (int k = 0; k < 2; k++) {
            if (isnan(r->nodes_per_ray[k]))
                fputs(" - |", f);
            else
                fprintf(f, " %.1f / %.1f |", r->nodes_per_ray[k], r->triangles_per_ray[k]);
        }
        bench_cell_num(f, r->sah_cost, "%.1f");
        fputc('\n', f);
    }
    fputc('\n', f);
}

/* What the packet columns can show in this build, from the structures'
 * vtables; and any packet mode that answered otherwise than auto. */
static void packets_note(FILE *f, const bench_yard *y, const bench_engine_config *cf, size_t nc)
{
    char offered[512] = "";
    for (size_t c = 0; c < nc; c++) {
        int any = 0;
        for (size_t i = 0; i < y->count; i++)
            any |= y->views[i].configs[c].ok && y->views[i].configs[c].packets_offered;
        if (any)
            snprintf(offered + strlen(offered), sizeof offered - strlen(offered), "%s%s",
                     offered[0] ? ", " : "", cf[c].label);
    }
    if (!offered[0])
        fprintf(f, "**Packets:** no structure of this build offers packet traversal (their "
                   "vtables have no packet entries), so packets off, on and auto would run the "
                   "same single-ray code and give the same numbers: each structure is timed "
                   "once, with the default (auto), and its packet rows say so. A structure "
                   "whose vtable gains packet entries is timed with off and on too (on: not for "
                   "the incoherent AO rays) and fills its packet rows beside Embree's p8 and "
                   "p16 with no change here.\n\n");
    else
        fprintf(f, "**Packets:** offered by %s, timed with packets off, on (not for AO rays) "
                   "and auto; *x off* is a mode's rate over packets off. The others run ray by "
                   "ray in every mode and are timed once, with auto.\n\n",
                offered);
    for (size_t i = 0; i < y->count; i++)
        for (size_t c = 0; c < nc; c++)
            for (int m = 0; m < YARD_MODES; m++)
                for (int k = 0; k < YARD_KINDS; k++)
                    if (y->views[i].configs[c].mode_mismatch[m][k])
                        fprintf(f, "- **Defect:** %s, packets %s, %s rays of view %zu: %llu answers "
                                   "differ from packets=auto's.\n",
                                cf[c].label, yard_mode_name((yard_mode)m),
                                yard_kind_name((yard_kind)k), i,
                                (unsigned long long)y->views[i].configs[c].mode_mismatch[m][k]);
}

void bench_report_engine(const bench_report *rp)
{
    if (!(rp->o->tables & BENCH_E1) || !rp->r->engine) return;
    FILE *f = rp->f;
    const bench_yard *y = rp->r->engine;
    size_t nc;
    const bench_engine_config *cf = bench_engine_configs(&nc);
    fprintf(f, "### %s\n\n", bench_table_title(BENCH_E1));
    fprintf(f,
            "The yardstick of issues 17 and 18, as Embree's users run Embree: the same ray arrays "
            "traced by our public batch calls and by Embree's own calls in a tight OpenMP loop, "
            "nothing of ours around Embree. %ux%u, %d threads on both sides, %s.\n\n"
            "- **Rays.** Primary: `tt_camera_rays` of the view. Shadow: the conventions' shadow "
            "ray (`tt_shadow_ray`) of every primary hit, in image order. AO: from every primary "
            "hit, %d cosine-distributed directions about the normal facing the ray, the "
            "shadow-ray convention's offset origin, t in [0, %.2g x the scene's diagonal), "
            "fixed seed (the same rays every run). All three come from the default R-tree's hits; "
            "every side traces the same arrays.\n"
            "- **Ours.** `tt_intersect` with `image_width` (16x16 tiles) and the eye's "
            "`tt_accel_locate` as start hint; `tt_occluded` for shadow and AO rays. Default "
            "options: `packets` auto; off and on too where a structure offers packets.\n"
            "- **Embree.** %s, medium build quality, the scene's mesh as loaded. Single rays: "
            "`rtcIntersect1` over the same 16x16 tiles, `rtcOccluded1` over runs of 256 rays; "
            "with the default scene flags (**the headline column**) and with "
            "`RTC_SCENE_FLAG_ROBUST`. Packets: `rtcIntersect8`/`16` on 4x2 / 4x4 pixels and "
            "`rtcOccluded8`/`16` on 8 / 16 consecutive rays, coherent flag, default flags. AO: "
            "single rays only. The library's Embree wrapper (robust, with its own checks) is not "
            "used here; it stays for the ray-by-ray agreement tests.\n"
            "- **Timing.** %d interleaved rounds (each round times, per ray kind, Embree's single "
            "rays, every structure and mode, then Embree's other sides); each figure is the fastest of its rounds, after an "
            "untimed pass that also checks the answers. Mrays/s: rays over that time. "
            "*x Embree* is ours over Embree's rate on the same rays: above 1 is faster.\n"
            "- **Build** is the fastest of %d builds (ours: `tt_accel_build`; Embree: "
            "`rtcCommitScene`); **memory** everything the structure holds, triangles included "
            "(Embree: its memory monitor, the BVH and its copy of the mesh). Ratios: ours over "
            "Embree's default-flags scene, below 1 is quicker or smaller.\n"
            "- **Answers.** *Same as Embree* counts as `raybench` does: the same triangle (or both "
            "miss) for primary rays, the same occluded flag for shadow and AO rays, against Embree "
            "single rays with default flags (not watertight: it may differ at shared edges). "
            "*= bruteforce*: %d evenly spaced rays of each kind and up to %d where Embree answered "
            "otherwise, retraced by bruteforce; ours must equal it bit for bit (or the same t "
            "where two triangles share an edge). *= default R-tree*: every ray's answer "
            "equal to the default R-tree's by the same rule. Per-ray counts: a separate counting pass.\n"
            "- Every figure is in `engine.csv` (one row per scene, view, engine, configuration, "
            "mode and ray kind; its columns are listed at the top of `cli/bench/bench_yard_csv.c`). "
            "The engine table took %.1f s.\n\n",
            y->size.width, y->size.height, y->threads, y->embree_version, y->ao_samples,
            (double)YARD_AO_RADIUS, y->embree_version, y->rounds, y->builds,
            YARD_BRUTEFORCE_SAMPLE, YARD_BRUTEFORCE_DISAGREE, y->total_s);
    packets_note(f, y, cf, nc);
    summary(rp, y);
    for (size_t i = 0; i < y->count; i++) {
        const yard_view *v = &y->views[i];
        char name[160];
        fprintf(f, "#### %s (%zu triangles; %llu primary, %llu shadow, %llu AO rays)\n\n",
                view_name(rp, v, name, sizeof name), v->triangles,
                (unsigned long long)v->rays[YARD_PRIMARY], (unsigned long long)v->rays[YARD_SHADOW],
                (unsigned long long)v->rays[YARD_AO]);
        if (!v->embree.ok) fprintf(f, "Embree: %s.\n\n", v->embree.error);
        single_table(f, v, cf, nc);
        packet_table(f, v, cf, nc);
        build_table(f, v, cf, nc);
    }
}
