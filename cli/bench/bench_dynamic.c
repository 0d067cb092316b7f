/* Table D: dynamic scenes, frame by frame (--only D). For each selected
 * scene, from its first view at 512 x 512 (dynembree's size), three
 * sequences:
 *   deform  every vertex moves each frame (dynembree's wave along x),
 *   edits   1% of the live triangles removed and 1% added each frame
 *           (copies of random triangles of the first frame, shifted in x
 *           by up to 10% of the diagonal, as dynembree replaces them),
 *   growth  the scene built by inserting objects one after another (the
 *           file's triangles in load order, cut into `frames` pieces, at
 *           most 50), traced after each;
 * treetrace's default R-tree updated in place by tt_accel_update, against
 * Embree in the same run (bench_dynamic_embree.c) with REFIT (deform
 * only), LOW and MEDIUM commits of the same geometry. Per frame: update /
 * commit time, primary and shadow trace time (the same shadow rays for
 * both engines: those of treetrace's primary hits), treetrace's SAH cost
 * against a fresh build of the same frame (every 10th frame and the last),
 * memory; the update's process CPU time beside its wall time (the machine
 * may be shared: CPU time is what an engine spent on all its threads, so
 * its ratio between the engines survives the load). dynamic.csv has every frame (its columns: /work/notes/dyn-csv.md
 * in the project's notes, and the header below); dynamic.md the table. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench.h"
#include "bench/bench_dynamic.h"

#define DYN_W 512u
#define DYN_FRESH_EVERY 10

typedef struct dyn_row {
    const char *scene, *mode, *engine;
    int frame;
    size_t triangles;
    double update_ms, primary_ms, shadow_ms;
    double sah, fresh_sah, fresh_trace_ms; /* < 0: not measured */
    double memory;
    double refit, removed, inserted; /* < 0: not treetrace */
    const char *layout;
    double compactions; /* the slack layout's, so far */
    double update_cpu_ms; /* process CPU time of the update / commit */
} dyn_row;

static void num(FILE *f, double v, const char *fmt)
{
    fputc(',', f);
    if (v >= 0.0) fprintf(f, fmt, v);
}

static void write_row(FILE *f, const dyn_row *r)
{
    fprintf(f, "%s,%s,%s,%d,%zu", r->scene, r->mode, r->engine, r->frame, r->triangles);
    num(f, r->update_ms, "%.4f");
    num(f, r->primary_ms, "%.4f");
    num(f, r->shadow_ms, "%.4f");
    num(f, r->primary_ms + r->shadow_ms, "%.4f");
    num(f, r->sah, "%.4f");
    num(f, r->fresh_sah, "%.4f");
    num(f, r->sah >= 0 && r->fresh_sah > 0 ? r->sah / r->fresh_sah : -1.0, "%.4f");
    num(f, r->fresh_trace_ms, "%.4f");
    num(f, r->fresh_trace_ms > 0 ? (r->primary_ms + r->shadow_ms) / r->fresh_trace_ms : -1.0,
        "%.4f");
    num(f, r->memory, "%.0f");
    num(f, r->refit, "%.0f");
    num(f, r->removed, "%.0f");
    num(f, r->inserted, "%.0f");
    fprintf(f, ",%s", r->layout ? r->layout : "");
    num(f, r->update_cpu_ms, "%.4f");
    fputc('\n', f);
}

static const char csv_header[] =
    "scene,mode,engine,frame,triangles,update_ms,primary_ms,shadow_ms,trace_ms,sah,fresh_sah,"
    "sah_ratio,fresh_trace_ms,trace_ratio,memory_bytes,refit,removed,inserted,layout,update_cpu_ms\n";

/* What the report keeps of a sequence: means over the frames, the last
 * frame's drift. */
typedef struct dyn_sum {
    const char *scene, *mode, *engine;
    int frames;
    double update_ms, trace_ms, last_trace_ms, last_fresh_trace_ms, last_sah_ratio, memory;
    double update_cpu_ms;
} dyn_sum;

typedef struct dyn_run {
    tt_context *ctx;
    FILE *csv;
    dyn_sum *sums;
    size_t nsums, capsums;
    int threads, frames;
    FILE *err;
} dyn_run;

static dyn_sum *sum_open(dyn_run *r, const char *scene, const char *mode, const char *engine)
{
    if (r->nsums == r->capsums) {
        size_t cap = r->capsums ? 2 * r->capsums : 32;
        dyn_sum *s = realloc(r->sums, cap * sizeof *s);
        if (!s) return NULL;
        r->sums = s;
        r->capsums = cap;
    }
    dyn_sum *s = &r->sums[r->nsums++];
    memset(s, 0, sizeof *s);
    s->scene = scene;
    s->mode = mode;
    s->engine = engine;
    s->last_sah_ratio = s->last_fresh_trace_ms = -1.0;
    return s;
}

