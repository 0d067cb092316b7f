/* The benchmark's --device gpu logic on any machine, GPU or not: the bench's
 * own sources (cli/bench) compiled into this program and driven in-process
 * with fabricated results, so that nothing needs a GPU:
 *  - options: --device cpu|gpu parsed, anything else refused;
 *  - matrix: with --device gpu the CPU runs are exactly those without it,
 *    and every run the GPU traces (R-tree stackless/ordered, kd-tree
 *    SLTR/HTR) has one GPU copy with the same tables, plus the ordered
 *    R-trees of Feldmann's Tables 1 and 2; nothing else runs on the GPU;
 *  - CSV: the device columns (gpu rows: name, upload and download times);
 *  - report: the GPU section's tables carry the right runs' times beside
 *    the paper's GPU numbers, and one line per GPU run.
 * The real GPU runs are checked by test_bench_device where a GPU exists. */
#include "bench/bench_agree.c"
#include "bench/bench_csv.c"
#include "bench/bench_fs.c"
#include "bench/bench_machine.c"
/* bench_matrix.c and bench_paper.c each have a static `feldmann` (the CLI
 * compiles them apart); rename the matrix's here */
#define feldmann bench_matrix_feldmann
#define havran bench_matrix_havran
#include "bench/bench_matrix.c"
#undef feldmann
#undef havran
#include "bench/bench_names.c"
#include "bench/bench_options.c"
#include "bench/bench_paper.c"
#include "bench/bench_progress.c"
#include "bench/bench_report.c"
#include "bench/bench_report_gpu.c"
#include "bench/bench_runner.c"

#include "check.h"
#include "cli_run.h"

/* The CPU papers' tables are not under test here. */
void bench_report_feldmann(const bench_report *rp) { (void)rp; }
void bench_report_havran(const bench_report *rp) { (void)rp; }
void bench_report_engine(const bench_report *rp) { (void)rp; }
/* Nor the figures (drawn by python3 -m treetrace.plots). */
const char *bench_figures_python(void) { return NULL; }
void bench_figures_hint(FILE *f, const char *out_dir) { fprintf(f, "no figures: %s", out_dir); }

static int parse(const char *a1, const char *a2, bench_options *o)
{
    char *argv[] = {"bench", (char *)a1, (char *)a2, NULL};
    FILE *err = fopen("/dev/null", "w");
    int rc = bench_parse_options(a2 ? 3 : 2, argv, o, err ? err : stderr);
    if (err) fclose(err);
    return rc;
}

static void test_options(void)
{
    bench_options o;
    CHECK(parse("--quick", NULL, &o) == 0 && o.device == TT_DEVICE_CPU);
    bench_options_free(&o);
    CHECK(parse("--device", "gpu", &o) == 0 && o.device == TT_DEVICE_GPU);
    bench_options_free(&o);
    CHECK(parse("--device=cpu", NULL, &o) == 0 && o.device == TT_DEVICE_CPU);
    bench_options_free(&o);
    CHECK(parse("--device", "tpu", &o) == 2);
    CHECK(parse("--device", NULL, &o) == 2);
}

/* One scene "bunny" (the paper's Bunny) with one view. */
static bench_scene_list one_scene(void)
{
    static bench_view view;
    static bench_scene scene;
    memset(&view, 0, sizeof view);
    strcpy(view.name, "main");
    memset(&scene, 0, sizeof scene);
    strcpy(scene.name, "bunny");
    scene.triangles = 69451;
    scene.views = &view;
    scene.view_count = 1;
    bench_scene_list l;
    memset(&l, 0, sizeof l);
    l.items = &scene;
    l.count = 1;
    strcpy(l.dir, "/nowhere");
    return l;
}

static int is_gpu_config(const tt_build_options *b)
{
    if (strcmp(b->accel, "rtree") == 0)
        return b->rtree.layout == TT_RTREE_LAYOUT_COMPLETE &&
               (b->rtree.traversal == TT_RTREE_AUTO || b->rtree.traversal == TT_RTREE_STACKLESS ||
                b->rtree.traversal == TT_RTREE_ORDERED);
    if (strcmp(b->accel, "kdtree") == 0)
        return b->kdtree.traversal == TT_KD_SLTR || b->kdtree.traversal == TT_KD_HTR;
    return 0;
}

