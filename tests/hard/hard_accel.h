/* Every registered structure in every option variant worth telling apart,
 * and a ray-by-ray comparison against bruteforce whose reference answers are
 * computed once per ray set (bruteforce on a few thousand triangles is the
 * slow part, and it is the same for the dozens of variants). The agreement
 * rule is compare.h's (tt_test_hits_agree); like compare.c, both the fast
 * and the counting variant of the structure under test are traced. */
#ifndef TT_HARD_ACCEL_H
#define TT_HARD_ACCEL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "compare.h"
#include "hard_scenes.h"

typedef struct hard_variant {
    tt_build_options opt;
    char label[160];
} hard_variant;

#define HARD_MAX_VARIANTS 96

static const char *const hard_rtree_strategy_names[] = {"min-volume", "min-surface", "min-overlap",
                                                        "rstar", "rstar-surface"};
static const char *const hard_rtree_traversal_names[] = {"auto", "stackless", "ordered", "stack"};
static const char *const hard_kd_traversal_names[] = {"htr", "btr", "sltr", "seq"};

static inline void hard_push(hard_variant *v, size_t *n, const tt_build_options *o,
                             const char *label)
{
    if (*n >= HARD_MAX_VARIANTS) {
        fprintf(stderr, "too many variants\n");
        exit(1);
    }
    v[*n].opt = *o;
    snprintf(v[*n].label, sizeof v[*n].label, "%s", label);
    (*n)++;
}

/* The variants of structure `name`: for the R-tree every insertion strategy
 * x forced reinsert on/off x every traversal at (m, M) = (2, 4), every
 * strategy at (4, 16), (3, 8), the quadratic split, close reinsert, each
 * bulk loader with every traversal at (2, 4) and at (3, 8), (4, 16), the
 * compact layout's traversals per ISA at M = 4, 8, 16 and with the bulk
 * loaders; for the kd-tree all three builders x every traversal x sparse
 * boxes every 1 or 3 levels or none, every traversal with each ISA's
 * kernels, plus the shadow-caster hint; any other structure with its
 * defaults. */
