/* The automatic packet choice (TT_PACKETS_AUTO, tt_packet_coherent in
 * accel/packets.h): coherent rows are a packet, incoherent ones are not,
 * judged from the sampled runs (the first and last rows included); and
 * through the batch calls, a view's shadow rays to its point light take
 * the packet path in every item (the packet counts equal those of
 * TT_PACKETS_ON), ambient-occlusion rays take none, and either way the
 * answers are the single rays' (TT_PACKETS_OFF). The structure's word
 * (vt->packets_pay): the R-tree's rule on probe counts, and the batch
 * following a structure that says packets never or always pay. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "accel/accel.h"
#include "accel/packets.h"
#include "check.h"

#define SIZE 96

static uint32_t next(uint32_t *x)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return *x;
}

static float unit(uint32_t *x) { return (float)(next(x) >> 8) * (1.0f / 16777216.0f); }

static void set_row(tt_packet_rays *p, uint32_t j, const float org[3], const float dir[3],
                    float tmax)
{
    tt_packet_ray_set(p, j, org, dir, 0.0f, tmax);
}

/* A 16 x 16 camera tile: one eye, directions through a small patch. */
static void camera_tile(tt_packet_rays *p)
{
    const float eye[3] = {0.0f, 1.0f, -5.0f};
    for (uint32_t j = 0; j < 256; j++) {
        const float dir[3] = {0.2f + 0.01f * (float)(j % 16), 0.1f - 0.01f * (float)(j / 16), 1.0f};
        set_row(p, j, eye, dir, INFINITY);
    }
    p->n = 256;
}

/* Shadow rays from points spread over a floor to one light: the
 * directions fan out (past the direction box), the ends meet; a light of
 * size `size` (soft shadows) spreads them a little. */
static void light_rays(tt_packet_rays *p, uint32_t n, int open, float size)
{
    const float light[3] = {0.0f, 2.0f, 0.0f};
    uint32_t seed = 4242u;
    for (uint32_t j = 0; j < n; j++) {
        const float org[3] = {-8.0f + 16.0f * (float)(j % 16) / 15.0f, 0.0f,
                              -8.0f + 16.0f * (float)(j / 16) / 15.0f};
        float d[3];
        for (int k = 0; k < 3; k++) d[k] = light[k] + size * (unit(&seed) - 0.5f) - org[k];
        const float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; k++) d[k] /= len;
        set_row(p, j, org, d, open ? INFINITY : len * (1.0f - 1e-4f));
    }
    p->n = n;
}

static void rule_on_rows(void)
{
    static tt_packet_rays p;
    camera_tile(&p);
    CHECK_MSG(tt_packet_coherent(&p), "a camera tile is coherent");
    p.n = TT_PACKET_MIN - 1;
    CHECK_MSG(!tt_packet_coherent(&p), "fewer than TT_PACKET_MIN rows are no packet");
    p.n = TT_PACKET_MIN;
    CHECK(tt_packet_coherent(&p));

    /* an outlier in the first or the last row: the sample's end runs see it */
    const float back[3] = {0.0f, 0.0f, -1.0f};
    for (uint32_t at = 0; at < 2; at++) {
        camera_tile(&p);
        const uint32_t j = at ? p.n - 1 : 0;
        const float org[3] = {p.org[0][j], p.org[1][j], p.org[2][j]};
        set_row(&p, j, org, back, INFINITY);
        CHECK_MSG(!tt_packet_coherent(&p), "outlier in row %u", j);
    }

    /* rows past n are not read: outliers there change nothing */
    for (uint32_t n = TT_PACKET_MIN; n < 256; n++) {
        camera_tile(&p);
        const float far[3] = {1e6f, -1e6f, 1e6f};
        for (uint32_t j = n; j < 256; j++) set_row(&p, j, far, back, 1.0f);
        p.n = n;
        CHECK_MSG(tt_packet_coherent(&p), "%u rows, outliers past them", n);
    }

    light_rays(&p, 256, 0, 0.0f);
    CHECK_MSG(tt_packet_coherent(&p), "shadow rays to a point light are coherent");
    light_rays(&p, 100, 0, 0.0f);
    CHECK_MSG(tt_packet_coherent(&p), "(an item of 100 rows)");
    light_rays(&p, 256, 1, 0.0f);
    CHECK_MSG(!tt_packet_coherent(&p), "the same directions without an end are not");
    /* the shortest ray is 2 long: a light 0.5 wide keeps the ends within
     * TT_PACKET_SPREAD of it (soft shadows), one 4 wide does not */
    light_rays(&p, 256, 0, 0.5f);
    CHECK_MSG(tt_packet_coherent(&p), "shadow rays to a small sphere light are coherent");
    light_rays(&p, 256, 0, 4.0f);
    CHECK_MSG(!tt_packet_coherent(&p), "rays to ends spread twice their shortest length are not");

    /* random directions over the sphere */
    uint32_t seed = 12345u;
    for (uint32_t j = 0; j < 256; j++) {
        const float org[3] = {unit(&seed), unit(&seed), unit(&seed)};
        const float dir[3] = {unit(&seed) - 0.5f, unit(&seed) - 0.5f, unit(&seed) - 0.5f};
        set_row(&p, j, org, dir, 1.0f);
    }
    p.n = 256;
    CHECK_MSG(!tt_packet_coherent(&p), "random directions are not coherent");
}