static void test_matrix(const bench_scene_list *sl, bench_matrix *gm)
{
    bench_options cpu_o, gpu_o;
    CHECK(parse("--device", "cpu", &cpu_o) == 0);
    CHECK(parse("--device", "gpu", &gpu_o) == 0);
    gpu_o.rtree_size = gpu_o.kd_size = cpu_o.rtree_size = cpu_o.kd_size = (bench_size){64, 48};
    bench_matrix cm;
    REQUIRE_OK(NULL, bench_matrix_make(&cpu_o, sl, &cm) == 0 ? TT_OK : TT_ERR_OUT_OF_MEMORY);
    REQUIRE_OK(NULL, bench_matrix_make(&gpu_o, sl, gm) == 0 ? TT_OK : TT_ERR_OUT_OF_MEMORY);
    /* the CPU part is the CPU-only matrix, in the same order */
    size_t ncpu = 0;
    for (size_t i = 0; i < gm->count; i++) ncpu += gm->runs[i].device == TT_DEVICE_CPU;
    CHECK_MSG(ncpu == cm.count, "%zu CPU runs with --device gpu, %zu without", ncpu, cm.count);
    for (size_t i = 0; i < cm.count && i < gm->count; i++)
        CHECK(memcmp(&cm.runs[i], &gm->runs[i], sizeof cm.runs[i]) == 0);
    /* every GPU-able CPU run has its GPU copy with the same tables */
    size_t expect_gpu = 0;
    for (size_t i = 0; i < cm.count; i++) {
        const bench_run *c = &cm.runs[i];
        if (!is_gpu_config(&c->build)) continue;
        expect_gpu++;
        bench_run key = *c;
        key.device = TT_DEVICE_GPU;
        const bench_run *g = bench_matrix_find(gm, &key);
        CHECK_MSG(g && (g->tables & c->tables) == c->tables && !g->heatmap,
                  "no GPU copy of CPU run %zu (%s %s)", i, c->build.accel,
                  bench_traversal_name(&c->build));
        /* Feldmann's GPU rows of Tables 1 and 2 used the ordered traversal */
        if (strcmp(c->build.accel, "rtree") == 0 && (c->tables & (BENCH_F1 | BENCH_F2)) &&
            c->build.rtree.traversal == TT_RTREE_STACKLESS) {
            key.build.rtree.traversal = TT_RTREE_ORDERED;
            const bench_run *o = bench_matrix_find(gm, &key);
            CHECK_MSG(o && (o->tables & c->tables & (BENCH_F1 | BENCH_F2)),
                      "no ordered GPU run of Table 1/2's %s",
                      bench_strategy_name(c->build.rtree.strategy));
            key.device = TT_DEVICE_CPU;
            if (!bench_matrix_find(&cm, &key)) expect_gpu++;
        }
    }
    size_t ngpu = gm->count - ncpu;
    CHECK_MSG(ngpu == expect_gpu, "%zu GPU runs, expected %zu", ngpu, expect_gpu);
    for (size_t i = 0; i < gm->count; i++)
        if (gm->runs[i].device == TT_DEVICE_GPU)
            CHECK_MSG(is_gpu_config(&gm->runs[i].build), "GPU run %zu: %s %s", i,
                      gm->runs[i].build.accel, bench_traversal_name(&gm->runs[i].build));
    CHECK(expect_gpu > 10); /* all tables: F1 x 5, F3, H1, H3 ... */
    bench_matrix_free(&cm);
    bench_options_free(&cpu_o);
    bench_options_free(&gpu_o);
}

/* Distinct fabricated times: CPU run i takes 1 + i s, GPU run i 0.001 (i + 1) s. */
static double fake_time(const bench_run *run, size_t i)
{
    return run->device == TT_DEVICE_GPU ? 0.001 * (double)(i + 1) : 1.0 + (double)i;
}

