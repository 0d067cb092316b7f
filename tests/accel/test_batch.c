/* The batch calls (tt_intersect, tt_occluded and their strided forms) give,
 * ray by ray, exactly what the single-ray calls give: the same hit bit for
 * bit (t, u, v, triangle) and the same occlusion, for every structure of
 * the build and every traversal, R-tree builders and layouts, the scalar
 * and the best ISA path, at 1 and 2 threads and any chunk size, in
 * every layout (AoS, SoA with separate x/y/z arrays, broadcast origins,
 * strided outputs). Bad rays get their status and a miss while the rest of
 * the batch is traced; the message names the first bad index. Statistics
 * sum to the single-ray counts, and camera rays traced as a batch give the
 * renderer's hit buffer. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

#define W 48
#define H 48
#define N_RANDOM 3000

static uint32_t next(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}

static float unit(uint32_t *x) { return (float)(next(x) >> 8) * (1.0f / 16777216.0f); }

/* Camera rays of bunny:main, then random rays: origins in and around the
 * scene box, some axis-parallel directions, some finite or empty
 * intervals. Bad rays are put at the indices in `bad`. */
static tt_ray *make_rays(const tt_scene *scene, const tt_camera *cam, size_t *n_out,
                         const size_t *bad, size_t n_bad)
{
    size_t n = (size_t)W * H + N_RANDOM;
    tt_ray *rays = malloc(n * sizeof *rays);
    if (!rays) exit(1);
    if (tt_camera_rays(cam, W, H, rays) != TT_OK) exit(1);
    float lo[3], hi[3];
    tt_scene_bounds(scene, lo, hi);
    uint32_t seed = 12345;
    for (size_t i = (size_t)W * H; i < n; i++) {
        tt_ray *r = &rays[i];
        for (int k = 0; k < 3; k++) {
            float e = hi[k] - lo[k];
            r->org[k] = lo[k] - 0.5f * e + 2.0f * e * unit(&seed);
            r->dir[k] = unit(&seed) * 2.0f - 1.0f;
        }
        if (i % 7 == 0) r->dir[i % 3] = 0.0f;
        if (i % 11 == 0) r->dir[0] = r->dir[1] = 0.0f, r->dir[2] = -1.0f;
        if (r->dir[0] == 0.0f && r->dir[1] == 0.0f && r->dir[2] == 0.0f) r->dir[1] = 1.0f;
        r->tmin = (i % 5 == 0) ? 0.01f * unit(&seed) : 0.0f;
        r->tmax = (i % 3 == 0) ? 0.3f * unit(&seed) : INFINITY;
        if (i % 101 == 0) r->tmax = r->tmin; /* empty interval: legal, a miss */
    }
    for (size_t b = 0; b < n_bad; b++) {
        tt_ray *r = &rays[bad[b]];
        switch (b % 6) {
        case 0: r->tmin = -1.0f; break;
        case 1: r->dir[0] = r->dir[1] = r->dir[2] = 0.0f; break;
        case 2: r->org[1] = NAN; break;
        case 3: r->tmax = NAN; break;
        /* infinities: the batch's branch-free finiteness test (x - x) */
        case 4: r->org[2] = INFINITY; break;
        default: r->dir[0] = -INFINITY; break;
        }
    }
    *n_out = n;
    return rays;
}

static int hit_miss(const tt_hit *h)
{
    return h->prim == TT_INVALID_ID && isinf(h->t) && h->t > 0 && h->u == 0.0f && h->v == 0.0f;
}

/* One structure at one thread count: AoS and strided batches against the
 * single-ray calls. */
