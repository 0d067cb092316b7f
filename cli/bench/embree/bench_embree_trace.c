/* Embree's own calls in tight OpenMP loops over our ray arrays: what an
 * Embree user writes, and nothing of ours in between. Primary rays go by
 * 16 x 16 tiles of the image (dynamic schedule), as our batch call takes
 * them with image_width; occlusion rays by runs of consecutive rays. */
#include <embree3/rtcore.h>
#include <math.h>

#include "bench/bench_embree.h"
#include "bench/embree/bench_embree_impl.h"

#define TILE 16

static void single_ray(struct RTCRay *r, const tt_ray *in)
{
    r->org_x = in->org[0];
    r->org_y = in->org[1];
    r->org_z = in->org[2];
    r->dir_x = in->dir[0];
    r->dir_y = in->dir[1];
    r->dir_z = in->dir[2];
    r->tnear = in->tmin;
    r->tfar = in->tmax;
    r->time = 0.0f;
    r->mask = ~0u;
    r->id = 0;
    r->flags = 0;
}

static void intersect1(RTCScene sc, const tt_ray *rays, uint32_t w, uint32_t h, tt_hit *hits,
                       int threads)
{
    const int tx = (int)((w + TILE - 1) / TILE), ty = (int)((h + TILE - 1) / TILE);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int tile = 0; tile < tx * ty; tile++) {
        const uint32_t x0 = (uint32_t)(tile % tx) * TILE, y0 = (uint32_t)(tile / tx) * TILE;
        for (uint32_t y = y0; y < y0 + TILE && y < h; y++) {
            for (uint32_t x = x0; x < x0 + TILE && x < w; x++) {
                const size_t i = (size_t)y * w + x;
                struct RTCRayHit rh;
                single_ray(&rh.ray, &rays[i]);
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                struct RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                rtcIntersect1(sc, &ctx, &rh);
                const int hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                hits[i].prim = hit ? rh.hit.primID : TT_INVALID_ID;
                hits[i].t = hit ? rh.ray.tfar : INFINITY;
                hits[i].u = hit ? rh.hit.u : 0.0f;
                hits[i].v = hit ? rh.hit.v : 0.0f;
            }
        }
    }
}

static void occluded1(RTCScene sc, const tt_ray *rays, size_t n, uint8_t *occ, int threads)
{
    const long long count = (long long)n;
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
    for (long long i = 0; i < count; i++) {
        struct RTCRay r;
        single_ray(&r, &rays[i]);
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcOccluded1(sc, &ctx, &r);
        occ[i] = r.tfar < 0.0f; /* Embree sets tfar to -inf on a hit */
    }
}

/* Lane k of a packet (RTCRay8 or RTCRay16: the same fields, K wide). */
#define FILL_LANE(R, k, in)                                                                        \
    do {                                                                                           \
        (R).org_x[k] = (in)->org[0];                                                               \
        (R).org_y[k] = (in)->org[1];                                                               \
        (R).org_z[k] = (in)->org[2];                                                               \
        (R).dir_x[k] = (in)->dir[0];                                                               \
        (R).dir_y[k] = (in)->dir[1];                                                               \
        (R).dir_z[k] = (in)->dir[2];                                                               \
        (R).tnear[k] = (in)->tmin;                                                                 \
        (R).tfar[k] = (in)->tmax;                                                                  \
        (R).time[k] = 0.0f;                                                                        \
        (R).mask[k] = ~0u;                                                                         \
        (R).id[k] = 0;                                                                             \
        (R).flags[k] = 0;                                                                          \
    } while (0)

/* K-wide versions: a tile in blocks of 4 x (K / 4) pixels; occlusion rays
 * K consecutive at a time. Lanes past the image's edge or the batch's end
 * are invalid (valid[k] = 0) and carry a copy of a valid ray. */