static void fabricate(const bench_matrix *m, bench_results *res)
{
    memset(res, 0, sizeof *res);
    res->items = calloc(m->count, sizeof *res->items);
    if (!res->items) exit(1);
    res->count = m->count;
    res->threads = 1;
    for (size_t i = 0; i < m->count; i++) {
        bench_result *r = &res->items[i];
        r->run = &m->runs[i];
        r->ok = 1;
        r->repeats = 1;
        r->triangles = 69451;
        tt_render_summary *s = &r->summary;
        s->width = m->runs[i].size.width;
        s->height = m->runs[i].size.height;
        s->primary_rays = (uint64_t)s->width * s->height;
        s->trace_s = s->trace_median_s = fake_time(&m->runs[i], i);
        s->device = m->runs[i].device;
        if (s->device == TT_DEVICE_GPU) {
            strcpy(s->device_name, "Test GPU 9000");
            s->upload_s = 0.25;
            s->download_s = 0.125;
        }
    }
}

static char *slurp(const char *path)
{
    long n = 0;
    unsigned char *t = tt_test_read_file(path, &n);
    return (char *)t;
}

/* Lines of text (after the first `skip`) ending with suffix / containing s. */
static size_t count_lines(const char *text, int skip, const char *suffix, const char *contains)
{
    size_t n = 0;
    const size_t ls = suffix ? strlen(suffix) : 0;
    for (const char *line = text; line && *line; skip--) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) : strlen(line);
        if (skip <= 0) {
            if (suffix && len >= ls && strncmp(line + len - ls, suffix, ls) == 0) n++;
            if (contains) {
                const char *hit = strstr(line, contains);
                n += hit && hit < line + len;
            }
        }
        line = end ? end + 1 : NULL;
    }
    return n;
}

/* The time cell of run `build` on `device` as the report writes it. */
static void cell_of(const bench_matrix *m, tt_build_options build, bench_rays rays,
                    bench_size size, tt_device device, char *out, size_t n)
{
    bench_run key;
    memset(&key, 0, sizeof key);
    key.size = size;
    key.build = build;
    key.rays = rays;
    key.device = device;
    const bench_run *run = bench_matrix_find(m, &key);
    if (!run) {
        snprintf(out, n, "(missing)");
        return;
    }
    bench_format_seconds(out, n, fake_time(run, (size_t)(run - m->runs)));
}

