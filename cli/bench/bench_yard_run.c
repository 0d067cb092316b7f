/* The engine table's measurements (bench_yard.h), one view at a time:
 *   1. builds: Embree (default flags, robust) and each structure, each the
 *      minimum of o->builds builds, the last one kept;
 *   2. answers (untimed, also the warm-up): the default R-tree's primary
 *      hits give the shadow and AO rays every side traces; every structure's
 *      answers are compared with Embree's, with the default R-tree's and, on
 *      a sample, with bruteforce's; packets off and on must answer as auto;
 *      a counting pass gives per-ray node and triangle counts;
 *   3. timing: o->rounds interleaved rounds (each round times every side
 *      and structure once per ray kind); the minimum of each is kept. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_yard.h"
#ifdef TT_HAVE_EMBREE
#include "bench/bench_embree.h"
#endif

const char *yard_kind_name(yard_kind k)
{
    return k == YARD_PRIMARY ? "primary" : k == YARD_SHADOW ? "shadow" : "ao";
}

const char *yard_mode_name(yard_mode m)
{
    return m == YARD_AUTO ? "auto" : m == YARD_OFF ? "off" : "on";
}

uint32_t yard_mode_packets(yard_mode m)
{
    return m == YARD_AUTO ? TT_PACKETS_AUTO : m == YARD_OFF ? TT_PACKETS_OFF : TT_PACKETS_ON;
}

const char *yard_side_name(yard_side s)
{
    static const char *const names[] = {"single", "robust", "p8", "p16"};
    return (unsigned)s < YARD_SIDES ? names[s] : "?";
}

int yard_measured(const yard_config *c, yard_mode m, int k)
{
    if (m == YARD_AUTO) return 1;
    return c->packets_offered && !(m == YARD_ON && k == YARD_AO);
}

/* ---------------------------------------------------------- configurations */

static bench_engine_config configs[8];
static size_t config_count;

static void config_add(const char *label, tt_build_options b)
{
    configs[config_count].build = b;
    snprintf(configs[config_count].label, sizeof configs[0].label, "%s", label);
    config_count++;
}

/* The default R-tree first: its hits make the shadow and AO rays. Then the
 * wide BVH, the default kd-tree, the binned kd-tree and Feldmann's configuration (built
 * by insertion, complete level-order layout), each with the library's other
 * defaults (M and d_min resolved as the library resolves them). */
const bench_engine_config *bench_engine_configs(size_t *count)
{
    if (!config_count) {
        tt_build_options b;
        tt_build_options_default(&b);
        b.accel = "rtree";
        b.rtree.build = TT_RTREE_BUILD_SAH;
        b.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
        b.rtree.M = tt_rtree_max_entries(&b.rtree);
        config_add("rtree sah, compact", b);
        /* the unbalanced wide BVH on the same compact records (issue 17:
         * what the R-tree's balance costs, view by view) */
        tt_build_options_default(&b);
        b.accel = "wbvh";
        config_add("wbvh sah", b);
        static const struct {
            const char *label;
            tt_kd_builder builder;
        } kd[] = {{"kdtree nlogn, htr", TT_KD_NLOGN}, {"kdtree binned, htr", TT_KD_BINNED}};
        for (size_t i = 0; i < 2; i++) {
            tt_build_options_default(&b);
            b.accel = "kdtree";
            b.kdtree.builder = kd[i].builder;
            b.kdtree.traversal = TT_KD_HTR;
            b.kdtree.dmin = tt_kdtree_dmin(&b.kdtree);
            config_add(kd[i].label, b);
        }
        tt_build_options_default(&b);
        b.accel = "rtree";
        b.rtree.build = TT_RTREE_BUILD_INSERT;
        b.rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
        b.rtree.M = tt_rtree_max_entries(&b.rtree);
        config_add("rtree insert, complete (Feldmann)", b);
    }
    *count = config_count;
    return configs;
}

