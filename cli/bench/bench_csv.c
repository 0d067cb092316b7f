/* results.csv: one row per run with every figure the benchmark measured.
 * Plain RFC 4180: fields with commas or quotes are quoted. */
#include <string.h>

#include "bench/bench.h"

/* clang-format off */
static const char *const columns[] = {
    "scene", "view", "width", "height", "triangles", "vertices", "load_s", "accel",
    "traversal", "options", "rays", "tables", "status", "error", "threads", "repeats",
    "build_s", "memory_bytes", "accel_stats", "primary_rays", "primary_hits", "shadow_rays",
    "shadow_occluded", "trace_min_s", "trace_median_s", "primary_min_s", "shadow_min_s",
    "mrays_per_s_median", "mrays_per_s_best", "primary_mrays_per_s", "shadow_mrays_per_s",
    "primary_nodes_per_ray", "primary_interior_per_ray", "primary_leaves_per_ray",
    "primary_boxes_per_ray", "primary_triangles_per_ray", "shadow_nodes_per_ray",
    "shadow_interior_per_ray", "shadow_leaves_per_ray", "shadow_boxes_per_ray",
    "shadow_triangles_per_ray", "all_nodes_per_ray", "all_interior_per_ray",
    "all_leaves_per_ray", "all_boxes_per_ray", "all_triangles_per_ray",
    "embree_trace_median_s", "time_vs_embree", "agree_embree_pixels", "compared_pixels",
    "agree_embree_pct", "arbitrated_pixels", "ours_match_bruteforce", "device",
    "device_name", "upload_s", "download_s"};
/* clang-format on */
/* The last columns: where the run was traced (GPU runs: the copies to and
 * from the device are timed apart from trace_*). */
#define DEVICE_COLUMNS 4

static void field(FILE *f, const char *s, int last)
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
    fputc(last ? '\n' : ',', f);
}

static void num(FILE *f, double v) { fprintf(f, "%.6g,", v); }
static void u64(FILE *f, uint64_t v) { fprintf(f, "%llu,", (unsigned long long)v); }

static void tables_string(unsigned bits, char *buf, size_t size)
{
    buf[0] = '\0';
    for (size_t i = 0; i < bench_table_count; i++) {
        if (!(bits & bench_tables[i].bit)) continue;
        size_t len = strlen(buf);
        snprintf(buf + len, size - len, "%s%s", len ? ";" : "", bench_tables[i].id);
    }
}

static void stats_fields(FILE *f, const tt_ray_stats *s, int has)
{
    if (!has) {
        fputs(",,,,,", f);
        return;
    }
    num(f, bench_per_ray(s->nodes, s->rays));
    num(f, bench_per_ray(s->interior, s->rays));
    num(f, bench_per_ray(s->leaves, s->rays));
    num(f, bench_per_ray(s->boxes, s->rays));
    num(f, bench_per_ray(s->triangles, s->rays));
}

int bench_write_csv(const char *path, const bench_scene_list *sc, const bench_matrix *m,
                    const bench_results *res, FILE *err)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(err, "treetrace bench: cannot write %s\n", path);
        return -1;
    }
    size_t nc = sizeof columns / sizeof columns[0];
    for (size_t i = 0; i < nc; i++) field(f, columns[i], i + 1 == nc);
    for (size_t i = 0; i < m->count; i++) {
        const bench_run *run = &m->runs[i];
        const bench_result *r = &res->items[i];
        const bench_scene *s = &sc->items[run->scene];
        const tt_render_summary *su = &r->summary;
        char buf[512];
        field(f, s->name, 0);
        field(f, s->views[run->view].name, 0);
        fprintf(f, "%u,%u,", run->size.width, run->size.height);
        if (r->ok)
            fprintf(f, "%zu,%zu,%.6g,", r->triangles, r->vertices, r->load_s);
        else
            fputs(",,,", f);
        field(f, run->build.accel, 0);
        field(f, bench_traversal_name(&run->build), 0);
        bench_options_string(&run->build, buf, sizeof buf);
        field(f, buf, 0);
        field(f, bench_rays_name(run->rays), 0);
        tables_string(run->tables, buf, sizeof buf);
        field(f, buf, 0);
        field(f, r->ok ? "ok" : (strcmp(r->error, "not in this build") == 0 ? "skipped" : "error"),
              0);
        field(f, r->ok ? "" : r->error, 0);
        const char *device = run->device == TT_DEVICE_GPU ? "gpu" : "cpu";
        if (!r->ok) {
            /* the remaining columns stay empty but the device */
            for (size_t k = 14; k < nc - DEVICE_COLUMNS; k++) fputc(',', f);
            fprintf(f, "%s,,,\n", device);
            continue;
        }
        fprintf(f, "%d,%d,", res->threads, r->repeats);
        num(f, r->build_s);
        fprintf(f, "%zu,", r->memory_bytes);
        field(f, r->accel_stats.all, 0);
        u64(f, su->primary_rays);
        u64(f, su->primary_hits);
        u64(f, su->shadow_rays);
        u64(f, su->shadow_occluded);
        num(f, su->trace_s);
        num(f, su->trace_median_s);
        num(f, su->primary_s);
        num(f, su->shadow_s);
        num(f, bench_mrays(r));
        num(f, su->mrays_per_s);
        num(f, su->primary_mrays_per_s);
        num(f, su->shadow_mrays_per_s);
        stats_fields(f, &su->primary_stats, su->has_stats);
        stats_fields(f, &su->shadow_stats, su->has_stats && run->rays == BENCH_PRIMARY_SHADOW);
        tt_ray_stats all = su->primary_stats;
        all.rays += su->shadow_stats.rays;
        all.nodes += su->shadow_stats.nodes;
        all.interior += su->shadow_stats.interior;
        all.leaves += su->shadow_stats.leaves;
        all.boxes += su->shadow_stats.boxes;
        all.triangles += su->shadow_stats.triangles;
        stats_fields(f, &all, su->has_stats);
        if (r->embree && r->embree->ok) {
            num(f, bench_time_s(r->embree));
            num(f, bench_time_s(r) / bench_time_s(r->embree));
        } else {
            fputs(",,", f);
        }
        if (r->compared_pixels) {
            u64(f, r->agree_pixels);
            u64(f, r->compared_pixels);
            fprintf(f, "%.4f,", 100.0 * (double)r->agree_pixels / (double)r->compared_pixels);
            u64(f, r->arbitrated_pixels);
            u64(f, r->ours_match_bruteforce);
        } else {
            fputs(",,,,,", f);
        }
        field(f, device, 0);
        field(f, su->device_name, 0);
        if (run->device == TT_DEVICE_GPU)
            fprintf(f, "%.6g,%.6g\n", su->upload_s, su->download_s);
        else
            fputs(",\n", f);
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        fprintf(err, "treetrace bench: error writing %s\n", path);
        return -1;
    }
    return 0;
}