static void sum_add(dyn_sum *s, const dyn_row *row)
{
    if (!s || row->frame == 0) return;
    s->frames++;
    s->update_ms += row->update_ms;
    s->update_cpu_ms += row->update_cpu_ms > 0 ? row->update_cpu_ms : 0.0;
    s->trace_ms += row->primary_ms + row->shadow_ms;
    s->last_trace_ms = row->primary_ms + row->shadow_ms;
    if (row->fresh_sah > 0 && row->sah >= 0) s->last_sah_ratio = row->sah / row->fresh_sah;
    if (row->fresh_trace_ms > 0) s->last_fresh_trace_ms = row->fresh_trace_ms;
    s->memory = row->memory;
}

/* This process's CPU time (all threads), ms. */
static double cpu_ms(void)
{
    struct timespec t;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0.0;
    return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

/* The frame's rays: primary W x W, and the shadow rays of treetrace's hits. */
typedef struct dyn_rays {
    tt_camera cam;
    tt_ray *primary, *shadow;
    tt_hit *hits;
    uint8_t *occ;
    size_t n, m;
} dyn_rays;

static tt_status trace_tt(const tt_accel *a, const tt_scene *sc, dyn_rays *R, double *pms,
                          double *sms)
{
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    bo.image_width = DYN_W;
    double t0 = bench_now();
    tt_status st = tt_intersect(a, R->primary, R->n, R->hits, NULL, &bo);
    *pms = 1e3 * (bench_now() - t0);
    if (st != TT_OK) return st;
    R->m = 0;
    for (size_t i = 0; i < R->n; i++)
        if (R->hits[i].prim != TT_INVALID_ID &&
            tt_shadow_ray(sc, &R->cam, &R->primary[i], &R->hits[i], &R->shadow[R->m]))
            R->m++;
    t0 = bench_now();
    st = tt_occluded(a, R->shadow, R->m, R->occ, NULL, NULL);
    *sms = 1e3 * (bench_now() - t0);
    return st;
}

static void stat_pick(void *user, const char *key, double v)
{
    if (strcmp(key, "sah_cost") == 0) *(double *)user = v;
}

static double sah_of(const tt_accel *a)
{
    double s = -1.0;
    tt_accel_statistics(a, stat_pick, &s);
    return s;
}

static void stat_update(void *user, const char *key, double v)
{
    dyn_row *r = user;
    if (strcmp(key, "update_refit") == 0) r->refit = v;
    else if (strcmp(key, "update_removed") == 0) r->removed = v;
    else if (strcmp(key, "update_inserted") == 0) r->inserted = v;
    else if (strcmp(key, "update_compactions") == 0) r->compactions = v;
}

/* A fresh default build of the frame: its SAH cost and trace time. */
static tt_status fresh(dyn_run *r, const tt_scene *sc, dyn_rays *R, dyn_row *row)
{
    tt_accel *f;
    tt_status st = tt_accel_build(r->ctx, sc, NULL, &f);
    if (st != TT_OK) return st;
    double p, s;
    st = trace_tt(f, sc, R, &p, &s);
    row->fresh_sah = sah_of(f);
    row->fresh_trace_ms = p + s;
    tt_accel_destroy(f);
    return st;
}

/* The scene's triangles as one soup (Embree's mesh). */
static float *soup(const tt_scene *sc, float *buf)
{
    const size_t T = tt_scene_triangle_count(sc);
    float *b = realloc(buf, (T ? T : 1) * 9 * sizeof(float));
    if (!b) return NULL;
    for (size_t i = 0; i < T; i++) tt_scene_triangle(sc, i, b + 9 * i);
    return b;
}

typedef enum { DEFORM = 0, EDITS = 1, GROWTH = 2 } dyn_mode;
static const char *const mode_name[] = {"deform", "edits", "growth"};
static const char *const emb_name[] = {"embree-refit", "embree-low", "embree-medium"};

/* Frame f's edit of scene sc (treetrace's copy); `base` the first frame's
 * vertices (deform) or triangles (edits); rng state in *seed. */
static tt_status edit_frame(dyn_mode mode, tt_scene *sc, int f, const float *base,
                            size_t base_count, float diag, float *pos, uint32_t *ids,
                            float *tri, unsigned *seed)
{
    if (mode == DEFORM) {
        for (size_t v = 0; v < base_count; v++) {
            const float *p = base + 3 * v;
            const float w = 0.002f * diag * sinf(0.7f * (float)f + 40.0f * p[1] / diag);
            pos[3 * v] = p[0] + w * (float)f * 0.2f;
            pos[3 * v + 1] = p[1];
            pos[3 * v + 2] = p[2];
        }
        return tt_scene_move_vertices(sc, NULL, pos, base_count);
    }
    const size_t T = tt_scene_triangle_count(sc), k = tt_scene_live_triangle_count(sc) / 100;
    size_t got = 0;
    for (size_t tries = 0; got < k && tries < 100 * k; tries++) {
        const uint32_t id = (uint32_t)(rand_r(seed) % (int)T);
        if (!tt_scene_triangle_alive(sc, id)) continue;
        int dup = 0;
        for (size_t j = got; j-- > 0 && !dup;) dup = ids[j] == id;
        if (!dup) ids[got++] = id;
    }
    tt_status st = tt_scene_remove_triangles(sc, ids, got);
    if (st != TT_OK) return st;
    for (size_t j = 0; j < got; j++) {
        const size_t s = (size_t)rand_r(seed) % base_count;
        const float d = (float)(rand_r(seed) % 100) / 100.0f * 0.1f * diag;
        for (int q = 0; q < 9; q++) tri[9 * j + q] = base[9 * s + q] + (q % 3 == 0 ? d : 0.0f);
    }
    return tt_scene_add_triangles(sc, tri, got, NULL);
}

static int run_sequence(dyn_run *r, const bench_scene *bs, dyn_mode mode, dyn_rays *R)
{
    tt_context *ctx = r->ctx;
    tt_scene *sc = NULL, *full = NULL;
    tt_status st = tt_scene_load(ctx, bs->path, &full);
    if (st != TT_OK) {
        fprintf(r->err, "treetrace bench D: %s\n", tt_context_last_error(ctx));
        return 1;
    }
    const size_t T0 = tt_scene_triangle_count(full), V0 = tt_scene_vertex_count(full);
    float lo[3], hi[3];
    tt_scene_bounds(full, lo, hi);
    const float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                             (hi[2] - lo[2]) * (hi[2] - lo[2]));
    float *all_tri = soup(full, NULL), *base = NULL, *pos = NULL, *tri = NULL, *emb_buf = NULL;
    uint32_t *ids = NULL;
    size_t base_count = 0;
    int rc = 1, frames = r->frames, pieces = 0;
    if (mode == DEFORM) {
        base = malloc(V0 * 3 * sizeof(float));
        pos = malloc(V0 * 3 * sizeof(float));
        for (size_t v = 0; base && v < V0; v++) tt_scene_vertex(full, v, base + 3 * v);
        base_count = V0;
        sc = full;
        full = NULL;
    } else if (mode == EDITS) {
        base = all_tri;
        base_count = T0;
        ids = malloc((T0 / 100 + 1) * sizeof *ids);
        tri = malloc((T0 / 100 + 1) * 9 * sizeof(float));
        sc = full;
        full = NULL;
    } else {
        pieces = frames < 50 ? frames : 50;
        frames = pieces;
        st = tt_scene_create(ctx, NULL, 0, NULL, 0, &sc);
    }
    if (!all_tri || (mode == DEFORM && (!base || !pos)) || (mode == EDITS && (!ids || !tri)) ||
        st != TT_OK) {
        fprintf(r->err, "treetrace bench D: out of memory\n");
        goto done;
    }
    /* treetrace: the default structure, updated in place */
    tt_accel *a = NULL;
    double t0 = bench_now();
    st = tt_accel_build(ctx, sc, NULL, &a);
    double build_ms = 1e3 * (bench_now() - t0);
    if (st != TT_OK) goto fail_tt;
    dyn_sum *sum_tt = sum_open(r, bs->name, mode_name[mode], "treetrace");
    /* Embree: one device per build quality, the same geometry */
    bench_emb *emb[3] = {NULL, NULL, NULL};
    dyn_sum *sum_emb[3] = {NULL, NULL, NULL};
    double emb_first[3] = {0, 0, 0};
    for (int q = mode == DEFORM ? 0 : 1; q < 3; q++) {
        emb[q] = bench_emb_create(q, r->threads);
        if (!emb[q]) continue;
        if (mode != GROWTH) {
            emb_buf = soup(sc, emb_buf);
            bench_emb_set(emb[q], emb_buf, tt_scene_triangle_count(sc));
        }
        emb_first[q] = bench_emb_commit(emb[q]);
        sum_emb[q] = sum_open(r, bs->name, mode_name[mode], emb_name[q]);
    }
    unsigned seed = 1;
    double compactions = 0;
    for (int f = 0; f <= frames; f++) {
        double upd_ms = build_ms, upd_cpu = -1.0;
        if (f > 0) {
            if (mode == GROWTH) {
                const size_t a0 = T0 * (size_t)(f - 1) / (size_t)pieces;
                const size_t a1 = T0 * (size_t)f / (size_t)pieces;
                st = tt_scene_add_triangles(sc, all_tri + 9 * a0, a1 - a0, NULL);
                for (int q = 1; q < 3 && st == TT_OK; q++)
                    if (emb[q]) bench_emb_add_object(emb[q], all_tri + 9 * a0, a1 - a0);
            } else {
                st = edit_frame(mode, sc, f, base, base_count, diag, pos, ids, tri, &seed);
            }
            if (st != TT_OK) goto fail_tt;
            const double c0 = cpu_ms();
            t0 = bench_now();
            st = tt_accel_update(a);
            upd_ms = 1e3 * (bench_now() - t0);
            upd_cpu = cpu_ms() - c0;
            if (st != TT_OK) goto fail_tt;
        }
        dyn_row row = {bs->name, mode_name[mode], "treetrace", f, tt_scene_live_triangle_count(sc),
                       upd_ms, 0, 0, -1, -1, -1, 0, -1, -1, -1, NULL, 0, upd_cpu};
        st = trace_tt(a, sc, R, &row.primary_ms, &row.shadow_ms);
        if (st != TT_OK) goto fail_tt;
        row.sah = sah_of(a);
        row.memory = (double)tt_accel_memory_bytes(a);
        if (f > 0) {
            row.refit = row.removed = row.inserted = row.compactions = 0;
            tt_accel_statistics(a, stat_update, &row);
            /* inplace: only the touched records and blocks were written;
             * compact: the slack layout was rewritten whole (the first
             * update, a change of height, or fragmentation) */
            row.layout = row.compactions > compactions ? "compact" : "inplace";
            compactions = row.compactions;
        }
        if (f == frames || f % DYN_FRESH_EVERY == 0) {
            st = fresh(r, sc, R, &row);
            if (st != TT_OK) goto fail_tt;
        }
        write_row(r->csv, &row);
        sum_add(sum_tt, &row);
        /* Embree on the same frame (its shadow rays: the ones just made) */
        if (mode != GROWTH && f > 0) emb_buf = soup(sc, emb_buf);
        for (int q = 0; q < 3; q++) {
            if (!emb[q]) continue;
            dyn_row er = {bs->name, mode_name[mode], emb_name[q], f,
                          tt_scene_live_triangle_count(sc), emb_first[q], 0, 0, -1, -1, -1, 0,
                          -1, -1, -1, NULL, 0, -1.0};
            if (f > 0) {
                if (mode != GROWTH) bench_emb_set(emb[q], emb_buf, tt_scene_triangle_count(sc));
                const double c0 = cpu_ms();
                er.update_ms = 1e3 * bench_emb_commit(emb[q]);
                er.update_cpu_ms = cpu_ms() - c0;
            } else {
                er.update_ms = 1e3 * emb_first[q];
            }
            double p, s;
            bench_emb_trace(emb[q], R->primary, R->n, R->shadow, R->m, &p, &s);
            er.primary_ms = 1e3 * p;
            er.shadow_ms = 1e3 * s;
            er.memory = (double)bench_emb_memory(emb[q]);
            write_row(r->csv, &er);
            sum_add(sum_emb[q], &er);
        }
        fflush(r->csv);
    }
    rc = 0;
fail_tt:
    if (rc) fprintf(r->err, "treetrace bench D: %s %s: %s\n", bs->name, mode_name[mode],
                    tt_context_last_error(ctx));
    for (int q = 0; q < 3; q++) bench_emb_destroy(emb[q]);
    tt_accel_destroy(a);
done:
    if (base != all_tri) free(base);
    free(all_tri);
    free(pos);
    free(tri);
    free(ids);
    free(emb_buf);
    tt_scene_destroy(sc);
    tt_scene_destroy(full);
    return rc;
}