static void check_accel(tt_context *ctx, const tt_accel *accel, const tt_ray *rays, size_t n,
                        const size_t *bad, size_t n_bad, const char *what)
{
    tt_hit *one = malloc(n * sizeof *one), *many = malloc(n * sizeof *many);
    uint8_t *occ_one = malloc(n), *occ_many = malloc(n);
    tt_status *st_one = malloc(n * sizeof *st_one), *st_many = malloc(n * sizeof *st_many);
    if (!one || !many || !occ_one || !occ_many || !st_one || !st_many) exit(1);
    for (size_t i = 0; i < n; i++) {
        int o = 0;
        st_one[i] = tt_intersect1(accel, &rays[i], &one[i]);
        tt_status so = tt_occluded1(accel, &rays[i], &o);
        CHECK(so == st_one[i]);
        occ_one[i] = (uint8_t)o;
    }
    for (size_t b = 0; b < n_bad; b++) CHECK(st_one[bad[b]] == TT_ERR_INVALID_ARGUMENT);

    /* work cut into runs of consecutive rays, or into tiles of an image
     * (also widths that divide neither the batch nor 16) */
    static const uint32_t chunks[] = {0, 1, 7, 1000, 0, 0, 0};
    static const uint32_t widths[] = {0, 0, 0, 0, W, 37, 1};
    for (size_t c = 0; c < sizeof chunks / sizeof chunks[0]; c++) {
        tt_batch_options bo;
        tt_batch_options_default(&bo);
        bo.chunk = chunks[c];
        bo.image_width = widths[c];
        memset(many, 0xAB, n * sizeof *many);
        memset(occ_many, 0xAB, n);
        tt_status st = tt_intersect(accel, rays, n, many, st_many, &bo);
        CHECK_MSG(st == (n_bad ? TT_ERR_INVALID_ARGUMENT : TT_OK), "%s: %s", what,
                  tt_context_last_error(ctx));
        if (n_bad) {
            char expect[64];
            snprintf(expect, sizeof expect, "ray %zu of %zu: ", bad[0], n);
            CHECK_MSG(strstr(tt_context_last_error(ctx), expect) != NULL, "%s: message '%s'",
                      what, tt_context_last_error(ctx));
            CHECK(strstr(tt_context_last_error(ctx), "negative tmin") != NULL);
        }
        size_t differ = 0;
        for (size_t i = 0; i < n; i++) {
            if (st_many[i] != st_one[i]) differ++;
            else if (st_one[i] == TT_OK && memcmp(&one[i], &many[i], sizeof(tt_hit)) != 0)
                differ++;
            else if (st_one[i] != TT_OK && !hit_miss(&many[i])) differ++;
        }
        CHECK_MSG(differ == 0,
                  "%s chunk %u width %u: %zu of %zu closest hits differ from tt_intersect1", what,
                  chunks[c], widths[c], differ, n);

        st = tt_occluded(accel, rays, n, occ_many, st_many, &bo);
        CHECK(st == (n_bad ? TT_ERR_INVALID_ARGUMENT : TT_OK));
        differ = 0;
        for (size_t i = 0; i < n; i++) {
            if (st_many[i] != st_one[i]) differ++;
            else if (st_one[i] == TT_OK && occ_many[i] != occ_one[i]) differ++;
            else if (st_one[i] != TT_OK && occ_many[i] != 0) differ++;
        }
        CHECK_MSG(differ == 0,
                  "%s chunk %u width %u: %zu of %zu occlusions differ from tt_occluded1", what,
                  chunks[c], widths[c], differ, n);
    }

    /* Structure of arrays: x, y, z apart; tmin/tmax absent (0, +inf);
     * results into a strided interleaved buffer and a plain prim array. */
    float *soa = malloc(6 * n * sizeof *soa);
    tt_ray *plain = malloc(n * sizeof *plain);
    float *out = malloc(4 * n * sizeof *out);
    uint32_t *prim_only = malloc(n * sizeof *prim_only);
    if (!soa || !plain || !out || !prim_only) exit(1);
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            soa[k * n + i] = rays[i].org[k];
            soa[(3 + k) * n + i] = rays[i].dir[k];
        }
        plain[i] = rays[i];
        plain[i].tmin = 0.0f;
        plain[i].tmax = INFINITY;
    }
    tt_ray_arrays ra;
    memset(&ra, 0, sizeof ra);
    for (int k = 0; k < 3; k++) {
        ra.org[k] = soa + k * n;
        ra.dir[k] = soa + (3 + k) * n;
    }
    ra.org_stride = ra.dir_stride = sizeof(float);
    tt_hit_arrays ha = {out + 0, 4 * sizeof(float), out + 1, 4 * sizeof(float),
                        out + 2, 4 * sizeof(float), (uint32_t *)(void *)(out + 3), 4 * sizeof(float)};
    /* what each ray of the SoA set must give: tt_intersect1's status; the
     * call itself TT_ERR_INVALID_ARGUMENT when any ray is refused */
    size_t refused = 0;
    for (size_t i = 0; i < n; i++) {
        tt_hit h;
        st_one[i] = tt_intersect1(accel, &plain[i], &h);
        refused += st_one[i] != TT_OK;
    }
    const tt_status want = refused ? TT_ERR_INVALID_ARGUMENT : TT_OK;
    tt_status st = tt_intersect_arrays(accel, &ra, n, &ha, st_many, NULL);
    CHECK_MSG(st == want, "%s: tt_intersect_arrays gave %s, want %s", what, tt_strerror(st),
              tt_strerror(want));
    st = tt_intersect(accel, plain, n, many, NULL, NULL);
    CHECK_MSG(st == want, "%s: tt_intersect gave %s, want %s", what, tt_strerror(st),
              tt_strerror(want));
    size_t differ = 0, status_differ = 0;
    for (size_t i = 0; i < n; i++) {
        status_differ += st_many[i] != st_one[i];
        if (st_many[i] != TT_OK) continue;
        if (memcmp(out + 4 * i, &many[i], sizeof(tt_hit)) != 0) differ++;
    }
    CHECK_MSG(status_differ == 0, "%s: %zu SoA ray statuses differ from tt_intersect1's", what,
              status_differ);
    CHECK_MSG(differ == 0, "%s: %zu SoA hits differ from the AoS batch", what, differ);
    tt_hit_arrays only = {NULL, 0, NULL, 0, NULL, 0, prim_only, sizeof(uint32_t)};
    st = tt_intersect_arrays(accel, &ra, n, &only, NULL, NULL);
    CHECK_MSG(st == want, "%s: prim-only tt_intersect_arrays gave %s", what, tt_strerror(st));
    differ = 0;
    for (size_t i = 0; i < n; i++)
        if (st_many[i] == TT_OK && prim_only[i] != many[i].prim) differ++;
    CHECK_MSG(differ == 0, "%s: %zu prim-only results differ", what, differ);
    /* occlusion written every 3rd byte */
    uint8_t *occ3 = malloc(3 * n);
    if (!occ3) exit(1);
    st = tt_occluded(accel, plain, n, occ_many, NULL, NULL);
    CHECK_MSG(st == want, "%s: tt_occluded gave %s", what, tt_strerror(st));
    st = tt_occluded_arrays(accel, &ra, n, occ3, 3, st_many, NULL);
    CHECK_MSG(st == want, "%s: tt_occluded_arrays gave %s", what, tt_strerror(st));
    differ = 0;
    status_differ = 0;
    for (size_t i = 0; i < n; i++) {
        status_differ += st_many[i] != st_one[i];
        if (st_many[i] == TT_OK && occ3[3 * i] != occ_many[i]) differ++;
    }
    CHECK_MSG(status_differ == 0, "%s: %zu strided occlusion statuses differ", what,
              status_differ);
    CHECK_MSG(differ == 0, "%s: %zu strided occlusions differ", what, differ);

    free(occ3);
    free(soa);
    free(plain);
    free(out);
    free(prim_only);
    free(one);
    free(many);
    free(occ_one);
    free(occ_many);
    free(st_one);
    free(st_many);
}