static inline size_t hard_variants(const char *name, hard_variant *v)
{
    size_t n = 0;
    char label[160];
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = name;
    if (strcmp(name, "rtree") == 0) {
        for (int s = TT_RTREE_MIN_VOLUME; s <= TT_RTREE_RSTAR_SURFACE; s++)
            for (int re = 1; re >= 0; re--)
                for (int t = TT_RTREE_AUTO; t <= TT_RTREE_STACK; t++) {
                    tt_build_options r = o;
                    r.rtree.strategy = (tt_rtree_strategy)s;
                    r.rtree.reinsert = re;
                    r.rtree.traversal = (tt_rtree_traversal)t;
                    snprintf(label, sizeof label, "rtree %s m=2 M=4 reinsert=%d traversal=%s",
                             hard_rtree_strategy_names[s], re, hard_rtree_traversal_names[t]);
                    hard_push(v, &n, &r, label);
                }
        for (int s = TT_RTREE_MIN_VOLUME; s <= TT_RTREE_RSTAR_SURFACE; s++) {
            tt_build_options r = o;
            r.rtree.strategy = (tt_rtree_strategy)s;
            r.rtree.m = 4, r.rtree.M = 16;
            r.rtree.traversal = (tt_rtree_traversal)(s % 4);
            snprintf(label, sizeof label, "rtree %s m=4 M=16 reinsert=1 traversal=%s",
                     hard_rtree_strategy_names[s], hard_rtree_traversal_names[s % 4]);
            hard_push(v, &n, &r, label);
        }
        tt_build_options r = o;
        r.rtree.m = 3, r.rtree.M = 8;
        hard_push(v, &n, &r, "rtree rstar-surface m=3 M=8");
        r = o;
        r.rtree.split = TT_RTREE_SPLIT_QUADRATIC;
        hard_push(v, &n, &r, "rtree quadratic split m=2 M=4");
        r.rtree.m = 4, r.rtree.M = 16;
        r.rtree.strategy = TT_RTREE_MIN_VOLUME;
        r.rtree.reinsert = 0;
        hard_push(v, &n, &r, "rtree quadratic split min-volume m=4 M=16 reinsert=0");
        r = o;
        r.rtree.reinsert_far = 0;
        r.rtree.reinsert_fraction = 0.5f;
        r.rtree.traversal = TT_RTREE_STACK;
        hard_push(v, &n, &r, "rtree close reinsert fraction 0.5 traversal=stack");
        /* the bulk loaders: every traversal at (2, 4), and (3, 8), (4, 16) */
        static const char *const builds[] = {"insert", "str", "hilbert", "sah"};
        static const int mm[3][2] = {{2, 4}, {3, 8}, {4, 16}};
        for (int b = TT_RTREE_BUILD_STR; b <= TT_RTREE_BUILD_SAH; b++)
            for (int q = 0; q < 3; q++)
                for (int t = TT_RTREE_AUTO; t <= TT_RTREE_STACK; t++) {
                    if (q > 0 && t != (b + q) % 4) continue; /* one traversal each */
                    r = o;
                    r.rtree.build = (tt_rtree_build)b;
                    r.rtree.m = mm[q][0], r.rtree.M = mm[q][1];
                    r.rtree.traversal = (tt_rtree_traversal)t;
                    snprintf(label, sizeof label, "rtree build=%s m=%d M=%d traversal=%s",
                             builds[b], mm[q][0], mm[q][1], hard_rtree_traversal_names[t]);
                    hard_push(v, &n, &r, label);
                }
        /* the compact layout: its stack traversal on every ISA this CPU
         * runs and its stackless traversal, M = 4, 8, 16 */
        static const int cm[3][2] = {{2, 4}, {3, 8}, {4, 16}};
        for (int k = 0; k < 3; k++) {
            for (int isa = TT_ISA_SCALAR; isa <= TT_ISA_AVX512 + 1; isa++) {
                const int stackless = isa == TT_ISA_AVX512 + 1;
                if (!stackless && !tt_test_isa_runs((tt_isa)isa)) continue;
                r = o;
                r.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
                r.rtree.m = cm[k][0], r.rtree.M = cm[k][1];
                r.rtree.traversal = stackless ? TT_RTREE_STACKLESS : TT_RTREE_STACK;
                r.isa = stackless ? TT_ISA_SCALAR : (tt_isa)isa;
                snprintf(label, sizeof label, "rtree compact m=%d M=%d traversal=%s isa=%s",
                         cm[k][0], cm[k][1], stackless ? "stackless" : "stack",
                         tt_isa_name(r.isa));
                hard_push(v, &n, &r, label);
            }
        }
        r = o;
        r.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
        r.rtree.strategy = TT_RTREE_MIN_VOLUME;
        r.rtree.reinsert = 0;
        r.rtree.m = 2, r.rtree.M = 6;
        hard_push(v, &n, &r, "rtree compact min-volume m=2 M=6 reinsert=0 traversal=auto");
        /* the bulk loaders in the compact layout */
        for (int b = TT_RTREE_BUILD_STR; b <= TT_RTREE_BUILD_SAH; b++) {
            r = o;
            r.rtree.build = (tt_rtree_build)b;
            r.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
            r.rtree.m = b == TT_RTREE_BUILD_SAH ? 4 : 3, r.rtree.M = b == TT_RTREE_BUILD_SAH ? 16 : 8;
            r.rtree.traversal = b == TT_RTREE_BUILD_HILBERT ? TT_RTREE_STACKLESS : TT_RTREE_AUTO;
            snprintf(label, sizeof label, "rtree compact build=%s m=%d M=%d traversal=%s",
                     builds[b], r.rtree.m, r.rtree.M, hard_rtree_traversal_names[r.rtree.traversal]);
            hard_push(v, &n, &r, label);
        }
    } else if (strcmp(name, "kdtree") == 0) {
        static const int dmins[3] = {1, 3, -1};
        static const char *const builders[3] = {"nlogn", "nlog2n", "binned"};
        for (int b = TT_KD_NLOGN; b <= TT_KD_BINNED; b++)
            for (int t = TT_KD_HTR; t <= TT_KD_SEQ; t++)
                for (int d = 0; d < 3; d++) {
                    tt_build_options k = o;
                    k.kdtree.builder = (tt_kd_builder)b;
                    k.kdtree.traversal = (tt_kd_traversal)t;
                    k.kdtree.dmin = dmins[d];
                    snprintf(label, sizeof label, "kdtree %s traversal=%s dmin=%d",
                             builders[b], hard_kd_traversal_names[t],
                             dmins[d]);
                    hard_push(v, &n, &k, label);
                }
        /* The variants above run the best ISA (options.isa auto); every
         * other ISA this CPU runs, each traversal once. */
        for (int i = TT_ISA_SCALAR; i <= TT_ISA_AVX512; i++) {
            if (!tt_test_isa_runs((tt_isa)i) || i == (int)tt_isa_best()) continue;
            for (int t = TT_KD_HTR; t <= TT_KD_SEQ; t++) {
                tt_build_options k = o;
                k.isa = (tt_isa)i;
                k.kdtree.traversal = (tt_kd_traversal)t;
                k.kdtree.dmin = 2;
                snprintf(label, sizeof label, "kdtree nlogn traversal=%s dmin=2 isa=%s",
                         hard_kd_traversal_names[t], tt_isa_name((tt_isa)i));
                hard_push(v, &n, &k, label);
            }
        }
        for (int t = TT_KD_BTR; t <= TT_KD_SEQ; t++) { /* htr has no boxes to start from */
            tt_build_options k = o;
            k.kdtree.traversal = (tt_kd_traversal)t;
            k.kdtree.shadow_caster_hint = 1;
            snprintf(label, sizeof label, "kdtree nlogn traversal=%s shadow-caster-hint",
                     hard_kd_traversal_names[t]);
            hard_push(v, &n, &k, label);
        }
    } else if (strcmp(name, "wbvh") == 0) {
        /* the wide BVH: every ISA this CPU runs at M = 16, and M = 4, 8 */
        for (int i = TT_ISA_SCALAR; i <= TT_ISA_AVX512; i++) {
            if (!tt_test_isa_runs((tt_isa)i)) continue;
            tt_build_options w = o;
            w.isa = (tt_isa)i;
            snprintf(label, sizeof label, "wbvh M=16 isa=%s", tt_isa_name((tt_isa)i));
            hard_push(v, &n, &w, label);
        }
        for (int M = 4; M <= 8; M += 4) {
            tt_build_options w = o;
            w.rtree.M = M;
            snprintf(label, sizeof label, "wbvh M=%d", M);
            hard_push(v, &n, &w, label);
        }
    } else {
        hard_push(v, &n, &o, name);
    }
    return n;
}

