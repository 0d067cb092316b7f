/* Packets (tt_batch_options.packets, the vtable's packet entries) give ray
 * by ray exactly what the single-ray calls give: the same triangle, t, u
 * and v bit for bit, and the same occlusion, for every structure x every
 * ISA this binary and CPU have x TT_PACKETS_ON / OFF / AUTO x packet sizes
 * (16 x 16 tiles, runs of 1..256 rays), on the shared views' primary and
 * shadow rays and on hostile rays: one valid ray per packet (the others
 * bad), mixed direction signs in one packet, axis-parallel directions,
 * empty and finite intervals, origins inside the scene, directions with
 * extreme components (the kernels derive reciprocals and shear themselves),
 * denormal and NaN components, tmin > tmax. The rows entries (single rays
 * one by one: the batch's items that are not packets) likewise, called
 * through the batch with packets off / auto and directly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "accel/accel.h"
#include "accel/packets.h"
#include "core/isa.h"
#include "check.h"

#define SIZE 128 /* view images SIZE x SIZE: 64 tiles */

/* small scenes: bruteforce too, and every packet size; big scenes: the
 * engines, fewer direct packet sizes (CPU time) */
static int g_small;

static uint32_t next(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}
static float unit(uint32_t *x) { return (float)(next(x) >> 8) * (1.0f / 16777216.0f); }

/* n rays against the single-ray answers, through the batch with `mode`,
 * cut as `width` (tiles) or `chunk`. */
static size_t compare_batch(const tt_accel *a, const tt_ray *rays, size_t n, uint32_t mode,
                            uint32_t width, uint32_t chunk, const tt_hit *one,
                            const uint8_t *occ_one, const tt_status *st_one)
{
    tt_hit *many = malloc(n * sizeof *many);
    uint8_t *occ = malloc(n);
    if (!many || !occ) exit(1);
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    bo.packets = mode;
    bo.image_width = width;
    bo.chunk = chunk;
    memset(many, 0xAB, n * sizeof *many);
    memset(occ, 0xAB, n);
    tt_intersect(a, rays, n, many, NULL, &bo);
    tt_occluded(a, rays, n, occ, NULL, &bo);
    size_t differ = 0;
    for (size_t i = 0; i < n; i++) {
        if (st_one[i] != TT_OK) {
            if (many[i].prim != TT_INVALID_ID || occ[i] != 0) differ++;
            continue;
        }
        if (memcmp(&many[i], &one[i], sizeof(tt_hit)) != 0 || occ[i] != occ_one[i]) {
            if (differ < 3)
                fprintf(stderr, "  ray %zu: batch prim %u t %.9g, single prim %u t %.9g; occ %d %d\n",
                        i, many[i].prim, (double)many[i].t, one[i].prim, (double)one[i].t, occ[i],
                        occ_one[i]);
            differ++;
        }
    }
    free(many);
    free(occ);
    return differ;
}

/* The next rows of a run of at most n: the valid rays (st_one TT_OK) from
 * rays[*i] on, into w's rows 0..k, their indices into idx; returns k. */
static uint32_t gather(tt_packet_rays *w, const tt_ray *rays, size_t count, size_t *i, uint32_t n,
                       const tt_status *st_one, size_t *idx)
{
    uint32_t k = 0;
    for (; *i < count && k < n; ++*i) {
        if (st_one[*i] != TT_OK) continue;
        tt_packet_ray_set(w, k, rays[*i].org, rays[*i].dir, rays[*i].tmin, rays[*i].tmax);
        idx[k++] = *i;
    }
    return k;
}