static void test_outputs(tt_context *ctx, const bench_scene_list *sl, const bench_matrix *m)
{
    bench_results res;
    fabricate(m, &res);
    bench_options o;
    CHECK(parse("--device", "gpu", &o) == 0);
    o.rtree_size = o.kd_size = (bench_size){64, 48};
    o.tables = BENCH_ALL_TABLES;

    /* CSV: the device columns */
    const char *csv = tt_cli_tmp("results.csv");
    CHECK(bench_write_csv(csv, sl, m, &res, stderr) == 0);
    char *text = slurp(csv);
    CHECK(text && strstr(text, ",device,device_name,upload_s,download_s\n"));
    size_t gpu_rows = count_lines(text, 1, ",gpu,Test GPU 9000,0.25,0.125", NULL);
    size_t cpu_rows = count_lines(text, 1, ",cpu,,,", NULL);
    size_t ngpu = 0;
    for (size_t i = 0; i < m->count; i++) ngpu += m->runs[i].device == TT_DEVICE_GPU;
    CHECK_MSG(gpu_rows == ngpu && cpu_rows == m->count - ngpu, "csv: %zu gpu rows (%zu), %zu cpu "
              "rows (%zu)", gpu_rows, ngpu, cpu_rows, m->count - ngpu);
    free(text);

    /* report.md: the GPU section */
    const char *dir = tt_cli_tmp("out");
    CHECK(bench_mkdirs(dir) == 0);
    CHECK(bench_write_report(ctx, dir, &o, sl, m, &res, stderr) == 0);
    char path[4200];
    snprintf(path, sizeof path, "%s/report.md", dir);
    text = slurp(path);
    CHECK_MSG(text && strstr(text, "## GPU (CUDA)\n") && strstr(text, "Device: Test GPU 9000."),
              "no GPU section");
    if (!text) return;
    const bench_size sz = o.rtree_size;
    char want[512], a[32], b[32], c[32], d[32], e[32];
    /* Table 1, ordered row: the five strategies' GPU ordered runs */
    const tt_rtree_strategy st[5] = {TT_RTREE_MIN_VOLUME, TT_RTREE_MIN_SURFACE,
                                     TT_RTREE_MIN_OVERLAP, TT_RTREE_RSTAR, TT_RTREE_RSTAR_SURFACE};
    char cells[5][32];
    for (int i = 0; i < 5; i++)
        cell_of(m, bench_rtree_build(st[i], 1, TT_RTREE_ORDERED), BENCH_PRIMARY_SHADOW, sz,
                TT_DEVICE_GPU, cells[i], sizeof cells[i]);
    snprintf(want, sizeof want, "| bunny | main | GPU ordered | %s | %s | %s | %s | %s |\n",
             cells[0], cells[1], cells[2], cells[3], cells[4]);
    CHECK_MSG(strstr(text, want), "report lacks '%s'", want);
    /* the paper's GPU row (ms): 67 63 - 71 59 */
    CHECK_MSG(strstr(text, "| Bunny | | paper GPU | 0.0670 s | 0.0630 s | - | 0.0710 s | 0.0590 s |"),
              "no paper GPU row for Table 1");
    /* Table 3: GPU stackless, GPU ordered, CPU stackless, CPU ordered */
    tt_build_options sl_b = bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_STACKLESS);
    tt_build_options or_b = bench_rtree_build(TT_RTREE_RSTAR_SURFACE, 1, TT_RTREE_ORDERED);
    cell_of(m, sl_b, BENCH_PRIMARY_SHADOW, sz, TT_DEVICE_GPU, a, sizeof a);
    cell_of(m, or_b, BENCH_PRIMARY_SHADOW, sz, TT_DEVICE_GPU, b, sizeof b);
    cell_of(m, sl_b, BENCH_PRIMARY_SHADOW, sz, TT_DEVICE_CPU, c, sizeof c);
    cell_of(m, or_b, BENCH_PRIMARY_SHADOW, sz, TT_DEVICE_CPU, d, sizeof d);
    snprintf(want, sizeof want, "| bunny | main | %s | %s | %s | %s |", a, b, c, d);
    CHECK_MSG(strstr(text, want), "report lacks Table 3's GPU row '%s'", want);
    CHECK(strstr(text, "| 0.0650 s | 0.0590 s |\n")); /* paper GPU stackless, ordered */
    /* Havran & Bittner Table 1 on the GPU: HTR, SLTR */
    tt_build_options def;
    tt_build_options_default(&def);
    cell_of(m, bench_kdtree_build(TT_KD_NLOGN, -1, TT_KD_HTR), BENCH_PRIMARY, sz, TT_DEVICE_GPU,
            a, sizeof a);
    cell_of(m, bench_kdtree_build(TT_KD_NLOGN, TT_KD_DMIN_BOXES, TT_KD_SLTR), BENCH_PRIMARY, sz,
            TT_DEVICE_GPU, e, sizeof e);
    snprintf(want, sizeof want, "| bunny | main | %s | %s |", a, e);
    CHECK_MSG(strstr(text, want), "report lacks the GPU kd-tree row '%s'", want);
    /* one line per GPU run in the last table, each with the upload time */
    const char *all = strstr(text, "### Every GPU run");
    CHECK(all != NULL);
    size_t lines = all ? count_lines(all, 0, NULL, "| 64x48 |") : 0;
    CHECK(all && count_lines(all, 0, NULL, "| 0.250 s |") == lines);
    CHECK_MSG(lines == ngpu, "%zu GPU run lines with the upload time, expected %zu", lines, ngpu);
    /* the agreement table tells GPU rows apart (none here: nothing compared) */
    free(text);
    free(res.items);
    bench_options_free(&o);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    test_options();
    bench_scene_list sl = one_scene();
    bench_matrix m;
    test_matrix(&sl, &m);
    test_outputs(ctx, &sl, &m);
    bench_matrix_free(&m);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