/* ----------------------------------------------------------- ray sets */

/* Rays with their bruteforce answers: closest hit on [tmin, tmax) and
 * occlusion on the same interval. */
typedef struct hard_rays {
    tt_ray *ray;
    const char **kind; /* a static string per ray naming its family           */
    tt_hit *hit;
    int *occluded;
    size_t n, cap;
} hard_rays;

static inline void hard_rays_add(hard_rays *s, const char *kind, const float org[3],
                                 const float dir[3], float tmin, float tmax)
{
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 1024;
        s->ray = hard_xrealloc(s->ray, s->cap * sizeof *s->ray);
        s->kind = hard_xrealloc(s->kind, s->cap * sizeof *s->kind);
    }
    tt_ray *r = &s->ray[s->n];
    memcpy(r->org, org, sizeof r->org);
    memcpy(r->dir, dir, sizeof r->dir);
    r->tmin = tmin;
    r->tmax = tmax;
    s->kind[s->n++] = kind;
}

/* Families named "generic: ..." are rays in general position (random
 * origins and directions, nowhere near an edge, a vertex or a triangle's
 * plane; see hard_rays.h for why this matters): the only targeted rays an
 * external reference is held to exactly (hard_mode below). */
#define HARD_GENERIC "generic: "
static inline int hard_family_generic(const char *kind)
{
    return strncmp(kind, HARD_GENERIC, sizeof HARD_GENERIC - 1) == 0;
}

/* Whether a ray breaks the ray contract of treetrace.h (tt_ray): a
 * non-finite or zero direction, a non-finite origin, NaN interval ends or a
 * negative tmin (-inf included). Every structure must refuse such a ray with
 * TT_ERR_INVALID_ARGUMENT, in all four calls. */
static inline int hard_ray_breaks_contract(const tt_ray *r)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(r->org[k]) || !isfinite(r->dir[k])) return 1;
    if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) return 1;
    return isnan(r->tmin) || isnan(r->tmax) || r->tmin < 0.0f;
}

/* Traces every ray with the reference structure (bruteforce); a ray that
 * breaks the contract must be refused by it (its answer is then a miss). */