/* Camera rays with one origin given once (stride 0) and the eye's start
 * hint: the renderer's hit buffer, and tt_intersect1_ex with that hint. */
static void check_camera_batch(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                               const tt_camera *cam, const char *what)
{
    const size_t n = (size_t)W * H;
    tt_ray *rays = malloc(n * sizeof *rays);
    tt_hit *hits = malloc(n * sizeof *hits);
    uint8_t *occ = malloc(n);
    if (!rays || !hits || !occ) exit(1);
    REQUIRE_OK(ctx, tt_camera_rays(cam, W, H, rays));
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    bo.start_hint = tt_accel_locate(accel, cam->eye);
    bo.image_width = W;
    tt_ray_arrays ra;
    memset(&ra, 0, sizeof ra);
    for (int k = 0; k < 3; k++) {
        ra.org[k] = &cam->eye[k];
        ra.dir[k] = &rays[0].dir[k];
    }
    ra.org_stride = 0;
    ra.dir_stride = sizeof(tt_ray);
    const ptrdiff_t s = sizeof(tt_hit);
    tt_hit_arrays ha = {&hits[0].t, s, &hits[0].u, s, &hits[0].v, s, &hits[0].prim, s};
    CHECK_OK(ctx, tt_intersect_arrays(accel, &ra, n, &ha, NULL, &bo));

    tt_render_options ro;
    tt_render_options_default(&ro);
    ro.width = W;
    ro.height = H;
    ro.keep_hits = 1;
    tt_render_result *res;
    REQUIRE_OK(ctx, tt_render(ctx, scene, accel, cam, &ro, &res));
    size_t size;
    const uint8_t *buf = tt_render_hits(res, &size);
    size_t differ = 0, hint_differ = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t prim;
        float t;
        memcpy(&prim, buf + 12 * i, 4);
        memcpy(&t, buf + 12 * i + 4, 4);
        if (prim != hits[i].prim || memcmp(&t, &hits[i].t, 4) != 0) differ++;
        tt_hit h;
        tt_trace_args args = {bo.start_hint, TT_INVALID_ID, NULL};
        tt_intersect1_ex(accel, &rays[i], &h, &args);
        if (memcmp(&h, &hits[i], sizeof h) != 0) hint_differ++;
    }
    CHECK_MSG(differ == 0, "%s: %zu of %zu camera rays differ from tt_render's hit buffer", what,
              differ, n);
    CHECK_MSG(hint_differ == 0, "%s: %zu camera rays differ from tt_intersect1_ex with the hint",
              what, hint_differ);
    tt_render_result_destroy(res);

    /* Statistics: the batch's sums are the single-ray counting calls' sums
     * when it traces ray by ray (packets count their own walk: their
     * counts are checked in test_packets.c). */
    tt_ray_stats batch_stats, single_stats;
    memset(&batch_stats, 0, sizeof batch_stats);
    memset(&single_stats, 0, sizeof single_stats);
    bo.stats = &batch_stats;
    bo.packets = TT_PACKETS_OFF;
    tt_hit *counted = malloc(n * sizeof *counted);
    if (!counted) exit(1);
    CHECK_OK(ctx, tt_intersect(accel, rays, n, counted, NULL, &bo));
    CHECK_OK(ctx, tt_occluded(accel, rays, n, occ, NULL, &bo));
    for (size_t i = 0; i < n; i++) {
        tt_hit h;
        int o;
        tt_trace_args args = {bo.start_hint, TT_INVALID_ID, &single_stats};
        tt_intersect1_ex(accel, &rays[i], &h, &args);
        args.end_hint = TT_INVALID_ID;
        tt_occluded1_ex(accel, &rays[i], &o, &args);
    }
    CHECK(memcmp(counted, hits, n * sizeof *hits) == 0);
    CHECK_MSG(batch_stats.rays == 2 * n && single_stats.rays == 2 * n, "%s: rays %llu %llu", what,
              (unsigned long long)batch_stats.rays, (unsigned long long)single_stats.rays);
    CHECK_MSG(memcmp(&batch_stats, &single_stats, sizeof batch_stats) == 0,
              "%s: batch statistics (nodes %llu, triangles %llu) differ from single-ray ones "
              "(nodes %llu, triangles %llu)",
              what, (unsigned long long)batch_stats.nodes,
              (unsigned long long)batch_stats.triangles, (unsigned long long)single_stats.nodes,
              (unsigned long long)single_stats.triangles);
    /* Per-packet counts (packet_stats, alone: stats NULL): the same hits;
     * with packets on, a structure with a packet walk reports packets and
     * their node visits, at least one active ray a visit; ray by ray, none. */
    tt_packet_counts pc;
    memset(&pc, 0, sizeof pc);
    bo.stats = NULL;
    bo.packet_stats = &pc;
    bo.packets = TT_PACKETS_ON;
    CHECK_OK(ctx, tt_intersect(accel, rays, n, counted, NULL, &bo));
    CHECK(memcmp(counted, hits, n * sizeof *hits) == 0);
    CHECK_MSG(pc.active_lanes >= pc.node_visits && (pc.packets > 0) == (pc.node_visits > 0),
              "%s: packets %llu, node visits %llu, active lanes %llu", what,
              (unsigned long long)pc.packets, (unsigned long long)pc.node_visits,
              (unsigned long long)pc.active_lanes);
    memset(&pc, 0, sizeof pc);
    bo.packets = TT_PACKETS_OFF;
    CHECK_OK(ctx, tt_intersect(accel, rays, n, counted, NULL, &bo));
    CHECK(memcmp(counted, hits, n * sizeof *hits) == 0);
    CHECK(pc.packets == 0 && pc.node_visits == 0 && pc.fallback_rays == 0);
    free(counted);
    free(rays);
    free(hits);
    free(occ);
}

