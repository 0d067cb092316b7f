/* engine.csv: the engine table in long form, one row per measurement
 * (scene, view, engine, configuration, mode, ray kind), for plotting.
 * Columns (also in the report's text):
 *   scene, view, width, height, triangles, threads, rounds
 *   engine        treetrace | embree
 *   config        the row's label ("rtree sah, compact", "Embree 3 (medium)")
 *   accel, options, is_default (1: the library's default of its structure)
 *   mode          ours: auto | off | on (tt_batch_options.packets; off and
 *                 on only for a structure that offers packets, see
 *                 packets_offered, and on not for AO rays); Embree:
 *                 single | p8 | p16
 *   flags         Embree: default | robust; ours: empty
 *   kind          primary | shadow | ao
 *   rays, best_s (the fastest of the rounds), mrays_per_s
 *   x_embree, x_embree_robust, x_embree_p8, x_embree_p16
 *                 mrays_per_s over that Embree side's on the same rays
 *   x_packets_off mrays_per_s over the same structure's packets=off rate
 *   status, error, isa, packets_offered
 *   build_s (fastest of `builds`), builds, memory_bytes,
 *   x_embree_build, x_embree_memory   over Embree's default-flags scene
 *   agree_embree, agree_embree_pct    same answer as Embree single rays,
 *                 default flags (same triangle or both miss; same flag)
 *   bruteforce_checked, bruteforce_equal, same_as_reference,
 *   packets_mismatch (rays whose answer with this mode differs from auto's)
 *   nodes_per_ray, triangles_per_ray  (counting pass; primary, shadow)
 *   sah_cost
 * Empty fields: not measured or not applicable. */
#include <math.h>
#include <string.h>

#include "bench/bench_yard.h"

/* clang-format off */
static const char *const columns[] = {
    "scene", "view", "width", "height", "triangles", "threads", "rounds", "engine", "config",
    "accel", "options", "is_default", "mode", "flags", "kind", "rays", "best_s", "mrays_per_s",
    "x_embree", "x_embree_robust", "x_embree_p8", "x_embree_p16", "x_packets_off", "status",
    "error", "isa", "packets_offered", "build_s", "builds", "memory_bytes", "x_embree_build",
    "x_embree_memory", "agree_embree", "agree_embree_pct", "bruteforce_checked",
    "bruteforce_equal", "same_as_reference", "packets_mismatch", "nodes_per_ray",
    "triangles_per_ray", "sah_cost"};
/* clang-format on */

static void text(FILE *f, const char *s)
{
    if (strpbrk(s, ",\"\n")) {
        fputc('"', f);
        for (; *s; s++) {
            if (*s == '"') fputc('"', f);
            fputc(*s, f);
        }
        fputc('"', f);
    } else {
        fputs(s, f);
    }
    fputc(',', f);
}

/* A number, or an empty field for NaN. */
static void num(FILE *f, double v)
{
    if (!isnan(v)) fprintf(f, "%.6g", v);
    fputc(',', f);
}

static double mrays(uint64_t rays, double s) { return s > 0.0 ? (double)rays / s * 1e-6 : NAN; }
static double over(double a, double b) { return b > 0.0 ? a / b : NAN; }

typedef struct row_ctx {
    FILE *f;
    const bench_scene *sc;
    const bench_yard *y;
    const yard_view *v;
} row_ctx;

static void head(const row_ctx *r)
{
    FILE *f = r->f;
    text(f, r->sc->name);
    text(f, r->sc->views[r->v->view].name);
    fprintf(f, "%u,%u,%zu,%d,%d,", r->y->size.width, r->y->size.height, r->v->triangles,
            r->y->threads, r->y->rounds);
}

/* The Embree rates of this view and kind (NaN where not measured). */
static double embree_rate(const yard_view *v, yard_side s, int k)
{
    return v->embree.ok ? mrays(v->rays[k], v->embree.best_s[s][k]) : NAN;
}

static void ratios(FILE *f, const yard_view *v, int k, double rate)
{
    for (int s = 0; s < YARD_SIDES; s++) num(f, over(rate, embree_rate(v, (yard_side)s, k)));
}