static inline void hard_rays_reference(hard_rays *s, const tt_accel *ref)
{
    s->hit = hard_xrealloc(s->hit, (s->n ? s->n : 1) * sizeof *s->hit);
    s->occluded = hard_xrealloc(s->occluded, (s->n ? s->n : 1) * sizeof *s->occluded);
    for (size_t i = 0; i < s->n; i++) {
        tt_status a = tt_intersect1(ref, &s->ray[i], &s->hit[i]);
        tt_status b = tt_occluded1(ref, &s->ray[i], &s->occluded[i]);
        tt_status want = hard_ray_breaks_contract(&s->ray[i]) ? TT_ERR_INVALID_ARGUMENT : TT_OK;
        if (a != want || b != want) {
            fprintf(stderr, "the reference %s ray %zu (%s)\n", want ? "accepted" : "refused", i,
                    s->kind[i]);
            exit(1);
        }
        if (want != TT_OK) {
            s->hit[i].t = INFINITY;
            s->hit[i].u = s->hit[i].v = 0.0f;
            s->hit[i].prim = TT_INVALID_ID;
            s->occluded[i] = 0;
        }
    }
}

static inline void hard_rays_free(hard_rays *s)
{
    free(s->ray);
    free(s->kind);
    free(s->hit);
    free(s->occluded);
    memset(s, 0, sizeof *s);
}

/* How a structure is held to the reference answers.
 * HARD_EXACT: our structures, on every ray (the agreement rule of
 * compare.h: same triangle, or same t within 1e-4 relative, and the same
 * occlusion).
 * HARD_EXTERNAL: an external reference (Embree) with its own triangle test,
 * tolerant on edges and not watertight-identical to ours: exact only on the
 * generic families (hard_family_generic, hard_rays.h); on every other ray
 * (aimed at edges and vertices, grazing, hits at t ~ 0, odd directions) only
 * a valid answer: the calls succeed, a miss (t = +inf) or a triangle in range
 * with t in [tmin, tmax), the counting variant the same answer.
 * Rays that break the contract must be refused in both modes. */
typedef enum hard_mode { HARD_EXACT, HARD_EXTERNAL } hard_mode;

static inline int hard_is_external_reference(const char *name) { return strcmp(name, "embree") == 0; }

static inline int hard_valid_hit(const tt_accel *test, const tt_ray *r, const tt_hit *h)
{
    (void)test;
    if (h->prim == TT_INVALID_ID) return h->t == INFINITY;
    return h->t >= r->tmin && h->t < r->tmax;
}

/* Traces ray i with `test` (fast and counting variants, closest hit and
 * occlusion) and judges it per `mode`; on failure writes what went wrong
 * into detail (when not NULL). */
static inline int hard_ray_check(const tt_accel *test, const hard_rays *s, size_t i, size_t nt,
                                 hard_mode mode, char *detail, size_t detail_size)
{
    const tt_ray *r = &s->ray[i];
    tt_hit fast, counted;
    tt_ray_stats st;
    memset(&st, 0, sizeof st);
    memset(&fast, 0, sizeof fast);
    memset(&counted, 0, sizeof counted);
    tt_trace_args args = {TT_INVALID_ID, TT_INVALID_ID, &st};
    tt_status e1 = tt_intersect1(test, r, &fast);
    tt_status e2 = tt_intersect1_ex(test, r, &counted, &args);
    int o_fast = -1, o_counted = -1;
    tt_status e3 = tt_occluded1(test, r, &o_fast);
    tt_status e4 = tt_occluded1_ex(test, r, &o_counted, &args);
    int ok;
    const char *rule;
    if (hard_ray_breaks_contract(r)) {
        rule = "must be refused (ray contract)";
        ok = e1 == TT_ERR_INVALID_ARGUMENT && e2 == TT_ERR_INVALID_ARGUMENT &&
             e3 == TT_ERR_INVALID_ARGUMENT && e4 == TT_ERR_INVALID_ARGUMENT && st.rays == 0;
    } else if (mode == HARD_EXACT || hard_family_generic(s->kind[i])) {
        rule = "must agree with bruteforce";
        ok = !e1 && !e2 && !e3 && !e4 && tt_test_hits_agree(&s->hit[i], &fast) &&
             tt_test_hits_agree(&s->hit[i], &counted) && o_fast == s->occluded[i] &&
             o_counted == s->occluded[i] && st.rays == 2;
    } else {
        rule = "must be a valid answer (external reference, non-generic family)";
        ok = !e1 && !e2 && !e3 && !e4 && hard_valid_hit(test, r, &fast) &&
             (fast.prim == TT_INVALID_ID || fast.prim < nt) && counted.prim == fast.prim &&
             counted.t == fast.t && (o_fast == 0 || o_fast == 1) && o_counted == o_fast &&
             st.rays == 2;
    }
    if (!ok && detail)
        snprintf(detail, detail_size,
                 "ray %zu (%s) org %.9g %.9g %.9g dir %.9g %.9g %.9g t [%.9g, %.9g) %s: "
                 "bruteforce prim %u t %.9g occluded %d; fast prim %u t %.9g occluded %d; "
                 "counting prim %u t %.9g occluded %d (rays counted %llu; status %d %d %d %d)",
                 i, s->kind[i], r->org[0], r->org[1], r->org[2], r->dir[0], r->dir[1], r->dir[2],
                 r->tmin, r->tmax, rule, s->hit[i].prim, s->hit[i].t, s->occluded[i], fast.prim,
                 fast.t, o_fast, counted.prim, counted.t, o_counted, (unsigned long long)st.rays,
                 e1, e2, e3, e4);
    return ok;
}