/* The vtable's packet entries called directly on runs of n rays. */
static size_t compare_direct(const tt_accel *a, const tt_ray *rays, size_t count, uint32_t n,
                             const tt_hit *one, const uint8_t *occ_one, const tt_status *st_one)
{
    const tt_accel_vtable *vt = a->vt;
    if (!vt->intersect_packet) return 0;
    static tt_packet_rays w; /* (8 KB) */
    tt_hit h[TT_PACKET_MAX];
    uint8_t o[TT_PACKET_MAX];
    size_t idx[TT_PACKET_MAX], differ = 0;
    for (size_t i = 0; i < count;) {
        const uint32_t k = gather(&w, rays, count, &i, n, st_one, idx);
        w.n = k;
        vt->intersect_packet(a, &w, h);
        vt->occluded_packet(a, &w, o);
        for (uint32_t j = 0; j < k; j++)
            if (memcmp(&h[j], &one[idx[j]], sizeof(tt_hit)) != 0 || o[j] != occ_one[idx[j]])
                differ++;
        tt_packet_stats ps;
        memset(&ps, 0, sizeof ps);
        vt->intersect_packet_stats(a, &w, h, &ps);
        for (uint32_t j = 0; j < k; j++)
            if (memcmp(&h[j], &one[idx[j]], sizeof(tt_hit)) != 0) differ++;
        vt->occluded_packet_stats(a, &w, o, &ps);
        for (uint32_t j = 0; j < k; j++)
            if (o[j] != occ_one[idx[j]]) differ++;
        CHECK(ps.rays.rays == 2u * k);
    }
    return differ;
}

/* The vtable's rows entries (single rays one by one, the batch's non-packet
 * items) called directly on runs of n rows, the rows past n poisoned with
 * NaN (a unit prepares whole vectors of rows and must drop those lanes). */
static size_t compare_rows(const tt_accel *a, const tt_ray *rays, size_t count, uint32_t n,
                           const tt_hit *one, const uint8_t *occ_one, const tt_status *st_one)
{
    const tt_accel_vtable *vt = a->vt;
    if (!vt->intersect_rows || !vt->occluded_rows) return 0;
    static tt_packet_rays w; /* (8 KB) */
    tt_hit h[TT_PACKET_MAX];
    uint8_t o[TT_PACKET_MAX];
    size_t idx[TT_PACKET_MAX], differ = 0;
    for (size_t i = 0; i < count;) {
        const uint32_t k = gather(&w, rays, count, &i, n, st_one, idx);
        const float poison[3] = {NAN, NAN, NAN};
        for (uint32_t j = k; j < TT_PACKET_MAX; j++) tt_packet_ray_set(&w, j, poison, poison, NAN, NAN);
        w.n = k;
        memset(h, 0xAB, sizeof h);
        memset(o, 0xAB, sizeof o);
        vt->intersect_rows(a, &w, TT_INVALID_ID, h);
        vt->occluded_rows(a, &w, TT_INVALID_ID, o);
        for (uint32_t j = 0; j < k; j++)
            if (memcmp(&h[j], &one[idx[j]], sizeof(tt_hit)) != 0 || o[j] != occ_one[idx[j]]) {
                if (differ < 3)
                    fprintf(stderr, "  ray %zu: rows prim %u t %.9g, single prim %u t %.9g; occ %d %d\n",
                            idx[j], h[j].prim, (double)h[j].t, one[idx[j]].prim,
                            (double)one[idx[j]].t, o[j], occ_one[idx[j]]);
                differ++;
            }
        /* nothing written past the rows */
        for (uint32_t j = k; j < TT_PACKET_MAX; j++)
            if (o[j] != 0xAB || h[j].prim != 0xABABABABu) differ++;
    }
    return differ;
}

static void check_rays(const tt_accel *a, const tt_ray *rays, size_t n, uint32_t width,
                       const char *what)
{
    tt_hit *one = malloc(n * sizeof *one);
    uint8_t *occ_one = malloc(n);
    tt_status *st = malloc(n * sizeof *st);
    if (!one || !occ_one || !st) exit(1);
    for (size_t i = 0; i < n; i++) {
        int o = 0;
        st[i] = tt_intersect1(a, &rays[i], &one[i]);
        tt_occluded1(a, &rays[i], &o);
        occ_one[i] = (uint8_t)o;
    }
    static const uint32_t modes[] = {TT_PACKETS_ON, TT_PACKETS_AUTO, TT_PACKETS_OFF};
    static const char *mode_name[] = {"on", "auto", "off"};
    for (int m = 0; m < 3; m++) {
        size_t d = compare_batch(a, rays, n, modes[m], width, 0, one, occ_one, st);
        CHECK_MSG(d == 0, "%s %s packets %s, tiles of width %u: %zu rays differ",
                  tt_accel_name(a), what, mode_name[m], width, d);
        d = compare_batch(a, rays, n, modes[m], 0, 0, one, occ_one, st);
        CHECK_MSG(d == 0, "%s %s packets %s, runs: %zu rays differ", tt_accel_name(a), what,
                  mode_name[m], d);
    }
    static const uint32_t sizes[] = {1, 2, 5, 8, 9, 16, 33, 64, 100, 256};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        if (!g_small && sizes[s] != 1 && sizes[s] != 33 && sizes[s] != 256) continue;
        size_t d = compare_direct(a, rays, n, sizes[s], one, occ_one, st);
        CHECK_MSG(d == 0, "%s %s: packets of %u rays: %zu results differ", tt_accel_name(a),
                  what, sizes[s], d);
        d = compare_rows(a, rays, n, sizes[s], one, occ_one, st);
        CHECK_MSG(d == 0, "%s %s: rows of %u rays: %zu results differ", tt_accel_name(a), what,
                  sizes[s], d);
    }
    free(one);
    free(occ_one);
    free(st);
}

