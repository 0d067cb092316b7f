/* Embree's scene for the engine table: the scene's vertices and indices
 * handed over as an Embree user hands a mesh, built at medium quality with
 * the default flags or ROBUST. Its memory is counted by the device's
 * memory monitor; its build time is rtcCommitScene's alone (the copy into
 * Embree's buffers is the user's, as it is in raybench). */
#include <embree3/rtcore.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/bench_embree.h"
#include "bench/embree/bench_embree_impl.h"
#include "io/scene.h" /* the indexed arrays: Embree gets the mesh as loaded */

static bool on_memory(void *user, ssize_t bytes, bool post)
{
    (void)post;
    atomic_fetch_add(&((bench_embree *)user)->bytes, (long long)bytes);
    return true; /* counting only: never refuse an allocation */
}

static void on_error(void *user, enum RTCError code, const char *message)
{
    bench_embree *e = user;
    int expected = 0;
    if (atomic_compare_exchange_strong(&e->error_claimed, &expected, 1))
        snprintf(e->error, sizeof e->error, "Embree error %d: %s", (int)code,
                 message ? message : "");
}

static int failed(const bench_embree *e, const char *step, char *err, size_t err_size)
{
    if (!atomic_load(&((bench_embree *)e)->error_claimed)) return 0;
    snprintf(err, err_size, "%s: %s", step, e->error);
    return 1;
}

void bench_embree_version(char *buf, size_t size)
{
    RTCDevice d = rtcNewDevice("verbose=0");
    long v = d ? (long)rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION) : 0;
    if (d) rtcReleaseDevice(d);
    snprintf(buf, size, "Embree %ld.%ld.%ld", v / 10000, v / 100 % 100, v % 100);
}

bench_embree *bench_embree_build(const tt_scene *scene, int robust, int threads, double *build_s,
                                 size_t *memory_bytes, char *err, size_t err_size)
{
    bench_embree *e = calloc(1, sizeof *e);
    if (!e) {
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    atomic_init(&e->bytes, 0);
    atomic_init(&e->error_claimed, 0);
    char config[64] = "verbose=0";
    if (threads > 0) snprintf(config, sizeof config, "verbose=0,threads=%d", threads);
    e->device = rtcNewDevice(config);
    if (!e->device) {
        snprintf(err, err_size, "rtcNewDevice(\"%s\") failed", config);
        free(e);
        return NULL;
    }
    rtcSetDeviceErrorFunction(e->device, on_error, e);
    rtcSetDeviceMemoryMonitorFunction(e->device, on_memory, e);
    e->scene = rtcNewScene(e->device);
    if (robust) rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), scene->vertex_count);
    uint32_t *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(uint32_t), scene->triangle_count);
    if (failed(e, "rtcSetNewGeometryBuffer", err, err_size) || !v || !idx) {
        if (!err[0]) snprintf(err, err_size, "no Embree geometry buffers");
        rtcReleaseGeometry(g);
        bench_embree_destroy(e);
        return NULL;
    }
    memcpy(v, scene->vertices, scene->vertex_count * 3 * sizeof(float));
    memcpy(idx, scene->indices, scene->triangle_count * 3 * sizeof(uint32_t));
    rtcCommitGeometry(g);
    rtcAttachGeometry(e->scene, g);
    rtcReleaseGeometry(g);
    double t0 = bench_now();
    rtcCommitScene(e->scene);
    *build_s = bench_now() - t0;
    if (failed(e, "rtcCommitScene", err, err_size)) {
        bench_embree_destroy(e);
        return NULL;
    }
    long long b = atomic_load(&e->bytes);
    *memory_bytes = b > 0 ? (size_t)b : 0;
    return e;
}

void bench_embree_destroy(bench_embree *e)
{
    if (!e) return;
    if (e->scene) rtcReleaseScene(e->scene);
    if (e->device) rtcReleaseDevice(e->device);
    free(e);
}