/* Prints how many rays of each family fail, so that a report says at a
 * glance which kind of ray a structure gets wrong. */
static inline void hard_tally_families(const tt_accel *test, const hard_rays *s, size_t nt,
                                       hard_mode mode)
{
    const char *seen[64];
    size_t count[64], nseen = 0;
    for (size_t i = 0; i < s->n; i++) {
        if (hard_ray_check(test, s, i, nt, mode, NULL, 0)) continue;
        size_t k = 0;
        while (k < nseen && strcmp(seen[k], s->kind[i]) != 0) k++;
        if (k == nseen) {
            if (nseen == 64) continue;
            seen[nseen] = s->kind[i];
            count[nseen++] = 0;
        }
        count[k]++;
    }
    for (size_t k = 0; k < nseen; k++) fprintf(stderr, "%s %zu \"%s\"", k ? "," : "", count[k], seen[k]);
    fprintf(stderr, "\n");
}

/* Number of rays on which `test` fails its mode's rule (hard_ray_check);
 * prints the first few with the scene and variant. nt: the scene's
 * triangle count. */
static inline size_t hard_compare(const char *scene, const char *label, const tt_accel *test,
                                  const hard_rays *s, size_t nt, hard_mode mode)
{
    size_t bad = 0;
    char detail[768];
    for (size_t i = 0; i < s->n; i++) {
        if (hard_ray_check(test, s, i, nt, mode, detail, sizeof detail)) continue;
        if (bad++ < 4) fprintf(stderr, "%s / %s: %s\n", scene, label, detail);
    }
    if (bad) {
        fprintf(stderr, "%s / %s: %zu of %zu rays fail; by family:", scene, label, bad, s->n);
        hard_tally_families(test, s, nt, mode);
    }
    return bad;
}

/* --------------------------------------------------------- the driver */

/* What one structure's run reports to the parent process. */
typedef struct hard_tally {
    int built, passed, failed;
} hard_tally;

/* Whether compare.c's random rays are in general position on this scene:
 * not if the scene is flat (its random origins then lie on the surface, hits
 * at t ~ 0), nor if it sits so far from the origin that the float grid is
 * coarse against its size (random coordinates then often equal vertex
 * coordinates, and the rays with zero direction components that compare.c
 * makes lie in box faces' planes, Embree's known slab limitation). Our
 * structures are compared on them everywhere; Embree only where this holds. */
static inline int hard_scene_generic(const tt_scene *scene)
{
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    for (int k = 0; k < 3; k++) {
        float extent = hi[k] - lo[k];
        float far = fmaxf(fabsf(lo[k]), fabsf(hi[k]));
        if (!(extent > 0.0f) || nextafterf(far, INFINITY) - far > extent * 0x1p-16f) return 0;
    }
    return 1;
}

/* Every variant of structure `name`: build, check, targeted rays, random
 * rays and a framed view against the reference. The targeted rays are
 * judged per hard_mode (Embree: exact on generic families only); the
 * framed view is generic, and so are the random rays on a scene in general
 * position (hard_scene_generic): there every structure, Embree included,
 * must agree. */