/* Primary and shadow rays of a view, SIZE x SIZE. */
static tt_ray *view_rays(const tt_accel *ref, const tt_scene *scene, const tt_camera *cam,
                         size_t *n_shadow, tt_ray **shadow)
{
    const size_t n = (size_t)SIZE * SIZE;
    tt_ray *rays = malloc(n * sizeof *rays);
    tt_ray *sh = malloc(n * sizeof *sh);
    if (!rays || !sh) exit(1);
    if (tt_camera_rays(cam, SIZE, SIZE, rays) != TT_OK) exit(1);
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        tt_hit h;
        tt_intersect1(ref, &rays[i], &h);
        if (h.prim != TT_INVALID_ID && tt_shadow_ray(scene, cam, &rays[i], &h, &sh[k]))
            k++;
    }
    *n_shadow = k;
    *shadow = sh;
    return rays;
}

/* Shadow rays whose far end sits on their first occluder: tmax is the
 * closest hit's t, one float above or below it, or the shadow ray's own, by
 * ray index. Occlusion packets cull boxes by the rays' tmax (tcut and the
 * packet's far bound in rtc_packet.h): an occluder at the very end of a
 * ray must be found exactly when the single ray finds it. */
static tt_ray *shadow_edge_rays(const tt_accel *ref, const tt_ray *shadow, size_t n)
{
    tt_ray *rays = malloc((n ? n : 1) * sizeof *rays);
    if (!rays) exit(1);
    for (size_t i = 0; i < n; i++) {
        tt_ray r = shadow[i];
        tt_hit h;
        r.tmax = INFINITY;
        tt_intersect1(ref, &r, &h);
        rays[i] = shadow[i];
        if (h.prim == TT_INVALID_ID) continue;
        if (i % 4 == 0) rays[i].tmax = h.t;
        if (i % 4 == 1) rays[i].tmax = nextafterf(h.t, INFINITY);
        if (i % 4 == 2) rays[i].tmax = nextafterf(h.t, 0.0f);
    }
    return rays;
}