int bench_engine_is_default(const tt_build_options *b)
{
    tt_build_options d;
    tt_build_options_default(&d);
    d.accel = b->accel;
    d.rtree.M = tt_rtree_max_entries(&d.rtree);
    d.kdtree.dmin = tt_kdtree_dmin(&d.kdtree);
    return strcmp(b->accel, "embree") != 0 && bench_same_build(b, &d);
}

/* ------------------------------------------------------------ one view */

typedef struct view_work {
    tt_context *ctx;
    const bench_options *o;
    const tt_scene *scene;
    const tt_camera *cam;
    const tt_accel *bruteforce;
    uint32_t w, h;
    int threads;
    size_t nc; /* configurations */
    const bench_engine_config *cf;
    tt_ray *rays[YARD_KINDS];
    size_t n[YARD_KINDS];
    tt_accel **acc;
    uint32_t *hint; /* per configuration: tt_accel_locate of the eye */
#ifdef TT_HAVE_EMBREE
    bench_embree *emb[2]; /* default flags, robust */
#endif
    /* answers: the reference's, Embree's, a scratch buffer, per kind */
    tt_hit *ref_hits, *e_hits, *hits;
    uint8_t *ref_occ[YARD_KINDS], *e_occ[YARD_KINDS], *occ;
    size_t *picked[YARD_KINDS], npicked[YARD_KINDS];
    tt_hit *bf_hits;
    uint8_t *bf_occ[YARD_KINDS];
} view_work;

static void set_error(char *buf, size_t size, const char *what, const char *why)
{
    snprintf(buf, size, "%s: %s", what, why);
}

static tt_status ours(const view_work *w, size_t c, yard_kind k, yard_mode m, tt_hit *hits,
                      uint8_t *occ, tt_ray_stats *stats)
{
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    bo.packets = yard_mode_packets(m);
    bo.stats = stats;
    if (k == YARD_PRIMARY) {
        bo.image_width = w->w;
        bo.start_hint = w->hint[c];
        return tt_intersect(w->acc[c], w->rays[k], w->n[k], hits, NULL, &bo);
    }
    return tt_occluded(w->acc[c], w->rays[k], w->n[k], occ, NULL, &bo);
}

#ifdef TT_HAVE_EMBREE
static void theirs(const view_work *w, yard_side s, yard_kind k, tt_hit *hits, uint8_t *occ)
{
    const bench_embree *e = w->emb[s == YARD_E_ROBUST];
    const int packet = s == YARD_E_P16 ? 16 : s == YARD_E_P8 ? 8 : 1;
    if (k == YARD_PRIMARY)
        bench_embree_intersect(e, packet, w->rays[k], w->w, w->h, hits, w->threads);
    else
        bench_embree_occluded(e, packet, w->rays[k], w->n[k], occ, w->threads);
}

static void build_embree(view_work *w, yard_view *v)
{
    yard_embree *e = &v->embree;
    e->ok = 1;
    for (int f = 0; f < 2 && e->ok; f++) {
        e->build_s[f] = INFINITY;
        for (int b = 0; b < w->o->builds; b++) {
            double s;
            size_t mem;
            char why[256] = "";
            bench_embree *got =
                bench_embree_build(w->scene, f, w->threads, &s, &mem, why, sizeof why);
            if (!got) {
                e->ok = 0;
                set_error(e->error, sizeof e->error, f ? "robust build" : "build", why);
                break;
            }
            if (s < e->build_s[f]) e->build_s[f] = s;
            e->memory_bytes[f] = mem;
            bench_embree_destroy(w->emb[f]);
            w->emb[f] = got;
        }
    }
}
#endif

static void on_stat(void *user, const char *key, double value)
{
    if (strcmp(key, "sah_cost") == 0) *(double *)user = value;
}