#define PACKET_FUNCTIONS(K, RAYHIT, RAY, INTERSECT, OCCLUDED)                                      \
    static void intersect##K(RTCScene sc, const tt_ray *rays, uint32_t w, uint32_t h,             \
                             tt_hit *hits, int threads)                                            \
    {                                                                                              \
        const uint32_t bw = 4, bh = (K) / 4;                                                       \
        const int tx = (int)((w + TILE - 1) / TILE), ty = (int)((h + TILE - 1) / TILE);            \
        _Pragma("omp parallel for schedule(dynamic, 1) num_threads(threads)")                      \
        for (int tile = 0; tile < tx * ty; tile++) {                                               \
            const uint32_t x0 = (uint32_t)(tile % tx) * TILE, y0 = (uint32_t)(tile / tx) * TILE;   \
            for (uint32_t by = y0; by < y0 + TILE && by < h; by += bh) {                           \
                for (uint32_t bx = x0; bx < x0 + TILE && bx < w; bx += bw) {                       \
                    RAYHIT rh __attribute__((aligned(64)));                                        \
                    int valid[K] __attribute__((aligned(64)));                                     \
                    size_t at[K];                                                                  \
                    for (int k = 0; k < (K); k++) {                                                \
                        const uint32_t x = bx + (uint32_t)k % bw, y = by + (uint32_t)k / bw;       \
                        valid[k] = x < w && y < h ? -1 : 0;                                        \
                        at[k] = valid[k] ? (size_t)y * w + x : (size_t)by * w + bx;                \
                        FILL_LANE(rh.ray, k, &rays[at[k]]);                                        \
                        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;                                \
                        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;                             \
                    }                                                                              \
                    struct RTCIntersectContext ctx;                                                \
                    rtcInitIntersectContext(&ctx);                                                 \
                    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;                               \
                    INTERSECT(valid, sc, &ctx, &rh);                                               \
                    for (int k = 0; k < (K); k++) {                                                \
                        if (!valid[k]) continue;                                                   \
                        tt_hit *o = &hits[at[k]];                                                  \
                        const int hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;               \
                        o->prim = hit ? rh.hit.primID[k] : TT_INVALID_ID;                          \
                        o->t = hit ? rh.ray.tfar[k] : INFINITY;                                    \
                        o->u = hit ? rh.hit.u[k] : 0.0f;                                           \
                        o->v = hit ? rh.hit.v[k] : 0.0f;                                           \
                    }                                                                              \
                }                                                                                  \
            }                                                                                      \
        }                                                                                          \
    }                                                                                              \
    static void occluded##K(RTCScene sc, const tt_ray *rays, size_t n, uint8_t *occ, int threads)  \
    {                                                                                              \
        const long long packets = (long long)((n + (K)-1) / (K));                                  \
        _Pragma("omp parallel for schedule(dynamic, 16) num_threads(threads)")                     \
        for (long long p = 0; p < packets; p++) {                                                  \
            const size_t first = (size_t)p * (K);                                                  \
            RAY r __attribute__((aligned(64)));                                                    \
            int valid[K] __attribute__((aligned(64)));                                             \
            for (int k = 0; k < (K); k++) {                                                        \
                valid[k] = first + (size_t)k < n ? -1 : 0;                                         \
                FILL_LANE(r, k, &rays[valid[k] ? first + (size_t)k : first]);                      \
            }                                                                                      \
            struct RTCIntersectContext ctx;                                                        \
            rtcInitIntersectContext(&ctx);                                                         \
            ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;                                       \
            OCCLUDED(valid, sc, &ctx, &r);                                                         \
            for (int k = 0; k < (K); k++)                                                          \
                if (valid[k]) occ[first + (size_t)k] = r.tfar[k] < 0.0f;                           \
        }                                                                                          \
    }

PACKET_FUNCTIONS(8, struct RTCRayHit8, struct RTCRay8, rtcIntersect8, rtcOccluded8)
PACKET_FUNCTIONS(16, struct RTCRayHit16, struct RTCRay16, rtcIntersect16, rtcOccluded16)

void bench_embree_intersect(const bench_embree *e, int packet, const tt_ray *rays, uint32_t width,
                            uint32_t height, tt_hit *hits, int threads)
{
    if (threads < 1) threads = 1;
    if (packet == 16)
        intersect16(e->scene, rays, width, height, hits, threads);
    else if (packet == 8)
        intersect8(e->scene, rays, width, height, hits, threads);
    else
        intersect1(e->scene, rays, width, height, hits, threads);
}

void bench_embree_occluded(const bench_embree *e, int packet, const tt_ray *rays, size_t n,
                           uint8_t *occluded, int threads)
{
    if (threads < 1) threads = 1;
    if (packet == 16)
        occluded16(e->scene, rays, n, occluded, threads);
    else if (packet == 8)
        occluded8(e->scene, rays, n, occluded, threads);
    else
        occluded1(e->scene, rays, n, occluded, threads);
}
