/* Runs the matrix: each scene is loaded once, each structure built once and
 * rendered for every run that uses it. A render is a warm-up call (one fast
 * pass plus the counting pass: per-ray statistics, the hit buffer and the
 * heatmap come from it) and a timed call of K fast passes, whose median is
 * reported. Embree is built and rendered first in each scene so that every
 * other run can be compared with its hit buffer as soon as it is made. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"

typedef struct scene_state {
    tt_scene *scene;
    tt_accel *bruteforce; /* built when a run first disagrees with Embree */
    double load_s;
    /* Embree's hit buffer per run index (NULL for non-Embree runs). */
    uint8_t **embree_hits;
} scene_state;

static int accel_available(const char *name)
{
    for (const char *const *n = tt_accel_names(); *n; n++)
        if (strcmp(*n, name) == 0) return 1;
    return 0;
}

double bench_per_ray(uint64_t count, uint64_t rays)
{
    return rays ? (double)count / (double)rays : 0.0;
}

double bench_time_s(const bench_result *r) { return r->summary.trace_median_s; }

double bench_mrays(const bench_result *r)
{
    double t = bench_time_s(r);
    uint64_t rays = r->summary.primary_rays + r->summary.shadow_rays;
    return t > 0.0 ? (double)rays / t * 1e-6 : 0.0;
}

static void fail(bench_result *r, const char *fmt, const char *what)
{
    r->ok = 0;
    snprintf(r->error, sizeof r->error, fmt, what);
}

/* Collects the statistics the report needs from tt_accel_statistics. */
static void on_stat(void *user, const char *key, double value)
{
    bench_accel_stats *s = user;
    /* N_B: the kd-tree's augmented nodes, under whichever of these names */
    if (strcmp(key, "N_B") == 0 || strcmp(key, "augmented_nodes") == 0) s->boxes = value;
    if (strcmp(key, "nodes") == 0) s->nodes = value;
    if (strcmp(key, "height") == 0 || strcmp(key, "depth_max") == 0) s->height = value;
    size_t len = strlen(s->all);
    if (len + 1 < sizeof s->all)
        snprintf(s->all + len, sizeof s->all - len, "%s%s=%.10g", len ? ";" : "", key, value);
}

static void heatmap_path(char *buf, size_t size, const char *out_dir, const bench_scene *s,
                         const bench_run *run)
{
    char extra[32] = "";
    if (strcmp(run->build.accel, "kdtree") == 0 && run->build.kdtree.dmin >= 0)
        snprintf(extra, sizeof extra, "-dmin%d", run->build.kdtree.dmin);
    snprintf(buf, size, "%s/heatmaps/%s-%s-%s-%s%s-%ux%u.png", out_dir, s->name,
             s->views[run->view].name, run->build.accel, bench_traversal_name(&run->build), extra,
             run->size.width, run->size.height);
}

/* The index of the Embree run this run is compared with; -1 if none. */
static long embree_partner(const bench_matrix *m, const bench_run *run)
{
    if (strcmp(run->build.accel, "embree") == 0) return -1;
    bench_run e = *run;
    tt_build_options_default(&e.build);
    e.build.accel = "embree";
    e.device = TT_DEVICE_CPU; /* the reference for GPU runs too */
    const bench_run *found = bench_matrix_find(m, &e);
    return found ? (long)(found - m->runs) : -1;
}

/* Retraces the pixels where this run and Embree disagree with bruteforce,
 * so the report can say who was right. */
static void arbitrate(tt_context *ctx, scene_state *st, const bench_run *run, const tt_camera *cam,
                      const uint8_t *hits, const uint8_t *embree_hits, bench_result *r)
{
    if (!st->bruteforce) {
        tt_build_options b = bench_named_build("bruteforce");
        if (tt_accel_build(ctx, st->scene, &b, &st->bruteforce) != TT_OK) return;
    }
    uint64_t pixels = (uint64_t)run->size.width * run->size.height;
    for (uint64_t i = 0; i < pixels && r->arbitrated_pixels < BENCH_ARBITRATE_MAX; i++) {
        if (bench_pixel_agrees(hits + 12 * i, embree_hits + 12 * i)) continue;
        uint8_t truth[12];
        bench_bruteforce_pixel(st->scene, st->bruteforce, cam, run->size,
                               (uint32_t)(i % run->size.width), (uint32_t)(i / run->size.width),
                               run->rays == BENCH_PRIMARY_SHADOW, truth);
        r->arbitrated_pixels++;
        r->ours_match_bruteforce += (uint64_t)bench_pixel_agrees(hits + 12 * i, truth);
    }
}