static void build_ours(view_work *w, yard_view *v)
{
    for (size_t c = 0; c < w->nc; c++) {
        yard_config *r = &v->configs[c];
        r->ok = 1;
        r->build_s = INFINITY;
        r->sah_cost = NAN;
        for (int k = 0; k < YARD_KINDS; k++) r->nodes_per_ray[k] = r->triangles_per_ray[k] = NAN;
        for (int b = 0; b < w->o->builds; b++) {
            tt_accel *a = NULL;
            const double t0 = bench_now();
            if (tt_accel_build(w->ctx, w->scene, &w->cf[c].build, &a) != TT_OK) {
                r->ok = 0;
                set_error(r->error, sizeof r->error, "build", tt_context_last_error(w->ctx));
                break;
            }
            const double s = bench_now() - t0;
            if (s < r->build_s) r->build_s = s;
            tt_accel_destroy(w->acc[c]);
            w->acc[c] = a;
        }
        if (!r->ok) continue;
        r->memory_bytes = tt_accel_memory_bytes(w->acc[c]);
        r->isa = tt_accel_isa(w->acc[c]);
        r->packets_offered = yard_packets_offered(w->acc[c]);
        tt_accel_statistics(w->acc[c], on_stat, &r->sah_cost);
        w->hint[c] = tt_accel_locate(w->acc[c], w->cam->eye);
    }
}

/* The house rule: the same triangle with bit-identical t, u, v, or the
 * same t where two triangles share an edge. */
static int same_answer(const tt_hit *a, const tt_hit *b)
{
    if (a->prim == TT_INVALID_ID || b->prim == TT_INVALID_ID) return a->prim == b->prim;
    if (a->prim != b->prim) return memcmp(&a->t, &b->t, sizeof a->t) == 0; /* a shared edge */
    return yard_same_hits(a, b, 1) == 1;
}

/* The rays bruteforce retraces, per kind, and its answers. */
static int bruteforce_answers(view_work *w, int embree_ok)
{
    uint8_t *mask = malloc(w->n[YARD_PRIMARY] ? w->n[YARD_PRIMARY] : 1);
    size_t most = w->n[YARD_AO] > w->n[YARD_PRIMARY] ? w->n[YARD_AO] : w->n[YARD_PRIMARY];
    uint8_t *big = most > w->n[YARD_PRIMARY] ? malloc(most) : NULL;
    if (!mask || (most > w->n[YARD_PRIMARY] && !big)) {
        free(mask);
        free(big);
        return -1;
    }
    const size_t cap = YARD_BRUTEFORCE_SAMPLE + YARD_BRUTEFORCE_DISAGREE;
    for (int k = 0; k < YARD_KINDS; k++) {
        uint8_t *m = w->n[k] <= w->n[YARD_PRIMARY] ? mask : big;
        for (size_t i = 0; embree_ok && i < w->n[k]; i++)
            m[i] = k == YARD_PRIMARY ? w->ref_hits[i].prim != w->e_hits[i].prim
                                     : w->ref_occ[k][i] != w->e_occ[k][i];
        w->picked[k] = malloc(cap * sizeof *w->picked[k]);
        if (!w->picked[k]) break;
        w->npicked[k] = yard_pick_rays(w->n[k], embree_ok ? m : NULL, w->picked[k], cap);
        if (k == YARD_PRIMARY) {
            w->bf_hits = malloc(cap * sizeof *w->bf_hits);
            if (!w->bf_hits ||
                yard_bruteforce(w->bruteforce, w->rays[k], w->picked[k], w->npicked[k], w->bf_hits,
                                NULL) != TT_OK)
                w->npicked[k] = 0;
        } else {
            w->bf_occ[k] = malloc(cap);
            if (!w->bf_occ[k] || yard_bruteforce(w->bruteforce, w->rays[k], w->picked[k],
                                                 w->npicked[k], NULL, w->bf_occ[k]) != TT_OK)
                w->npicked[k] = 0;
        }
    }
    free(mask);
    free(big);
    return 0;
}

/* Every structure's answers against the reference, Embree and bruteforce;
 * packets off / on against auto; the counting pass. */