/* The header's scalar boxes over the rows the sample takes: the reference
 * tt_packet_coherent's lanes must agree with. */
static int reference_rule(const tt_packet_rays *p)
{
    if (p->n < TT_PACKET_MIN) return 0;
    tt_dir_box d;
    tt_end_box e;
    tt_dir_box_init(&d);
    tt_end_box_init(&e);
    for (uint32_t r = 0; r < TT_PACKET_RUNS; r++) {
        const uint32_t s = r * (p->n - TT_PACKET_RUN) / (TT_PACKET_RUNS - 1);
        for (uint32_t j = s; j < s + TT_PACKET_RUN; j++) {
            const float org[3] = {p->org[0][j], p->org[1][j], p->org[2][j]};
            const float dir[3] = {p->dir[0][j], p->dir[1][j], p->dir[2][j]};
            tt_dir_box_add(&d, dir);
            tt_end_box_add(&e, org, dir, p->tmax[j]);
        }
    }
    return tt_packet_boxes_coherent(&d, &e);
}

/* Rows near both tests' limits (cones about TT_PACKET_SPREAD wide, ends
 * spread about a hundredth of the shortest ray, now and then an open or a
 * zero-length ray): the same verdict as the reference, both ways. */
static void rule_matches_reference(void)
{
    static tt_packet_rays p;
    uint32_t seed = 99u;
    int verdicts[2] = {0, 0};
    for (int round = 0; round < 4000; round++) {
        const uint32_t n = TT_PACKET_MIN + next(&seed) % (TT_PACKET_MAX - TT_PACKET_MIN + 1);
        const float cone = 0.35f + 0.3f * unit(&seed), spread = 0.06f * unit(&seed);
        const int kind = round % 4;
        const float target[3] = {unit(&seed), 3.0f + unit(&seed), unit(&seed)};
        for (uint32_t j = 0; j < n; j++) {
            float org[3], dir[3], tmax;
            if (kind < 2) { /* a cone from one eye */
                for (int k = 0; k < 3; k++) org[k] = 0.0f, dir[k] = cone * (unit(&seed) - 0.5f);
                dir[1] += 1.0f;
                tmax = kind ? 10.0f : INFINITY;
            } else { /* ends about the target */
                float d[3];
                for (int k = 0; k < 3; k++) {
                    org[k] = 4.0f * (unit(&seed) - 0.5f);
                    d[k] = target[k] + spread * (unit(&seed) - 0.5f) - org[k];
                }
                const float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                for (int k = 0; k < 3; k++) dir[k] = d[k] / len;
                tmax = len;
                if (kind == 3 && next(&seed) % 64 == 0) tmax = next(&seed) % 2 ? INFINITY : 0.0f;
            }
            tt_packet_ray_set(&p, j, org, dir, 0.0f, tmax);
        }
        p.n = n;
        const int got = tt_packet_coherent(&p), want = reference_rule(&p);
        CHECK_MSG(got == want, "round %d (kind %d, %u rows): %d, the scalar boxes %d", round, kind,
                  n, got, want);
        verdicts[got]++;
    }
    CHECK_MSG(verdicts[0] > 1000 && verdicts[1] > 1000, "both verdicts met: %d / %d", verdicts[0],
              verdicts[1]);
}

