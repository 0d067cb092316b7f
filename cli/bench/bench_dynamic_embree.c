/* Table D's Embree side: Embree 3 driven directly, the way its users answer
 * a changing scene (RTC_SCENE_FLAG_DYNAMIC; REFIT keeps the BVH's topology
 * and refits it, LOW and MEDIUM rebuild), timed around rtcCommitScene
 * alone; rays in Embree's own tight OpenMP loop (rtcIntersect1 /
 * rtcOccluded1), never through treetrace's wrapper. Without Embree in the
 * build every call says so (NULL). */
#include "bench/bench_dynamic.h"

#ifdef TT_HAVE_EMBREE
#include <embree3/rtcore.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

struct bench_emb {
    RTCDevice dev;
    RTCScene scene;
    RTCGeometry geom; /* the one mesh of deform / edits (NULL: growth) */
    float *vb;
    size_t tris;
    int quality, threads;
    _Atomic long long bytes;
};

static const enum RTCBuildQuality quality_of[] = {RTC_BUILD_QUALITY_REFIT, RTC_BUILD_QUALITY_LOW,
                                                  RTC_BUILD_QUALITY_MEDIUM};

static bool on_memory(void *user, ssize_t bytes, bool post)
{
    (void)post;
    struct bench_emb *e = user;
    atomic_fetch_add(&e->bytes, (long long)bytes);
    return true;
}

bench_emb *bench_emb_create(int quality, int threads)
{
    struct bench_emb *e = calloc(1, sizeof *e);
    if (!e) return NULL;
    e->quality = quality;
    e->threads = threads;
    e->dev = rtcNewDevice(NULL);
    if (!e->dev) {
        free(e);
        return NULL;
    }
    rtcSetDeviceMemoryMonitorFunction(e->dev, on_memory, e);
    e->scene = rtcNewScene(e->dev);
    rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_DYNAMIC);
    /* the scene's BVH is built LOW under a REFIT geometry, as Embree's
     * dynamic tutorial sets it */
    rtcSetSceneBuildQuality(e->scene, quality == 0 ? RTC_BUILD_QUALITY_LOW : quality_of[quality]);
    return e;
}

static RTCGeometry new_mesh(struct bench_emb *e, const float *tri, size_t n, float **vb_out)
{
    RTCGeometry g = rtcNewGeometry(e->dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), 3 * (n ? n : 1));
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), n ? n : 1);
    memcpy(vb, tri, n * 9 * sizeof(float));
    for (size_t k = 0; k < 3 * n; k++) ib[k] = (unsigned)k;
    rtcSetGeometryBuildQuality(g, quality_of[e->quality]);
    rtcCommitGeometry(g);
    *vb_out = vb;
    return g;
}

int bench_emb_set(bench_emb *e, const float *tri, size_t n)
{
    if (e->geom && n == e->tris) { /* the same mesh, new positions */
        memcpy(e->vb, tri, n * 9 * sizeof(float));
        rtcUpdateGeometryBuffer(e->geom, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(e->geom);
        return 0;
    }
    if (e->geom) {
        rtcDetachGeometry(e->scene, 0);
        rtcReleaseGeometry(e->geom);
    }
    e->geom = new_mesh(e, tri, n, &e->vb);
    e->tris = n;
    rtcAttachGeometryByID(e->scene, e->geom, 0);
    return 0;
}

int bench_emb_add_object(bench_emb *e, const float *tri, size_t n)
{
    float *vb;
    RTCGeometry g = new_mesh(e, tri, n, &vb);
    rtcAttachGeometry(e->scene, g);
    rtcReleaseGeometry(g); /* the scene holds it */
    return 0;
}

double bench_emb_commit(bench_emb *e)
{
    double t0 = bench_now();
    rtcCommitScene(e->scene);
    return bench_now() - t0;
}

void bench_emb_trace(bench_emb *e, const tt_ray *rays, size_t n, const tt_ray *shadow, size_t m,
                     double *primary_s, double *shadow_s)
{
    RTCScene sc = e->scene;
    double t0 = bench_now();
#pragma omp parallel for schedule(dynamic, 256) num_threads(e->threads)
    for (size_t i = 0; i < n; i++) {
        struct RTCRayHit rh;
        rh.ray.org_x = rays[i].org[0];
        rh.ray.org_y = rays[i].org[1];
        rh.ray.org_z = rays[i].org[2];
        rh.ray.dir_x = rays[i].dir[0];
        rh.ray.dir_y = rays[i].dir[1];
        rh.ray.dir_z = rays[i].dir[2];
        rh.ray.tnear = rays[i].tmin;
        rh.ray.tfar = rays[i].tmax;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.flags = 0;
        rh.ray.time = 0.0f;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        struct RTCIntersectContext ic;
        rtcInitIntersectContext(&ic);
        rtcIntersect1(sc, &ic, &rh);
    }
    double t1 = bench_now();
#pragma omp parallel for schedule(dynamic, 256) num_threads(e->threads)
    for (size_t i = 0; i < m; i++) {
        struct RTCRay r;
        r.org_x = shadow[i].org[0];
        r.org_y = shadow[i].org[1];
        r.org_z = shadow[i].org[2];
        r.dir_x = shadow[i].dir[0];
        r.dir_y = shadow[i].dir[1];
        r.dir_z = shadow[i].dir[2];
        r.tnear = shadow[i].tmin;
        r.tfar = shadow[i].tmax;
        r.mask = 0xFFFFFFFFu;
        r.flags = 0;
        r.time = 0.0f;
        struct RTCIntersectContext ic;
        rtcInitIntersectContext(&ic);
        rtcOccluded1(sc, &ic, &r);
    }
    *primary_s = t1 - t0;
    *shadow_s = bench_now() - t1;
}

long long bench_emb_memory(const bench_emb *e) { return atomic_load(&((struct bench_emb *)e)->bytes); }

void bench_emb_destroy(bench_emb *e)
{
    if (!e) return;
    if (e->geom) rtcReleaseGeometry(e->geom);
    rtcReleaseScene(e->scene);
    rtcReleaseDevice(e->dev);
    free(e);
}

#else /* no Embree in this build */

bench_emb *bench_emb_create(int quality, int threads)
{
    (void)quality;
    (void)threads;
    return NULL;
}
int bench_emb_set(bench_emb *e, const float *tri, size_t n)
{
    (void)e, (void)tri, (void)n;
    return -1;
}
int bench_emb_add_object(bench_emb *e, const float *tri, size_t n)
{
    (void)e, (void)tri, (void)n;
    return -1;
}
double bench_emb_commit(bench_emb *e)
{
    (void)e;
    return 0.0;
}
void bench_emb_trace(bench_emb *e, const tt_ray *rays, size_t n, const tt_ray *shadow, size_t m,
                     double *primary_s, double *shadow_s)
{
    (void)e, (void)rays, (void)n, (void)shadow, (void)m;
    *primary_s = *shadow_s = 0.0;
}
long long bench_emb_memory(const bench_emb *e)
{
    (void)e;
    return 0;
}
void bench_emb_destroy(bench_emb *e) { (void)e; }

#endif