static void compare_answers(view_work *w, yard_view *v, int embree_ok)
{
    for (size_t c = 0; c < w->nc; c++) {
        yard_config *r = &v->configs[c];
        for (int k = 0; k < YARD_KINDS && r->ok; k++) {
            const size_t n = w->n[k];
            if (ours(w, c, (yard_kind)k, YARD_AUTO, w->hits, w->occ, NULL) != TT_OK) {
                r->ok = 0;
                set_error(r->error, sizeof r->error, yard_kind_name((yard_kind)k),
                          tt_context_last_error(w->ctx));
                break;
            }
            if (k == YARD_PRIMARY) {
                for (size_t i = 0; i < n; i++)
                    r->same_as_reference[k] +=
                        (uint64_t)same_answer(&w->hits[i], &w->ref_hits[i]);
                if (embree_ok) r->agree_embree[k] = yard_agree_hits(w->hits, w->e_hits, n);
                for (size_t j = 0; j < w->npicked[k]; j++)
                    r->bf_equal[k] += (uint64_t)same_answer(&w->hits[w->picked[k][j]],
                                                                       &w->bf_hits[j]);
            } else {
                r->same_as_reference[k] = yard_agree_flags(w->occ, w->ref_occ[k], n);
                if (embree_ok) r->agree_embree[k] = yard_agree_flags(w->occ, w->e_occ[k], n);
                for (size_t j = 0; j < w->npicked[k]; j++)
                    r->bf_equal[k] += (uint64_t)(w->occ[w->picked[k][j]] == w->bf_occ[k][j]);
            }
            r->bf_checked[k] = w->npicked[k];
            /* off and on: the same answers as auto, or the table says so */
            for (int m = YARD_OFF; m < YARD_MODES; m++) {
                if (!yard_measured(r, (yard_mode)m, k)) continue;
                tt_hit *mh = k == YARD_PRIMARY ? malloc((n ? n : 1) * sizeof *mh) : NULL;
                uint8_t *mo = k == YARD_PRIMARY ? NULL : malloc(n ? n : 1);
                if ((k == YARD_PRIMARY && !mh) || (k != YARD_PRIMARY && !mo) ||
                    ours(w, c, (yard_kind)k, (yard_mode)m, mh, mo, NULL) != TT_OK) {
                    r->ok = 0;
                    set_error(r->error, sizeof r->error, yard_mode_name((yard_mode)m),
                              mh || mo ? tt_context_last_error(w->ctx) : "out of memory");
                } else {
                    r->mode_mismatch[m][k] = n - (k == YARD_PRIMARY ? yard_same_hits(mh, w->hits, n)
                                                                    : yard_agree_flags(mo, w->occ, n));
                }
                free(mh);
                free(mo);
            }
            if (k == YARD_AO || !r->ok) continue;
            tt_ray_stats st;
            memset(&st, 0, sizeof st);
            if (ours(w, c, (yard_kind)k, YARD_AUTO, w->hits, w->occ, &st) == TT_OK && st.rays) {
                r->nodes_per_ray[k] = (double)st.nodes / (double)st.rays;
                r->triangles_per_ray[k] = (double)st.triangles / (double)st.rays;
            }
        }
    }
}