/* Hostile rays in tiles of 16 x 16: tile kinds by tile index. */
static tt_ray *hostile_rays(const tt_scene *scene, const tt_camera *cam, int denormal,
                            size_t *n_out)
{
    const size_t n = (size_t)SIZE * SIZE;
    tt_ray *rays = malloc(n * sizeof *rays);
    if (!rays) exit(1);
    if (tt_camera_rays(cam, SIZE, SIZE, rays) != TT_OK) exit(1);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    uint32_t seed = 777;
    for (size_t i = 0; i < n; i++) {
        tt_ray *r = &rays[i];
        const size_t x = i % SIZE, y = i / SIZE, tile = (y / 16) * (SIZE / 16) + x / 16;
        const size_t lane = (y % 16) * 16 + x % 16;
        switch (tile % 8) {
        case 0: /* one valid ray per tile: the others break the contract */
            if (lane != tile % 256) r->tmin = -1.0f;
            break;
        case 1: /* mixed direction signs: random directions, shared origin */
            for (int k = 0; k < 3; k++) r->dir[k] = 2.0f * unit(&seed) - 1.0f;
            break;
        case 2: /* from inside the scene, coherent directions */
            for (int k = 0; k < 3; k++) r->org[k] = lo[k] + (hi[k] - lo[k]) * (0.3f + 0.4f * unit(&seed));
            break;
        case 3: /* empty and finite intervals */
            r->tmin = unit(&seed);
            r->tmax = (lane % 3 == 0) ? r->tmin : r->tmin + 2.0f * unit(&seed);
            if (lane % 5 == 0) r->tmax = 0.5f * r->tmin;
            break;
        case 4: /* axis-parallel and signed-zero components */
            if (lane % 2) r->dir[lane % 3] = (lane % 4 == 1) ? -0.0f : 0.0f;
            if (lane % 7 == 0) r->dir[0] = r->dir[1] = 0.0f;
            if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) r->dir[2] = 1.0f;
            break;
        case 5: /* inside the scene, directions with extreme components (the
                 * packet kernels' own reciprocals and shear: zero and
                 * negative-zero, tiny below tt_safe_inv's limit, huge, ties
                 * between the largest components, subnormal ones whose
                 * reciprocals overflow, and +-3e38, whose reciprocals and
                 * shear are subnormal: their t underflow to 0 and their
                 * box tests lose the margin, so the R-tree's packets
                 * trace such rays one by one, rtc_packet.h). */
            for (int k = 0; k < 3; k++) {
                static const float special[] = {0.0f,   -0.0f,  1.0f,   -1.0f, 1e-31f, -1e-31f,
                                                1e-35f, -1e-35f, 3e18f, -3e18f, 0.5f,  -0.5f,
                                                1e-40f, -1e-40f, 3e38f, -3e38f};
                const uint32_t u = next(&seed);
                r->org[k] = lo[k] + (hi[k] - lo[k]) * (0.3f + 0.4f * unit(&seed));
                r->dir[k] = u % 3u == 0 ? special[(u >> 8) % 16u] : 2.0f * unit(&seed) - 1.0f;
            }
            if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) r->dir[2] = 1.0f;
            break;
        case 6: /* (denormal), zero and NaN components, NaN and infinite
                 * intervals, tmin > tmax: the rows entries' own
                 * preparation (accel/wray_rows.h) and the batch's checks.
                 * Denormal components only with `denormal` (a set of
                 * their own, so the others keep 1e-35): infinite
                 * reciprocals beside finite or subnormal ones, which once
                 * crashed the wide BVH's AVX2 walk (dir (-0, 1e-37,
                 * -1e-37)) and made the R-tree's packets miss hits the
                 * single rays found; every path is held to the single
                 * rays on them. */
            for (int k = 0; k < 3; k++) {
                static const float special[] = {1e-40f, -1e-40f, 1.4e-45f, -1.4e-45f,
                                                1e-35f, -1e-35f, 0.0f,     -0.0f};
                const uint32_t u = next(&seed);
                const uint32_t pick = denormal ? (u >> 8) % 8u : 4u + (u >> 8) % 4u;
                r->org[k] = lo[k] + (hi[k] - lo[k]) * (0.3f + 0.4f * unit(&seed));
                r->dir[k] = u % 2u == 0 ? special[pick] : 2.0f * unit(&seed) - 1.0f;
            }
            if (denormal && lane % 16 == 3) /* every component denormal */
                for (int k = 0; k < 3; k++) r->dir[k] = (lane & 32) ? -1e-40f : 1e-40f;
            if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f)
                r->dir[1] = denormal ? -1e-40f : -1.0f;
            if (lane % 17 == 5) r->dir[lane % 3] = NAN;
            if (lane % 19 == 7) r->org[lane % 3] = NAN;
            if (lane % 23 == 2) r->tmax = NAN;
            if (lane % 13 == 1) r->tmin = 2.0f, r->tmax = 1.0f;
            if (lane % 29 == 4) r->tmin = INFINITY;
            break;
        default: /* inside the scene, random directions */
            for (int k = 0; k < 3; k++) {
                r->org[k] = lo[k] + (hi[k] - lo[k]) * unit(&seed);
                r->dir[k] = 2.0f * unit(&seed) - 1.0f;
            }
            break;
        }
    }
    *n_out = n;
    return rays;
}


/* tt_render with packets off, on and auto (and the counting pass): the
 * same hit buffer (triangle, t, shadow flag of every pixel), and the
 * summary says whether packets were traced and counts them. */