static void render_one(tt_context *ctx, const bench_options *o, const bench_scene_list *scenes,
                       const bench_matrix *m, size_t idx, const tt_accel *accel, scene_state *st,
                       const char *out_dir, bench_results *res)
{
    const bench_run *run = &m->runs[idx];
    bench_result *r = &res->items[idx];
    const bench_scene *s = &scenes->items[run->scene];
    const tt_camera *cam = &s->views[run->view].camera;
    tt_render_options ro;
    tt_render_options_default(&ro);
    ro.width = run->size.width;
    ro.height = run->size.height;
    ro.shadows = run->rays == BENCH_PRIMARY_SHADOW;
    ro.device = run->device;

    /* warm-up: one fast pass + the counting pass, hits and per-pixel counts */
    ro.repeat = 1;
    ro.stats = 1;
    ro.keep_hits = 1;
    ro.keep_pixel_stats = run->heatmap;
    tt_render_result *warm = NULL;
    if (tt_render(ctx, st->scene, accel, cam, &ro, &warm) != TT_OK) {
        fail(r, "render: %s", tt_context_last_error(ctx));
        return;
    }
    const tt_render_summary *ws = tt_render_get_summary(warm);
    tt_render_summary stats = *ws;
    size_t hits_size = 0;
    const uint8_t *hits = tt_render_hits(warm, &hits_size);
    uint64_t pixels = (uint64_t)run->size.width * run->size.height;
    if (!hits || hits_size != pixels * 12) {
        tt_render_result_destroy(warm);
        fail(r, "%s", "render: no hit buffer of the expected size");
        return;
    }
    if (strcmp(run->build.accel, "embree") == 0) {
        st->embree_hits[idx] = malloc(hits_size);
        if (st->embree_hits[idx]) memcpy(st->embree_hits[idx], hits, hits_size);
    } else {
        long e = embree_partner(m, run);
        if (e >= 0 && st->embree_hits[e]) {
            r->embree = &res->items[e];
            r->compared_pixels = pixels;
            r->agree_pixels = bench_agree_count(hits, st->embree_hits[e], pixels);
            if (r->agree_pixels < pixels) arbitrate(ctx, st, run, cam, hits, st->embree_hits[e], r);
        }
    }
    if (run->heatmap) {
        const uint32_t *counts = tt_render_pixel_stats(warm, TT_HEAT_NODES);
        char path[4600];
        heatmap_path(path, sizeof path, out_dir, s, run);
        if (counts && tt_write_heatmap_png(ctx, path, counts, ro.width, ro.height) != TT_OK)
            fprintf(stderr, "treetrace bench: heatmap %s: %s\n", path, tt_context_last_error(ctx));
    }
    tt_render_result_destroy(warm);

    /* timed passes: as many as asked, but no more than the budget allows */
    double one = stats.trace_s > 0.0 ? stats.trace_s : 1e-3;
    int k = o->repeat;
    if ((double)k * one > o->budget_s) k = (int)(o->budget_s / one);
    if (k < 1) k = 1;
    ro.repeat = k;
    ro.stats = 0;
    ro.keep_hits = 0;
    ro.keep_pixel_stats = 0;
    tt_render_result *timed = NULL;
    if (tt_render(ctx, st->scene, accel, cam, &ro, &timed) != TT_OK) {
        fail(r, "render: %s", tt_context_last_error(ctx));
        return;
    }
    r->summary = *tt_render_get_summary(timed);
    tt_render_result_destroy(timed);
    r->summary.has_stats = stats.has_stats;
    r->summary.primary_stats = stats.primary_stats;
    r->summary.shadow_stats = stats.shadow_stats;
    r->repeats = k;
    r->ok = 1;
}

/* Builds one structure and renders every not yet done run of this scene
 * that uses the same build. */
static void build_and_render(tt_context *ctx, const bench_options *o,
                             const bench_scene_list *scenes, const bench_matrix *m, size_t first,
                             scene_state *st, char *done, const char *out_dir, bench_results *res,
                             bench_progress *prog)
{
    const bench_run *run0 = &m->runs[first];
    const bench_scene *s = &scenes->items[run0->scene];
    tt_accel *accel = NULL;
    tt_status bst = tt_accel_build(ctx, st->scene, &run0->build, &accel);
    char msg[256] = "";
    if (bst != TT_OK) snprintf(msg, sizeof msg, "build: %s", tt_context_last_error(ctx));
    bench_accel_stats as;
    memset(&as, 0, sizeof as);
    as.boxes = as.nodes = as.height = -1.0;
    if (accel) tt_accel_statistics(accel, on_stat, &as);
    for (size_t j = first; j < m->count; j++) {
        const bench_run *run = &m->runs[j];
        if (done[j] || run->scene != run0->scene || !bench_same_build(&run->build, &run0->build))
            continue;
        done[j] = 1;
        bench_result *r = &res->items[j];
        char what[512], opts[160];
        bench_options_string(&run->build, opts, sizeof opts);
        snprintf(what, sizeof what, "%s:%s %ux%u %s %s %s (%s)", s->name, s->views[run->view].name,
                 run->size.width, run->size.height, run->build.accel,
                 bench_traversal_name(&run->build), bench_rays_name(run->rays), opts);
        if (run->device == TT_DEVICE_GPU)
            snprintf(what + strlen(what), sizeof what - strlen(what), " on the GPU");
        if (!accel) {
            r->ok = 0;
            snprintf(r->error, sizeof r->error, "%s", msg);
        } else {
            r->load_s = st->load_s;
            r->triangles = tt_scene_triangle_count(st->scene);
            r->vertices = tt_scene_vertex_count(st->scene);
            r->build_s = tt_accel_build_seconds(accel);
            r->memory_bytes = tt_accel_memory_bytes(accel);
            r->isa = tt_accel_isa(accel);
            r->accel_stats = as;
            render_one(ctx, o, scenes, m, j, accel, st, out_dir, res);
        }
        if (!r->ok) fprintf(prog->f, "%s%s: %s\n", prog->tty ? "\r\033[K" : "", what, r->error);
        bench_progress_step(prog, what);
    }
    tt_accel_destroy(accel);
}