static void timed_rounds(view_work *w, yard_view *v, int embree_ok)
{
#ifndef TT_HAVE_EMBREE
    (void)embree_ok; /* no Embree side in this build */
#endif
    for (int round = 0; round < w->o->rounds; round++) {
        for (int k = 0; k < YARD_KINDS; k++) {
#ifdef TT_HAVE_EMBREE
            if (embree_ok) {
                const double t0 = bench_now();
                theirs(w, YARD_E_SINGLE, (yard_kind)k, w->hits, w->occ);
                const double s = bench_now() - t0;
                if (s < v->embree.best_s[YARD_E_SINGLE][k]) v->embree.best_s[YARD_E_SINGLE][k] = s;
            }
#endif
            for (size_t c = 0; c < w->nc; c++) {
                yard_config *r = &v->configs[c];
                /* each round starts with another mode, so none is always
                 * the first after a switch of structure or ray kind */
                for (int i = 0; i < YARD_MODES && r->ok; i++) {
                    const int m = (i + round) % YARD_MODES;
                    if (!yard_measured(r, (yard_mode)m, k)) continue;
                    const double t0 = bench_now();
                    const tt_status st = ours(w, c, (yard_kind)k, (yard_mode)m, w->hits, w->occ, NULL);
                    const double s = bench_now() - t0;
                    if (st != TT_OK) {
                        r->ok = 0;
                        set_error(r->error, sizeof r->error, "timed pass",
                                  tt_context_last_error(w->ctx));
                    } else if (s < r->best_s[m][k]) {
                        r->best_s[m][k] = s;
                    }
                }
            }
#ifdef TT_HAVE_EMBREE
            /* the other Embree sides: single rays robust and coherent
             * packets, for primary and shadow rays (AO rays are not
             * coherent: Embree's users trace them one by one) */
            for (int s = YARD_E_ROBUST; embree_ok && k != YARD_AO && s < YARD_SIDES; s++) {
                const double t0 = bench_now();
                theirs(w, (yard_side)s, (yard_kind)k, w->hits, w->occ);
                const double d = bench_now() - t0;
                if (d < v->embree.best_s[s][k]) v->embree.best_s[s][k] = d;
            }
#endif
        }
    }
    /* never measured stays NaN (not +inf) */
    for (int k = 0; k < YARD_KINDS; k++) {
        for (int s = 0; s < YARD_SIDES; s++)
            if (isinf(v->embree.best_s[s][k])) v->embree.best_s[s][k] = NAN;
        for (size_t c = 0; c < w->nc; c++)
            for (int m = 0; m < YARD_MODES; m++)
                if (isinf(v->configs[c].best_s[m][k])) v->configs[c].best_s[m][k] = NAN;
    }
}

static void free_work(view_work *w)
{
    for (size_t c = 0; w->acc && c < w->nc; c++) tt_accel_destroy(w->acc[c]);
    free(w->acc);
    free(w->hint);
#ifdef TT_HAVE_EMBREE
    bench_embree_destroy(w->emb[0]);
    bench_embree_destroy(w->emb[1]);
#endif
    for (int k = 0; k < YARD_KINDS; k++) {
        free(w->rays[k]);
        free(w->ref_occ[k]);
        free(w->e_occ[k]);
        free(w->picked[k]);
        free(w->bf_occ[k]);
    }
    free(w->ref_hits);
    free(w->e_hits);
    free(w->hits);
    free(w->occ);
    free(w->bf_hits);
}