/* The view's shadow rays (tt_shadow_ray of every primary hit, in image
 * order) and from every hit two random directions about the normal facing
 * the ray (ambient occlusion), as the engine table makes them. */
static void view_batches(const tt_accel *ref, const tt_scene *scene, const tt_camera *cam,
                         tt_ray **shadow, size_t *ns, tt_ray **ao, size_t *na)
{
    const size_t n = (size_t)SIZE * SIZE;
    tt_ray *rays = malloc(n * sizeof *rays);
    tt_hit *hits = malloc(n * sizeof *hits);
    *shadow = malloc(n * sizeof **shadow);
    *ao = malloc(2 * n * sizeof **ao);
    if (!rays || !hits || !*shadow || !*ao) exit(1);
    if (tt_camera_rays(cam, SIZE, SIZE, rays) != TT_OK) exit(1);
    if (tt_intersect(ref, rays, n, hits, NULL, NULL) != TT_OK) exit(1);
    const float reach = 0.1f * tt_scene_diagonal(scene), eps = 1e-4f * tt_scene_diagonal(scene);
    uint32_t seed = 777u;
    *ns = *na = 0;
    for (size_t i = 0; i < n; i++) {
        if (hits[i].prim == TT_INVALID_ID) continue;
        if (tt_shadow_ray(scene, cam, &rays[i], &hits[i], &(*shadow)[*ns])) (*ns)++;
        float v[9];
        if (tt_scene_triangle(scene, hits[i].prim, v) != TT_OK) exit(1);
        const float e1[3] = {v[3] - v[0], v[4] - v[1], v[5] - v[2]};
        const float e2[3] = {v[6] - v[0], v[7] - v[1], v[8] - v[2]};
        float nrm[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
        const tt_ray *r = &rays[i];
        const float len = sqrtf(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        if (!(len > 0.0f)) continue;
        /* facing the ray, off the surface by the shadow rays' offset */
        const float sign = nrm[0] * r->dir[0] + nrm[1] * r->dir[1] + nrm[2] * r->dir[2] > 0.0f ? -1.0f : 1.0f;
        float org[3];
        for (int k = 0; k < 3; k++) {
            nrm[k] *= sign / len;
            org[k] = r->org[k] + hits[i].t * r->dir[k] + eps * nrm[k];
        }
        for (int s = 0; s < 2; s++) {
            tt_ray *o = &(*ao)[(*na)++];
            /* a random direction, turned into the normal's hemisphere */
            float d[3] = {unit(&seed) - 0.5f, unit(&seed) - 0.5f, unit(&seed) - 0.5f};
            if (d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2] < 0.0f)
                for (int k = 0; k < 3; k++) d[k] = -d[k];
            for (int k = 0; k < 3; k++) {
                o->org[k] = org[k];
                o->dir[k] = d[k];
            }
            o->tmin = 0.0f;
            o->tmax = reach;
        }
    }
    free(rays);
    free(hits);
}

/* One batch in the three modes: the answers agree with single rays, and
 * auto's packet counts are on's (coherent) or none (incoherent). */
static void batch_modes(const tt_accel *a, const tt_ray *rays, size_t n, int coherent,
                        const char *what)
{
    uint8_t *occ[3];
    tt_packet_counts pc[3];
    static const uint32_t modes[3] = {TT_PACKETS_OFF, TT_PACKETS_ON, TT_PACKETS_AUTO};
    for (int m = 0; m < 3; m++) {
        occ[m] = malloc(n ? n : 1);
        if (!occ[m]) exit(1);
        memset(&pc[m], 0, sizeof pc[m]);
        tt_batch_options bo;
        tt_batch_options_default(&bo);
        bo.packets = modes[m];
        bo.chunk = 256; /* the same items in every mode and thread count */
        bo.packet_stats = &pc[m];
        CHECK(tt_occluded(a, rays, n, occ[m], NULL, &bo) == TT_OK);
        /* and the fast path (no counts) answers the same */
        uint8_t *fast = malloc(n ? n : 1);
        if (!fast) exit(1);
        bo.packet_stats = NULL;
        bo.chunk = 0;
        CHECK(tt_occluded(a, rays, n, fast, NULL, &bo) == TT_OK);
        CHECK_MSG(memcmp(fast, occ[m], n) == 0, "%s mode %u: counted and fast answers differ",
                  what, modes[m]);
        free(fast);
    }
    size_t differ = 0, occluded = 0;
    for (size_t i = 0; i < n; i++) {
        differ += (occ[1][i] != occ[0][i]) + (occ[2][i] != occ[0][i]);
        occluded += occ[0][i];
    }
    CHECK_MSG(differ == 0, "%s: %zu answers differ from single rays", what, differ);
    CHECK_MSG(pc[1].packets > 0, "%s: packets on traced no packet", what);
    if (coherent && a->vt->packets_pay) {
        /* A structure with a word on packets (vt->packets_pay) is asked on
         * sampled items, which threads meet in any order, and a tile of a
         * coherent view may fall below its bound alone (Sibenik's shadow
         * tiles here do, two in a row), so auto's counts are not on's to the
         * packet. What holds: the structure's word on the whole batch's
         * packets (on's counts) is yes on these views, and auto traces
         * packets, no more than on. */
        tt_packet_stats all;
        memset(&all, 0, sizeof all);
        all.rays.rays = n;
        all.packets = pc[1].packets;
        all.node_visits = pc[1].node_visits;
        all.active_lanes = pc[1].active_lanes;
        all.fallback_rays = pc[1].fallback_rays;
        CHECK_MSG(a->vt->packets_pay(a, 1, &all), "%s: the structure says the view's packets do not pay",
                  what);
        CHECK_MSG(pc[2].packets > 0 && pc[2].packets <= pc[1].packets,
                  "%s: auto traced %llu packets, on %llu", what, (unsigned long long)pc[2].packets,
                  (unsigned long long)pc[1].packets);
    } else if (coherent)
        CHECK_MSG(memcmp(&pc[2], &pc[1], sizeof pc[1]) == 0,
                  "%s: auto traced %llu packets (%llu node visits), on %llu (%llu): some item "
                  "went ray by ray",
                  what, (unsigned long long)pc[2].packets, (unsigned long long)pc[2].node_visits,
                  (unsigned long long)pc[1].packets, (unsigned long long)pc[1].node_visits);
    else
        CHECK_MSG(pc[2].packets == 0, "%s: auto traced %llu packets of incoherent rays", what,
                  (unsigned long long)pc[2].packets);
    CHECK_MSG(occluded > 0 && occluded < n, "%s: %zu of %zu occluded (a test that tests)", what,
              occluded, n);
    for (int m = 0; m < 3; m++) free(occ[m]);
}

/* The R-tree's word on an occlusion probe (vt->packets_pay): packets pay
 * while a node visit finds at least 3/8 of a packet's rays; closest hits
 * and probes without packets are left to the coherence rule. */
static void rtree_pay_rule(void)
{
    int (*pay)(const tt_accel *, int, const tt_packet_stats *) = tt_rtree_vtable.packets_pay;
    CHECK(pay != NULL);
    if (!pay) return;
    tt_packet_stats ps;
    memset(&ps, 0, sizeof ps);
    ps.rays.rays = 4 * 32 + 3, ps.fallback_rays = 3, ps.packets = 4; /* 32 rays a packet */
    ps.node_visits = 100, ps.active_lanes = 100 * 14;              /* 14 of 32: yes */
    CHECK(pay(NULL, 1, &ps) == 1);
    ps.active_lanes = 100 * 10; /* 10 of 32: no */
    CHECK(pay(NULL, 1, &ps) == 0);
    CHECK(pay(NULL, 0, &ps) == 1); /* closest hits: not judged */
    ps.packets = 0, ps.node_visits = 0, ps.active_lanes = 0;
    CHECK(pay(NULL, 1, &ps) == 1); /* nothing went as a packet */
}

/* The batch follows the structure's word (run_batch's probes): a
 * structure that says packets never pay gets under auto only the probes'
 * packets (a few a thread), one that says they always do gets on's; the
 * answers are the single rays' either way, counted or not. */
static int pay_never(const tt_accel *a, int any, const tt_packet_stats *p)
{
    (void)a, (void)any, (void)p;
    return 0;
}
static int pay_always(const tt_accel *a, int any, const tt_packet_stats *p)
{
    (void)a, (void)any, (void)p;
    return 1;
}
static void batch_follows_word(tt_accel *a, const tt_ray *rays, size_t n, const char *view)
{
    const tt_accel_vtable *own = a->vt;
    tt_accel_vtable never = *own, always = *own;
    never.packets_pay = pay_never;
    always.packets_pay = pay_always;
    uint8_t *ref = malloc(n), *got = malloc(n);
    if (!ref || !got) exit(1);
    tt_batch_options bo;
    tt_batch_options_default(&bo);
    bo.packets = TT_PACKETS_OFF;
    CHECK(tt_occluded(a, rays, n, ref, NULL, &bo) == TT_OK);
    tt_packet_counts on;
    memset(&on, 0, sizeof on);
    bo.packets = TT_PACKETS_ON;
    bo.chunk = 256;
    bo.packet_stats = &on;
    CHECK(tt_occluded(a, rays, n, got, NULL, &bo) == TT_OK);
    const size_t items = (n + 255) / 256;
    for (int w = 0; w < 2; w++) {
        a->vt = w ? &always : &never;
        tt_packet_counts pc;
        memset(&pc, 0, sizeof pc);
        tt_batch_options_default(&bo);
        bo.chunk = 256;
        bo.packet_stats = &pc;
        CHECK(tt_occluded(a, rays, n, got, NULL, &bo) == TT_OK);
        CHECK_MSG(memcmp(got, ref, n) == 0, "%s pay %d: counted answers differ from single rays",
                  view, w);
        if (w)
            CHECK_MSG(pc.packets == on.packets && pc.node_visits == on.node_visits,
                      "%s: auto with packets paying traced %llu packets, on %llu", view,
                      (unsigned long long)pc.packets, (unsigned long long)on.packets);
        else
            CHECK_MSG(pc.packets > 0 && pc.packets * 2 < on.packets,
                      "%s: auto with packets never paying traced %llu packets (on %llu, %zu "
                      "items)",
                      view, (unsigned long long)pc.packets, (unsigned long long)on.packets,
                      items);
        bo.packet_stats = NULL;
        bo.chunk = 0;
        memset(got, 0xff, n);
        CHECK(tt_occluded(a, rays, n, got, NULL, &bo) == TT_OK);
        CHECK_MSG(memcmp(got, ref, n) == 0, "%s pay %d: answers differ from single rays", view,
                  w);
    }
    a->vt = own;
    free(ref);
    free(got);
}

static void scene_view(tt_context *ctx, const char *file, const char *view)
{
    tt_scene *scene = tt_test_load_scene(ctx, file);
    tt_camera cam;
    tt_test_view(ctx, view, &cam);
    tt_accel *ref = tt_test_build_default(ctx, scene, "rtree");
    tt_ray *shadow, *ao;
    size_t ns, na;
    view_batches(ref, scene, &cam, &shadow, &ns, &ao, &na);
    CHECK_MSG(ns > 1000, "%s: %zu shadow rays", view, ns);
    static const char *const accels[] = {"rtree", "kdtree"};
    for (int s = 0; s < 2; s++) {
        if (!tt_test_has_accel(accels[s])) continue;
        tt_accel *a = s == 0 ? ref : tt_test_build_default(ctx, scene, accels[s]);
        char what[128];
        snprintf(what, sizeof what, "%s %s shadow", view, accels[s]);
        batch_modes(a, shadow, ns, 1, what);
        snprintf(what, sizeof what, "%s %s ambient occlusion", view, accels[s]);
        batch_modes(a, ao, na, 0, what);
        batch_follows_word(a, shadow, ns, view);
        if (a != ref) tt_accel_destroy(a);
    }
    free(shadow);
    free(ao);
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    rule_on_rows();
    rule_matches_reference();
    rtree_pay_rule();
    scene_view(ctx, "cornell_box.obj", "cornell:main");
    scene_view(ctx, "bun_zipper_res4.ply", "bunny_res4:main");
    scene_view(ctx, "sibenik.obj", "sibenik:main");
    tt_context_destroy(ctx);
    return tt_test_finish();
}