static void render_modes(tt_context *ctx, const tt_scene *scene, const tt_accel *a,
                         const tt_camera *cam, const char *what)
{
    static const uint32_t modes[] = {TT_PACKETS_OFF, TT_PACKETS_ON, TT_PACKETS_AUTO};
    uint8_t *first = NULL;
    size_t first_size = 0;
    for (int m = 0; m < 3; m++)
        for (int stats = 0; stats < 2; stats++) {
            tt_render_options ro;
            tt_render_options_default(&ro);
            ro.width = ro.height = 100; /* tiles cut by the border too */
            ro.keep_hits = 1;
            ro.stats = stats;
            ro.packets = modes[m];
            tt_render_result *res = NULL;
            CHECK_OK(ctx, tt_render(ctx, scene, a, cam, &ro, &res));
            if (!res) continue;
            size_t size = 0;
            const uint8_t *hits = tt_render_hits(res, &size);
            const tt_render_summary *s = tt_render_get_summary(res);
            const int has = a->vt->intersect_packet != NULL;
            CHECK_MSG(s->packets == (has && modes[m] != TT_PACKETS_OFF), "%s: summary.packets %d",
                      what, s->packets);
            if (stats && s->packets)
                CHECK_MSG(s->primary_packets.packets + s->primary_packets.fallback_rays > 0,
                          "%s: no packet counts", what);
            if (!first) {
                first = malloc(size);
                if (!first) exit(1);
                memcpy(first, hits, size);
                first_size = size;
            } else {
                CHECK_MSG(size == first_size && memcmp(first, hits, size) == 0,
                          "%s: render packets mode %u stats %d: hit buffer differs", what,
                          modes[m], stats);
            }
            tt_render_result_destroy(res);
        }
    free(first);
    tt_render_options ro;
    tt_render_options_default(&ro);
    ro.packets = 7;
    tt_render_result *res = NULL;
    CHECK(tt_render(ctx, scene, a, cam, &ro, &res) == TT_ERR_INVALID_ARGUMENT);
}

static void scene_view(tt_context *ctx, const char *file, const char *view, int small)
{
    g_small = small;
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, small ? "bruteforce" : "rtree");
    size_t n_shadow = 0, n_hostile = 0;
    tt_ray *shadow = NULL;
    tt_ray *primary = view_rays(bf, scene, &cam, &n_shadow, &shadow);
    tt_ray *hostile = hostile_rays(scene, &cam, 0, &n_hostile);
    tt_ray *denormal = hostile_rays(scene, &cam, 1, &n_hostile);
    tt_ray *edges = shadow_edge_rays(bf, shadow, n_shadow);
    /* (tt_shadow_ray returns 1 for a ray made: the view has a light, and
     * its shadow rays are checked, not an empty set) */
    CHECK_MSG(n_shadow > (size_t)SIZE * SIZE / 8, "%s: %zu shadow rays", view, n_shadow);
    static const char *names[] = {"rtree", "kdtree", "wbvh", "bruteforce"};
    for (size_t s = 0; s < sizeof names / sizeof names[0]; s++) {
        if (!tt_test_has_accel(names[s])) continue;
        if (!small && strcmp(names[s], "bruteforce") == 0) continue;
        for (int isa = TT_ISA_FIRST; isa <= TT_ISA_LAST; isa++) {
            if (!tt_isa_supported((tt_isa)isa)) continue;
            if (strcmp(names[s], "bruteforce") == 0 && isa != TT_ISA_FIRST) continue;
            tt_accel *a = tt_test_build_isa(ctx, scene, names[s], (tt_isa)isa);
            char what[128];
            snprintf(what, sizeof what, "%s %s primary", view, tt_isa_name((tt_isa)isa));
            check_rays(a, primary, (size_t)SIZE * SIZE, SIZE, what);
            snprintf(what, sizeof what, "%s %s shadow", view, tt_isa_name((tt_isa)isa));
            check_rays(a, shadow, n_shadow, 0, what);
            snprintf(what, sizeof what, "%s %s shadow ending on occluders", view,
                     tt_isa_name((tt_isa)isa));
            check_rays(a, edges, n_shadow, 0, what);
            snprintf(what, sizeof what, "%s %s hostile", view, tt_isa_name((tt_isa)isa));
            check_rays(a, hostile, n_hostile, SIZE, what);
            snprintf(what, sizeof what, "%s %s denormal", view, tt_isa_name((tt_isa)isa));
            check_rays(a, denormal, n_hostile, SIZE, what);
            snprintf(what, sizeof what, "%s %s %s render", tt_accel_name(a), view,
                     tt_isa_name((tt_isa)isa));
            render_modes(ctx, scene, a, &cam, what);
            tt_accel_destroy(a);
        }
    }
    free(primary);
    free(shadow);
    free(hostile);
    free(denormal);
    free(edges);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