/* Returns -1 only when out of memory. */
static int measure_view(view_work *w, yard_view *v)
{
    const size_t n = (size_t)w->w * w->h;
    for (int s = 0; s < YARD_SIDES; s++)
        for (int k = 0; k < YARD_KINDS; k++) v->embree.best_s[s][k] = INFINITY;
    for (size_t c = 0; c < w->nc; c++)
        for (int m = 0; m < YARD_MODES; m++)
            for (int k = 0; k < YARD_KINDS; k++) v->configs[c].best_s[m][k] = INFINITY;
    const size_t n_ao = n * (size_t)w->o->ao_samples;
    w->acc = calloc(w->nc, sizeof *w->acc);
    w->hint = calloc(w->nc, sizeof *w->hint);
    w->rays[YARD_PRIMARY] = malloc(n * sizeof(tt_ray));
    w->rays[YARD_SHADOW] = malloc(n * sizeof(tt_ray));
    w->rays[YARD_AO] = malloc((n_ao ? n_ao : 1) * sizeof(tt_ray));
    w->ref_hits = malloc(n * sizeof(tt_hit));
    w->e_hits = malloc(n * sizeof(tt_hit));
    w->hits = malloc(n * sizeof(tt_hit));
    w->occ = malloc(n_ao > n ? n_ao : n);
    for (int k = YARD_SHADOW; k < YARD_KINDS; k++) {
        w->ref_occ[k] = malloc(k == YARD_AO && n_ao > n ? n_ao : n);
        w->e_occ[k] = malloc(k == YARD_AO && n_ao > n ? n_ao : n);
    }
    int oom = !w->acc || !w->hint || !w->ref_hits || !w->e_hits || !w->hits || !w->occ;
    for (int k = 0; k < YARD_KINDS; k++)
        oom |= !w->rays[k] || (k != YARD_PRIMARY && (!w->ref_occ[k] || !w->e_occ[k]));
    if (oom) return -1;
    w->n[YARD_PRIMARY] = n;
    if (tt_camera_rays(w->cam, w->w, w->h, w->rays[YARD_PRIMARY]) != TT_OK) {
        for (size_t c = 0; c < w->nc; c++) {
            v->configs[c].ok = 0;
            set_error(v->configs[c].error, sizeof v->configs[c].error, "camera",
                      tt_context_last_error(w->ctx));
        }
        return 0;
    }
#ifdef TT_HAVE_EMBREE
    build_embree(w, v);
#else
    snprintf(v->embree.error, sizeof v->embree.error, "not in this build");
#endif
    build_ours(w, v);
    size_t ref = 0;
    while (ref < w->nc && !v->configs[ref].ok) ref++;
    if (ref == w->nc) return 0;
    /* the reference's answers make the shadow and AO rays */
    if (ours(w, ref, YARD_PRIMARY, YARD_AUTO, w->ref_hits, NULL, NULL) != TT_OK) {
        v->configs[ref].ok = 0;
        set_error(v->configs[ref].error, sizeof v->configs[ref].error, "primary",
                  tt_context_last_error(w->ctx));
        return 0;
    }
    for (size_t i = 0; i < n; i++) v->primary_hits += w->ref_hits[i].prim != TT_INVALID_ID;
    w->n[YARD_SHADOW] =
        yard_shadow_rays(w->scene, w->cam, w->rays[YARD_PRIMARY], w->ref_hits, n, w->rays[YARD_SHADOW]);
    w->n[YARD_AO] = yard_ao_rays(w->scene, w->rays[YARD_PRIMARY], w->ref_hits, n,
                                 w->o->ao_samples, w->rays[YARD_AO]);
    for (int k = 0; k < YARD_KINDS; k++) v->rays[k] = w->n[k];
    for (int k = YARD_SHADOW; k < YARD_KINDS; k++) {
        if (ours(w, ref, (yard_kind)k, YARD_AUTO, NULL, w->ref_occ[k], NULL) != TT_OK) {
            v->configs[ref].ok = 0;
            set_error(v->configs[ref].error, sizeof v->configs[ref].error,
                      yard_kind_name((yard_kind)k), tt_context_last_error(w->ctx));
            return 0;
        }
    }
    for (size_t i = 0; i < w->n[YARD_SHADOW]; i++) v->shadow_occluded += w->ref_occ[YARD_SHADOW][i];
    for (size_t i = 0; i < w->n[YARD_AO]; i++) v->ao_occluded += w->ref_occ[YARD_AO][i];
    const int embree_ok = v->embree.ok;
#ifdef TT_HAVE_EMBREE
    if (embree_ok) {
        theirs(w, YARD_E_SINGLE, YARD_PRIMARY, w->e_hits, NULL);
        for (int k = YARD_SHADOW; k < YARD_KINDS; k++)
            theirs(w, YARD_E_SINGLE, (yard_kind)k, NULL, w->e_occ[k]);
    }
#endif
    if (bruteforce_answers(w, embree_ok) != 0) return -1;
    compare_answers(w, v, embree_ok);
    timed_rounds(w, v, embree_ok);
    return 0;
}

/* -------------------------------------------------------------- the run */