static void write_report(dyn_run *r, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) return;
    fprintf(f, "# Table D: dynamic scenes\n\n"
               "%d frames a sequence (growth: at most 50 objects), %ux%u primary rays + their "
               "shadow rays, %d threads; treetrace: the default R-tree (SAH, compact layout) "
               "updated in place by tt_accel_update; Embree 3 with RTC_SCENE_FLAG_DYNAMIC at "
               "each build quality, timed around rtcCommitScene (wall, and the process's CPU time on all "
               "threads, which a shared machine disturbs less). Means over the frames; "
               "`last` is the last frame, `fresh` a new default build of that frame. Every "
               "frame: dynamic.csv.\n\n",
            r->frames, DYN_W, DYN_W, r->threads);
    fprintf(f, "| scene | sequence | engine | update / commit ms | vs Embree LOW | vs Embree "
               "REFIT | CPU ms | CPU vs LOW | CPU vs REFIT | trace ms | last trace / fresh | "
               "last SAH / fresh | memory MB |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < r->nsums; i++) {
        const dyn_sum *s = &r->sums[i];
        if (!s->frames) continue;
        double low = -1, refit = -1, low_cpu = -1, refit_cpu = -1;
        for (size_t j = 0; j < r->nsums; j++) {
            const dyn_sum *e = &r->sums[j];
            if (strcmp(e->scene, s->scene) || strcmp(e->mode, s->mode) || !e->frames) continue;
            if (!strcmp(e->engine, "embree-low")) {
                low = e->update_ms / e->frames;
                low_cpu = e->update_cpu_ms / e->frames;
            }
            if (!strcmp(e->engine, "embree-refit")) {
                refit = e->update_ms / e->frames;
                refit_cpu = e->update_cpu_ms / e->frames;
            }
        }
        const double upd = s->update_ms / s->frames;
        fprintf(f, "| %s | %s | %s | %.3f | ", s->scene, s->mode, s->engine, upd);
        if (low > 0) fprintf(f, "%.2fx", upd / low);
        fprintf(f, " | ");
        if (refit > 0) fprintf(f, "%.2fx", upd / refit);
        const double cpu = s->update_cpu_ms / s->frames;
        fprintf(f, " | %.3f | ", cpu);
        if (low_cpu > 0) fprintf(f, "%.2fx", cpu / low_cpu);
        fprintf(f, " | ");
        if (refit_cpu > 0) fprintf(f, "%.2fx", cpu / refit_cpu);
        fprintf(f, " | %.2f | ", s->trace_ms / s->frames);
        if (s->last_fresh_trace_ms > 0) fprintf(f, "%.2fx", s->last_trace_ms / s->last_fresh_trace_ms);
        fprintf(f, " | ");
        if (s->last_sah_ratio > 0) fprintf(f, "%.3f", s->last_sah_ratio);
        fprintf(f, " | %.1f |\n", s->memory / 1e6);
    }