/* The kd-tree's packet kernel serves HTR (the default); its other
 * traversals and builders must give the single-ray answers through the
 * packet entries too (ray by ray for BTR / SLTR / SEQ), and bigger leaves
 * (C_I 1.5) put more triangles a leaf in the packets' leaf test. */
static void kd_variants(tt_context *ctx, const char *file, const char *view)
{
    if (!tt_test_has_accel("kdtree")) return;
    g_small = 1;
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    size_t n_shadow = 0, n_hostile = 0;
    tt_ray *shadow = NULL;
    tt_ray *primary = view_rays(bf, scene, &cam, &n_shadow, &shadow);
    tt_ray *hostile = hostile_rays(scene, &cam, 0, &n_hostile);
    tt_ray *denormal = hostile_rays(scene, &cam, 1, &n_hostile);
    static const struct {
        tt_kd_builder builder;
        tt_kd_traversal traversal;
        float ci;
        const char *name;
    } v[] = {{TT_KD_BINNED, TT_KD_HTR, 0.0f, "binned htr"},
             {TT_KD_NLOGN, TT_KD_HTR, 1.5f, "htr C_I 1.5"},
             {TT_KD_NLOGN, TT_KD_BTR, 0.0f, "btr"},
             {TT_KD_NLOGN, TT_KD_SLTR, 0.0f, "sltr"}};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
        for (int isa = TT_ISA_FIRST; isa <= TT_ISA_LAST; isa++) {
            if (!tt_isa_supported((tt_isa)isa)) continue;
            tt_build_options o;
            tt_build_options_default(&o);
            o.accel = "kdtree";
            o.isa = (tt_isa)isa;
            o.kdtree.builder = v[i].builder;
            o.kdtree.traversal = v[i].traversal;
            if (v[i].ci > 0.0f) o.kdtree.cost_intersect = v[i].ci;
            tt_accel *a = NULL;
            REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &o, &a));
            char what[128];
            snprintf(what, sizeof what, "%s kdtree %s %s primary", view, v[i].name,
                     tt_isa_name((tt_isa)isa));
            check_rays(a, primary, (size_t)SIZE * SIZE, SIZE, what);
            snprintf(what, sizeof what, "%s kdtree %s %s shadow", view, v[i].name,
                     tt_isa_name((tt_isa)isa));
            check_rays(a, shadow, n_shadow, 0, what);
            snprintf(what, sizeof what, "%s kdtree %s %s hostile", view, v[i].name,
                     tt_isa_name((tt_isa)isa));
            check_rays(a, hostile, n_hostile, SIZE, what);
            snprintf(what, sizeof what, "%s kdtree %s %s denormal", view, v[i].name,
                     tt_isa_name((tt_isa)isa));
            check_rays(a, denormal, n_hostile, SIZE, what);
            tt_accel_destroy(a);
        }
    free(primary);
    free(shadow);
    free(hostile);
    free(denormal);
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
}

/* A bad packets option is refused by name. */
static void bad_option(tt_context *ctx)
{
    tt_scene *scene = tt_test_load_scene(ctx, "cornell_box.obj");
    tt_accel *a = tt_test_build_default(ctx, scene, "rtree");
    tt_ray r = {{0.0f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, INFINITY};
    tt_hit h;
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    CHECK(bo.packets == TT_PACKETS_AUTO);
    bo.packets = 3;
    CHECK(tt_intersect(a, &r, 1, &h, NULL, &bo) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "packets") != NULL);
    tt_accel_destroy(a);
    tt_scene_destroy(scene);
}

/* Occlusion packets of a few rays through a grid's vertices and edge
 * midpoints (zero edge functions: the double-precision recomputation),
 * segments ending just short of the plane or past it, leaves with odd
 * triangle counts and a zero-area triangle: the leaf test that takes two
 * triangles at once when at most half a vector of lanes is left (AVX2
 * kp_pairs) must answer as single rays, whatever the packet size. */