static inline void hard_one_structure(tt_context *ctx, const char *name, const char *scene_name,
                                      const tt_scene *scene, const tt_accel *ref,
                                      const hard_rays *rays, uint32_t random_rays, hard_tally *t)
{
    static hard_variant v[HARD_MAX_VARIANTS];
    tt_camera cam;
    tt_camera_frame_scene(scene, &cam);
    size_t nv = hard_variants(name, v);
    const hard_mode mode = hard_is_external_reference(name) ? HARD_EXTERNAL : HARD_EXACT;
    for (size_t i = 0; i < nv; i++) {
        tt_accel *acc = NULL;
        tt_status st = tt_accel_build(ctx, scene, &v[i].opt, &acc);
        CHECK_MSG(st == TT_OK, "%s / %s: build: %s: %s", scene_name, v[i].label, tt_strerror(st),
                  tt_context_last_error(ctx));
        if (st != TT_OK) continue;
        t->built++;
        st = tt_accel_check(acc);
        CHECK_MSG(st == TT_OK, "%s / %s: check: %s: %s", scene_name, v[i].label, tt_strerror(st),
                  tt_context_last_error(ctx));
        if (rays)
            CHECK_MSG(hard_compare(scene_name, v[i].label, acc, rays,
                                   tt_scene_triangle_count(scene), mode) == 0,
                      "%s / %s: targeted rays fail (%s)", scene_name, v[i].label,
                      mode == HARD_EXACT ? "agreement with bruteforce"
                                         : "external reference: generic families exact, "
                                           "valid answers elsewhere");
        if (random_rays && (mode == HARD_EXACT || hard_scene_generic(scene))) {
            size_t bad = tt_test_compare_random(scene, acc, ref, random_rays, 12345u + (uint32_t)i);
            CHECK_MSG(bad == 0, "%s / %s: %zu random rays disagree", scene_name, v[i].label, bad);
            bad = tt_test_compare_view(scene, acc, ref, &cam, 12, 10);
            CHECK_MSG(bad == 0, "%s / %s: %zu pixels of the framed view disagree", scene_name,
                      v[i].label, bad);
        }
        tt_accel_destroy(acc);
    }
}

/* Runs hard_one_structure for every registered structure, each in a child
 * process: a structure that crashes on a hard scene is reported as such
 * (with the scene), and the others are still tested. The child inherits
 * the scene and the reference answers and sends its counts back through a
 * pipe. Returns the number of variants built. HARD_ONLY=name restricts the
 * run to one structure (a debugging aid). */
static inline size_t hard_each_structure(tt_context *ctx, const char *scene_name,
                                         const tt_scene *scene, const hard_rays *rays,
                                         uint32_t random_rays)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));
    size_t built = 0;
    const char *only = getenv("HARD_ONLY");
    for (const char *const *name = tt_accel_names(); *name; name++) {
        if (only && *only && strcmp(only, *name) != 0) continue;
        int fd[2];
        fflush(stdout);
        fflush(stderr);
        if (pipe(fd) != 0) {
            perror("pipe");
            exit(1);
        }
        pid_t pid = fork();
        if (pid < 0) {
            perror("fork");
            exit(1);
        }
        if (pid == 0) {
            close(fd[0]);
            hard_tally t = {0, 0, 0};
            int p0 = tt_test_passed, f0 = tt_test_failed;
            hard_one_structure(ctx, *name, scene_name, scene, ref, rays, random_rays, &t);
            t.passed = tt_test_passed - p0;
            t.failed = tt_test_failed - f0;
            ssize_t w = write(fd[1], &t, sizeof t);
            fflush(stdout);
            fflush(stderr);
            _exit(w == (ssize_t)sizeof t ? 0 : 1);
        }
        close(fd[1]);
        hard_tally t = {0, 0, 0};
        ssize_t got = read(fd[0], &t, sizeof t);
        close(fd[0]);
        int status = 0;
        waitpid(pid, &status, 0);
        const char *role = hard_is_external_reference(*name)
                               ? " (external reference: exact on generic rays, valid answers "
                                 "elsewhere)"
                               : "";
        if (WIFSIGNALED(status) || got != (ssize_t)sizeof t) {
            CHECK_MSG(0, "%s: %s crashed (signal %d) after %d variants%s", scene_name, *name,
                      WIFSIGNALED(status) ? WTERMSIG(status) : 0, t.built, role);
            continue;
        }
        printf("  %-12s %-10s %3d variants, %5d checks passed, %3d failed%s\n", scene_name, *name,
               t.built, t.passed, t.failed, role);
        tt_test_passed += t.passed;
        tt_test_failed += t.failed;
        built += (size_t)t.built;
    }
    tt_accel_destroy(ref);
    return built;
}

#endif