#ifndef TT_HAVE_EMBREE
    fprintf(f, "\nEmbree is not in this build (install libembree-dev and rebuild): its rows are "
               "missing.\n");
#endif
    fclose(f);
}

int bench_dynamic_run(tt_context *ctx, const bench_options *o, const bench_scene_list *scenes,
                      const char *out, FILE *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/dynamic.csv", out);
    dyn_run r = {ctx, fopen(path, "w"), NULL, 0, 0, tt_context_threads(ctx), o->frames, err};
    if (!r.csv) {
        fprintf(err, "treetrace bench: cannot write %s\n", path);
        return 1;
    }
    fputs(csv_header, r.csv);
    int rc = 0;
    for (size_t i = 0; i < scenes->count && rc == 0; i++) {
        const bench_scene *bs = &scenes->items[i];
        if (!bs->view_count) continue;
        dyn_rays R = {bs->views[0].camera, NULL, NULL, NULL, NULL, (size_t)DYN_W * DYN_W, 0};
        R.primary = malloc(R.n * sizeof *R.primary);
        R.shadow = malloc(R.n * sizeof *R.shadow);
        R.hits = malloc(R.n * sizeof *R.hits);
        R.occ = malloc(R.n);
        if (!R.primary || !R.shadow || !R.hits || !R.occ ||
            tt_camera_rays(&R.cam, DYN_W, DYN_W, R.primary) != TT_OK) {
            fprintf(err, "treetrace bench D: %s: cannot make the view's rays\n", bs->name);
            rc = 1;
        }
        for (int m = 0; m < 3 && rc == 0; m++) {
            fprintf(err, "treetrace bench D: %s %s\n", bs->name, mode_name[m]);
            rc = run_sequence(&r, bs, (dyn_mode)m, &R);
        }
        free(R.primary);
        free(R.shadow);
        free(R.hits);
        free(R.occ);
    }
    fclose(r.csv);
    snprintf(path, sizeof path, "%s/dynamic.md", out);
    write_report(&r, path);
    free(r.sums);
    if (rc == 0) fprintf(err, "treetrace bench: wrote %s/dynamic.csv and %s/dynamic.md\n", out, out);
    return rc;
}