static int add_skipped(bench_results *res, const char *line)
{
    for (size_t i = 0; i < res->skipped_count; i++)
        if (strcmp(res->skipped[i], line) == 0) return 0;
    char **grown = realloc(res->skipped, (res->skipped_count + 1) * sizeof *grown);
    if (!grown) return -1;
    res->skipped = grown;
    res->skipped[res->skipped_count] = strdup(line);
    if (!res->skipped[res->skipped_count]) return -1;
    res->skipped_count++;
    return 0;
}

int bench_run_all(tt_context *ctx, const bench_options *o, const bench_scene_list *scenes,
                  const bench_matrix *m, const char *out_dir, bench_results *res, FILE *err)
{
    memset(res, 0, sizeof *res);
    res->items = calloc(m->count ? m->count : 1, sizeof *res->items);
    char *done = calloc(m->count ? m->count : 1, 1);
    if (!res->items || !done) {
        free(done);
        fprintf(err, "treetrace bench: out of memory\n");
        return -1;
    }
    res->count = m->count;
    res->threads = tt_context_threads(ctx) > 0 ? tt_context_threads(ctx) : omp_get_max_threads();
    size_t runnable = 0;
    for (size_t i = 0; i < m->count; i++) {
        res->items[i].run = &m->runs[i];
        const char *a = m->runs[i].build.accel;
        if (!accel_available(a)) {
            char line[160];
            snprintf(line, sizeof line, "%s: not in this build; its runs are left out", a);
            snprintf(res->items[i].error, sizeof res->items[i].error, "not in this build");
            done[i] = 1;
            if (add_skipped(res, line)) {
                free(done);
                return -1;
            }
        } else {
            runnable++;
        }
    }
    char hm[4200];
    snprintf(hm, sizeof hm, "%s/heatmaps", out_dir);
    if (o->heatmaps && bench_mkdirs(hm) != 0) {
        fprintf(err, "treetrace bench: cannot create %s\n", hm);
        free(done);
        return -1;
    }
    bench_progress prog;
    bench_progress_start(&prog, err, runnable);
    double t0 = bench_now();
    for (size_t si = 0; si < scenes->count; si++) {
        const bench_scene *s = &scenes->items[si];
        if (o->ranks > 1 && (int)(si % (size_t)o->ranks) != o->rank) {
            /* another MPI rank's scene (cli/mpi/mpi_bench.c gathers it) */
            for (size_t i = 0; i < m->count; i++)
                if (m->runs[i].scene == si) done[i] = 1;
            continue;
        }
        int any = 0;
        for (size_t i = 0; i < m->count; i++) any |= m->runs[i].scene == si && !done[i];
        if (!any) continue;
        scene_state st = {NULL, NULL, 0.0, calloc(m->count, sizeof(uint8_t *))};
        double t_load = bench_now();
        if (!st.embree_hits || tt_scene_load(ctx, s->path, &st.scene) != TT_OK) {
            const char *why = st.embree_hits ? tt_context_last_error(ctx) : "out of memory";
            fprintf(err, "%streetrace bench: scene %s: %s\n", prog.tty ? "\r\033[K" : "", s->name,
                    why);
            for (size_t i = 0; i < m->count; i++) {
                if (m->runs[i].scene != si || done[i]) continue;
                done[i] = 1;
                snprintf(res->items[i].error, sizeof res->items[i].error, "load: %s", why);
                bench_progress_step(&prog, s->name);
            }
            free(st.embree_hits);
            continue;
        }
        st.load_s = bench_now() - t_load;
        /* Embree first (every other run is compared with it), then the rest
         * in the matrix's order, one build at a time */
        for (int pass = 0; pass < 2; pass++) {
            for (size_t i = 0; i < m->count; i++) {
                if (done[i] || m->runs[i].scene != si) continue;
                int is_embree = strcmp(m->runs[i].build.accel, "embree") == 0;
                if (is_embree != (pass == 0)) continue;
                build_and_render(ctx, o, scenes, m, i, &st, done, out_dir, res, &prog);
            }
        }
        tt_accel_destroy(st.bruteforce);
        for (size_t i = 0; i < m->count; i++) free(st.embree_hits[i]);
        free(st.embree_hits);
        tt_scene_destroy(st.scene);
    }
    bench_progress_end(&prog);
    res->total_s = bench_now() - t0;
    free(done);
    return 0;
}

void bench_results_free(bench_results *r)
{
    for (size_t i = 0; i < r->skipped_count; i++) free(r->skipped[i]);
    free(r->skipped);
    free(r->items);
    memset(r, 0, sizeof *r);
}