static void grid_pairs(tt_context *ctx)
{
    if (!tt_test_has_accel("kdtree")) return;
    enum { G = 7, NV = (G + 1) * (G + 1) };
    float vert[3 * (NV + 3)];
    uint32_t idx[3 * (4 * G * G + 3)];
    size_t nt = 0;
    for (int y = 0; y <= G; y++)
        for (int x = 0; x <= G; x++) {
            float *v = &vert[3 * (y * (G + 1) + x)];
            v[0] = (float)x, v[1] = (float)y, v[2] = 0.0f;
        }
    for (int y = 0; y < G; y++)
        for (int x = 0; x < G; x++) {
            const uint32_t a = (uint32_t)(y * (G + 1) + x), b = a + 1, c = a + G + 1, d = c + 1;
            const uint32_t t[6] = {a, b, d, a, d, c};
            /* rows y < 2 twice, each copy right after its triangle: equal
             * hits of neighbours in one leaf, where the first must win */
            const int copies = y < 2 ? 2 : 1;
            for (int h = 0; h < 2; h++)
                for (int k = 0; k < copies; k++, nt++)
                    for (int q = 0; q < 3; q++) idx[3 * nt + (size_t)q] = t[3 * h + q];
        }
    /* a zero-area triangle on the row y = 2 and a copy of the first */
    float *e = &vert[3 * NV];
    e[0] = 1.0f, e[1] = 2.0f, e[2] = 0.0f;
    e[3] = 2.0f, e[4] = 2.0f, e[5] = 0.0f;
    e[6] = 3.0f, e[7] = 2.0f, e[8] = 0.0f;
    idx[3 * nt] = NV, idx[3 * nt + 1] = NV + 1, idx[3 * nt + 2] = NV + 2, nt++;
    idx[3 * nt] = idx[0], idx[3 * nt + 1] = idx[1], idx[3 * nt + 2] = idx[2], nt++;
    tt_scene *scene = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, vert, NV + 3, idx, nt, &scene));
    /* targets at vertices, edge midpoints and face centres, and inside
     * triangles (k >= 4); dyadic offsets so the rays pass exactly through
     * them */
    enum { N = 6 * (2 * G + 1) * (2 * G + 1) };
    tt_ray *rays = malloc(N * sizeof *rays);
    if (!rays) exit(1);
    size_t n = 0;
    for (int y = 0; y <= 2 * G; y++)
        for (int x = 0; x <= 2 * G; x++)
            for (int k = 0; k < 6; k++) {
                tt_ray *r = &rays[n++];
                const float off[3] = {k & 1 ? 0.25f : -0.125f, k & 2 ? 0.375f : -0.25f, 1.0f};
                const float in = k >= 4 ? 1.0f : 0.0f;
                r->org[0] = 0.5f * (float)x + 0.25f * in + off[0];
                r->org[1] = 0.5f * (float)y + 0.0625f * in + off[1];
                r->org[2] = off[2];
                for (int j = 0; j < 3; j++) r->dir[j] = -off[j];
                r->tmin = 0.0f;
                /* t = 1 at the plane: short of it, exactly at it, past it */
                r->tmax = (n % 3 == 0) ? 0.9990234375f : (n % 3 == 1) ? 1.0f : 2.0f;
            }
    for (int isa = TT_ISA_FIRST; isa <= TT_ISA_LAST; isa++) {
        if (!tt_isa_supported((tt_isa)isa)) continue;
        for (int cap = 0; cap < 2; cap++) {
            tt_build_options o;
            tt_build_options_default(&o);
            o.accel = "kdtree";
            o.isa = (tt_isa)isa;
            if (cap) o.kdtree.cost_intersect = 1.5f; /* bigger leaves */
            tt_accel *a = NULL;
            REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &o, &a));
            char what[96];
            snprintf(what, sizeof what, "grid pairs %s%s", tt_isa_name((tt_isa)isa),
                     cap ? " C_I 1.5" : "");
            g_small = 1;
            check_rays(a, rays, n, 0, what);
            tt_accel_destroy(a);
        }
    }
    free(rays);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    bad_option(ctx);
    grid_pairs(ctx);
    scene_view(ctx, "bun_zipper_res4.ply", "bunny_res4:main", 1);
    scene_view(ctx, "cornell_box.obj", "cornell:main", 1);
    scene_view(ctx, "bun_zipper.ply", "bunny:main", 0);
    scene_view(ctx, "sibenik.obj", "sibenik:main", 0);
    scene_view(ctx, "conference.ply", "conference:main", 0);
    kd_variants(ctx, "cornell_box.obj", "cornell:main");
    kd_variants(ctx, "bun_zipper_res4.ply", "bunny_res4:main");
    tt_context_destroy(ctx);
    return tt_test_finish();
}