static void check_arguments(tt_context *ctx, const tt_accel *accel, const tt_ray *rays)
{
    tt_hit h;
    uint8_t o;
    tt_ray_arrays ra;
    memset(&ra, 0, sizeof ra);
    CHECK(tt_intersect(NULL, rays, 1, &h, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_occluded(NULL, rays, 1, &o, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_intersect(accel, NULL, 1, &h, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "tt_intersect") != NULL);
    CHECK(tt_intersect(accel, rays, 1, NULL, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_occluded(accel, rays, 1, NULL, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_intersect(accel, NULL, 0, NULL, NULL, NULL) == TT_OK);
    CHECK(tt_occluded(accel, NULL, 0, NULL, NULL, NULL) == TT_OK);
    tt_hit_arrays ha = {&h.t, 0, NULL, 0, NULL, 0, NULL, 0};
    CHECK(tt_intersect_arrays(accel, &ra, 1, &ha, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_intersect_arrays(accel, NULL, 1, &ha, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_occluded_arrays(accel, &ra, 1, &o, 1, NULL, NULL) == TT_ERR_INVALID_ARGUMENT);
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    CHECK(bo.start_hint == TT_INVALID_ID && bo.stats == NULL && bo.chunk == 0 &&
          bo.image_width == 0);
    bo.chunk = 0xFFFFFFFFu;
    CHECK(tt_intersect(accel, rays, 1, &h, NULL, &bo) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "chunk") != NULL);
    bo.chunk = 0;
    bo.image_width = 0xFFFFFFFFu;
    CHECK(tt_occluded(accel, rays, 1, &o, NULL, &bo) == TT_ERR_INVALID_ARGUMENT);
    CHECK(strstr(tt_context_last_error(ctx), "image_width") != NULL);
    /* one bad ray alone: its status, a miss, and the message */
    tt_ray bad = rays[0];
    bad.dir[0] = bad.dir[1] = bad.dir[2] = 0.0f;
    tt_status rs = TT_OK;
    h.prim = 7;
    CHECK(tt_intersect(accel, &bad, 1, &h, &rs, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(rs == TT_ERR_INVALID_ARGUMENT && hit_miss(&h));
    CHECK_MSG(strstr(tt_context_last_error(ctx), "ray 0 of 1: ray with a zero direction") != NULL,
              "message '%s'", tt_context_last_error(ctx));
    /* a direction too short (largest component below 2^-80), through both
     * quick checks (single rays and rows) */
    bad.dir[1] = -0x1.fffffep-81f;
    rs = TT_OK;
    CHECK(tt_occluded(accel, &bad, 1, &o, &rs, NULL) == TT_ERR_INVALID_ARGUMENT);
    CHECK(rs == TT_ERR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(tt_context_last_error(ctx), "ray 0 of 1: ray with a direction too short") !=
                  NULL,
              "message '%s'", tt_context_last_error(ctx));
}

/* Shadow rays of a camera's hits, in image order with the misses left out,
 * the way a renderer hands them over (no image width): the batch finds
 * their rows and cuts items along them (batch.c). Every answer is the
 * single ray's, in the tt_ray form and in structure of arrays, packets
 * automatic and on. */
static void check_shadow_batch(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                               const tt_camera *cam, const char *what)
{
    const uint32_t w = 97, h = 61; /* a width no power of two */
    const size_t n = (size_t)w * h;
    tt_ray *rays = malloc(n * sizeof *rays), *sr = malloc(n * sizeof *sr);
    tt_hit *hits = malloc(n * sizeof *hits);
    uint8_t *occ = malloc(n), *want = malloc(n);
    float *soa = malloc(8 * n * sizeof *soa);
    if (!rays || !sr || !hits || !occ || !want || !soa) exit(1);
    REQUIRE_OK(ctx, tt_camera_rays(cam, w, h, rays));
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    bo.image_width = w;
    CHECK_OK(ctx, tt_intersect(accel, rays, n, hits, NULL, &bo));
    size_t ns = 0;
    for (size_t i = 0; i < n; i++)
        if (hits[i].prim != TT_INVALID_ID && tt_shadow_ray(scene, cam, &rays[i], &hits[i], &sr[ns]))
            ns++;
    CHECK_MSG(ns > 1024, "%s: %zu shadow rays", what, ns);
    for (size_t i = 0; i < ns; i++) {
        int o;
        tt_occluded1(accel, &sr[i], &o);
        want[i] = (uint8_t)(o != 0);
        for (int k = 0; k < 3; k++) {
            soa[k * ns + i] = sr[i].org[k];
            soa[(3 + k) * ns + i] = sr[i].dir[k];
        }
        soa[6 * ns + i] = sr[i].tmin;
        soa[7 * ns + i] = sr[i].tmax;
    }
    tt_ray_arrays ra;
    memset(&ra, 0, sizeof ra);
    for (int k = 0; k < 3; k++) {
        ra.org[k] = soa + k * ns;
        ra.dir[k] = soa + (3 + k) * ns;
    }
    ra.tmin = soa + 6 * ns;
    ra.tmax = soa + 7 * ns;
    ra.org_stride = ra.dir_stride = ra.tmin_stride = ra.tmax_stride = sizeof(float);
    for (int mode = 0; mode < 4; mode++) {
        tt_batch_options_default(&bo);
        bo.packets = mode & 1 ? TT_PACKETS_ON : TT_PACKETS_AUTO;
        memset(occ, 0xAB, ns);
        if (mode & 2) CHECK_OK(ctx, tt_occluded_arrays(accel, &ra, ns, occ, 1, NULL, &bo));
        else CHECK_OK(ctx, tt_occluded(accel, sr, ns, occ, NULL, &bo));
        size_t differ = 0;
        for (size_t i = 0; i < ns; i++) differ += occ[i] != want[i];
        CHECK_MSG(differ == 0, "%s: %zu of %zu shadow rays (mode %d) differ from tt_occluded1",
                  what, differ, ns, mode);
    }
    free(rays);
    free(sr);
    free(hits);
    free(occ);
    free(want);
    free(soa);
}

int main(void)
{
    static const size_t bad[] = {5, 77, 2400, 4000, 4100, 4200};
    const size_t n_bad = sizeof bad / sizeof bad[0];
    for (int threads = 1; threads <= 2; threads++) {
        tt_context_options co;
        tt_context_options_default(&co);
        co.threads = threads;
        tt_context *ctx;
        REQUIRE_OK(NULL, tt_context_create(&co, &ctx));
        tt_scene *scene = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
        tt_camera cam;
        tt_test_view(ctx, "bunny_res4:main", &cam);
        size_t n;
        tt_ray *rays = make_rays(scene, &cam, &n, bad, n_bad);

        struct {
            const char *accel;
            int traversal; /* -1: default */
            tt_rtree_build build;
            tt_rtree_layout layout;
            tt_isa isa;
        } variants[] = {
            {"bruteforce", -1, 0, 0, TT_ISA_AUTO},
            {"rtree", TT_RTREE_STACKLESS, 0, 0, TT_ISA_AUTO},
            {"rtree", TT_RTREE_ORDERED, 0, 0, TT_ISA_AUTO},
            {"rtree", TT_RTREE_STACK, 0, 0, TT_ISA_AUTO},
            {"rtree", -1, TT_RTREE_BUILD_SAH, TT_RTREE_LAYOUT_COMPACT, TT_ISA_AUTO},
            {"rtree", -1, TT_RTREE_BUILD_SAH, TT_RTREE_LAYOUT_COMPACT, TT_ISA_SCALAR},
            {"rtree", -1, TT_RTREE_BUILD_STR, TT_RTREE_LAYOUT_COMPACT, TT_ISA_AUTO},
            {"kdtree", TT_KD_HTR, 0, 0, TT_ISA_AUTO},
            {"kdtree", TT_KD_HTR, 0, 0, TT_ISA_SCALAR},
            {"kdtree", TT_KD_BTR, 0, 0, TT_ISA_AUTO},
            {"kdtree", TT_KD_SLTR, 0, 0, TT_ISA_AUTO},
            {"kdtree", TT_KD_SEQ, 0, 0, TT_ISA_AUTO},
            {"embree", -1, 0, 0, TT_ISA_AUTO},
        };
        for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
            if (!tt_test_has_accel(variants[v].accel)) continue;
            tt_build_options bo;
            tt_build_options_default(&bo);
            bo.accel = variants[v].accel;
            bo.isa = variants[v].isa;
            bo.rtree.build = variants[v].build;
            bo.rtree.layout = variants[v].layout;
            if (variants[v].traversal >= 0) {
                bo.rtree.traversal = (tt_rtree_traversal)variants[v].traversal;
                bo.kdtree.traversal = (tt_kd_traversal)variants[v].traversal;
            }
            tt_accel *accel;
            REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &accel));
            char what[160];
            snprintf(what, sizeof what, "%s traversal %d build %d layout %d isa %s, %d thread(s)",
                     variants[v].accel, variants[v].traversal, (int)variants[v].build,
                     (int)variants[v].layout, tt_isa_name(tt_accel_isa(accel)), threads);
            check_accel(ctx, accel, rays, n, bad, n_bad, what);
            check_camera_batch(ctx, scene, accel, &cam, what);
            check_shadow_batch(ctx, scene, accel, &cam, what);
            if (v == 1) check_arguments(ctx, accel, rays);
            tt_accel_destroy(accel);
        }
        free(rays);
        tt_scene_destroy(scene);
        tt_context_destroy(ctx);
    }
    return tt_test_finish();
}