static void embree_rows(const row_ctx *r)
{
    FILE *f = r->f;
    const yard_view *v = r->v;
    for (int s = 0; s < YARD_SIDES; s++) {
        for (int k = 0; k < YARD_KINDS; k++) {
            if (v->embree.ok && isnan(v->embree.best_s[s][k])) continue; /* not measured */
            const int robust = s == YARD_E_ROBUST;
            head(r);
            text(f, "embree");
            text(f, "Embree 3 (medium)");
            text(f, "embree");
            text(f, robust ? "quality=medium flags=robust" : "quality=medium flags=default");
            text(f, "0");
            text(f, robust ? "single" : yard_side_name((yard_side)s));
            text(f, robust ? "robust" : "default");
            text(f, yard_kind_name((yard_kind)k));
            fprintf(f, "%llu,", (unsigned long long)v->rays[k]);
            const double best = v->embree.ok ? v->embree.best_s[s][k] : NAN;
            num(f, best);
            const double rate = mrays(v->rays[k], best);
            num(f, rate);
            ratios(f, v, k, rate);
            fputc(',', f); /* x_packets_off */
            text(f, v->embree.ok ? "ok" : strcmp(v->embree.error, "not in this build") == 0
                                              ? "skipped"
                                              : "error");
            text(f, v->embree.ok ? "" : v->embree.error);
            fputs(",,", f); /* isa, packets_offered */
            if (v->embree.ok) {
                num(f, v->embree.build_s[robust]);
                fprintf(f, "%d,%zu,", r->y->builds, v->embree.memory_bytes[robust]);
                num(f, over(v->embree.build_s[robust], v->embree.build_s[0]));
                num(f, over((double)v->embree.memory_bytes[robust],
                            (double)v->embree.memory_bytes[0]));
            } else {
                fputs(",,,,,", f);
            }
            fputs(",,,,,,,,\n", f); /* agreement .. sah_cost: ours only */
        }
        if (!v->embree.ok) break; /* one row per kind says why */
    }
}

static void ours_rows(const row_ctx *r, const bench_engine_config *cf, const yard_config *c)
{
    FILE *f = r->f;
    const yard_view *v = r->v;
    char opts[200];
    bench_options_string(&cf->build, opts, sizeof opts);
    for (int m = 0; m < YARD_MODES; m++) {
        for (int k = 0; k < YARD_KINDS; k++) {
            if (!yard_measured(c, (yard_mode)m, k)) continue;
            head(r);
            text(f, "treetrace");
            text(f, cf->label);
            text(f, cf->build.accel);
            text(f, opts);
            text(f, bench_engine_is_default(&cf->build) ? "1" : "0");
            text(f, yard_mode_name((yard_mode)m));
            text(f, "");
            text(f, yard_kind_name((yard_kind)k));
            fprintf(f, "%llu,", (unsigned long long)v->rays[k]);
            const double best = c->ok ? c->best_s[m][k] : NAN;
            num(f, best);
            const double rate = mrays(v->rays[k], best);
            num(f, rate);
            ratios(f, v, k, rate);
            num(f, c->ok && yard_measured(c, YARD_OFF, k)
                       ? over(rate, mrays(v->rays[k], c->best_s[YARD_OFF][k]))
                       : NAN);
            text(f, c->ok ? "ok" : "error");
            text(f, c->ok ? "" : c->error);
            if (!c->ok) {
                for (size_t i = 0; i < 15; i++) fputc(',', f);
                fputc('\n', f);
                continue;
            }
            text(f, tt_isa_name(c->isa));
            fprintf(f, "%d,", c->packets_offered);
            num(f, c->build_s);
            fprintf(f, "%d,%zu,", r->y->builds, c->memory_bytes);
            num(f, v->embree.ok ? over(c->build_s, v->embree.build_s[0]) : NAN);
            num(f, v->embree.ok ? over((double)c->memory_bytes, (double)v->embree.memory_bytes[0])
                                : NAN);
            if (v->embree.ok)
                fprintf(f, "%llu,%.4f,", (unsigned long long)c->agree_embree[k],
                        v->rays[k] ? 100.0 * (double)c->agree_embree[k] / (double)v->rays[k]
                                   : 100.0);
            else
                fputs(",,", f);
            fprintf(f, "%llu,%llu,%llu,%llu,", (unsigned long long)c->bf_checked[k],
                    (unsigned long long)c->bf_equal[k], (unsigned long long)c->same_as_reference[k],
                    (unsigned long long)c->mode_mismatch[m][k]);
            num(f, c->nodes_per_ray[k]);
            num(f, c->triangles_per_ray[k]);
            if (!isnan(c->sah_cost)) fprintf(f, "%.6g", c->sah_cost);
            fputc('\n', f);
        }
    }
}

int bench_yard_write_csv(const char *path, const bench_scene_list *s, const bench_yard *y,
                         FILE *err)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(err, "treetrace bench: cannot write %s\n", path);
        return -1;
    }
    const size_t ncol = sizeof columns / sizeof columns[0];
    for (size_t i = 0; i < ncol; i++) fprintf(f, "%s%c", columns[i], i + 1 < ncol ? ',' : '\n');
    size_t nc;
    const bench_engine_config *cf = bench_engine_configs(&nc);
    for (size_t i = 0; i < y->count; i++) {
        const yard_view *v = &y->views[i];
        row_ctx r = {f, &s->items[v->scene], y, v};
        embree_rows(&r);
        for (size_t c = 0; c < nc; c++) ours_rows(&r, &cf[c], &v->configs[c]);
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        fprintf(err, "treetrace bench: error writing %s\n", path);
        return -1;
    }
    return 0;
}