int bench_yard_run(tt_context *ctx, const bench_options *o, const bench_scene_list *scenes,
                   bench_yard *out, FILE *err)
{
    memset(out, 0, sizeof *out);
    out->size = o->rtree_size;
    out->rounds = o->rounds;
    out->builds = o->builds;
    out->ao_samples = o->ao_samples;
    out->threads = tt_context_threads(ctx) > 0 ? tt_context_threads(ctx) : omp_get_max_threads();
#ifdef TT_HAVE_EMBREE
    bench_embree_version(out->embree_version, sizeof out->embree_version);
#else
    snprintf(out->embree_version, sizeof out->embree_version, "Embree: not in this build");
#endif
    size_t nc;
    const bench_engine_config *cf = bench_engine_configs(&nc);
    size_t total = 0;
    for (size_t s = 0; s < scenes->count; s++) total += scenes->items[s].view_count;
    out->views = calloc(total ? total : 1, sizeof *out->views);
    if (!out->views) goto oom;
    const double t0 = bench_now();
    bench_progress prog;
    bench_progress_start(&prog, err, total);
    for (size_t s = 0; s < scenes->count; s++) {
        const bench_scene *sc = &scenes->items[s];
        tt_scene *scene = NULL;
        tt_accel *bf = NULL;
        const tt_build_options bfo = bench_named_build("bruteforce");
        const int loaded = tt_scene_load(ctx, sc->path, &scene) == TT_OK &&
                           tt_accel_build(ctx, scene, &bfo, &bf) == TT_OK;
        for (size_t vi = 0; vi < sc->view_count; vi++) {
            yard_view *v = &out->views[out->count++];
            v->scene = s;
            v->view = vi;
            v->configs = calloc(nc, sizeof *v->configs);
            if (!v->configs) {
                tt_accel_destroy(bf);
                tt_scene_destroy(scene);
                goto oom;
            }
            char what[200];
            snprintf(what, sizeof what, "%s:%s engine table", sc->name, sc->views[vi].name);
            if (!loaded) {
                for (size_t c = 0; c < nc; c++)
                    set_error(v->configs[c].error, sizeof v->configs[c].error, "load",
                              tt_context_last_error(ctx));
                snprintf(v->embree.error, sizeof v->embree.error, "scene not loaded");
                fprintf(err, "%s%s: %s\n", prog.tty ? "\r\033[K" : "", what, v->configs[0].error);
                bench_progress_step(&prog, what);
                continue;
            }
            v->triangles = tt_scene_triangle_count(scene);
            view_work w;
            memset(&w, 0, sizeof w);
            w.ctx = ctx;
            w.o = o;
            w.scene = scene;
            w.cam = &sc->views[vi].camera;
            w.bruteforce = bf;
            w.w = o->rtree_size.width;
            w.h = o->rtree_size.height;
            w.threads = out->threads;
            w.nc = nc;
            w.cf = cf;
            const int rc = measure_view(&w, v);
            free_work(&w);
            if (rc != 0) {
                tt_accel_destroy(bf);
                tt_scene_destroy(scene);
                goto oom;
            }
            for (size_t c = 0; c < nc; c++)
                if (!v->configs[c].ok)
                    fprintf(err, "%s%s, %s: %s\n", prog.tty ? "\r\033[K" : "", what, cf[c].label,
                            v->configs[c].error);
            if (!v->embree.ok && strcmp(v->embree.error, "not in this build") != 0)
                fprintf(err, "%s%s, Embree: %s\n", prog.tty ? "\r\033[K" : "", what,
                        v->embree.error);
            bench_progress_step(&prog, what);
        }
        tt_accel_destroy(bf);
        tt_scene_destroy(scene);
    }
    bench_progress_end(&prog);
    out->total_s = bench_now() - t0;
    return 0;
oom:
    fprintf(err, "treetrace bench: out of memory in the engine table\n");
    return -1;
}

void bench_yard_free(bench_yard *y)
{
    for (size_t i = 0; i < y->count; i++) free(y->views[i].configs);
    free(y->views);
    memset(y, 0, sizeof *y);
}
