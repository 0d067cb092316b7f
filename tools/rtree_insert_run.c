/* See rtree_insert_run.h. */
#include "rtree_insert_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "accel/rtree/build/rtree_build.h"
#include "accel/rtree/rtree_box.h"
#include "io/scene.h"

double rir_thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

const char *rir_strategy_name(tt_rtree_strategy s)
{
    static const char *names[] = {"min-volume", "min-surface", "min-overlap",
                                  "rstar",      "rstar-surface", "rrstar"};
    return (unsigned)s < sizeof names / sizeof names[0] ? names[s] : "?";
}

float *rir_boxes(const tt_scene *scene, uint32_t *count)
{
    const uint32_t T = (uint32_t)scene->triangle_count;
    float *box = malloc((size_t)(T ? T : 1) * 6 * sizeof *box);
    if (!box) return NULL;
    for (uint32_t i = 0; i < T; i++) {
        const float *v = scene->tri + 9 * (size_t)i;
        float *bx = box + 6 * (size_t)i;
        for (int k = 0; k < 3; k++) {
            bx[k] = rt_min(rt_min(v[k], v[3 + k]), v[6 + k]);
            bx[k + 3] = rt_max(rt_max(v[k], v[3 + k]), v[6 + k]);
        }
    }
    *count = T;
    return box;
}

float *rir_load(tt_context *ctx, const char *path, tt_scene **scene, const char **name,
                uint32_t *count)
{
    *scene = NULL;
    if (tt_scene_load(ctx, path, scene) != TT_OK) {
        fprintf(stderr, "%s\n", tt_context_last_error(ctx)); /* it names the file */
        return NULL;
    }
    const char *slash = strrchr(path, '/');
    *name = slash ? slash + 1 : path;
    float *box = rir_boxes(*scene, count);
    if (!box) {
        fprintf(stderr, "%s: out of memory for the triangle boxes\n", path);
        tt_scene_destroy(*scene);
        *scene = NULL;
    }
    return box;
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; i++) {
        h ^= c[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* Depth first from the root, entries in node order: a node's level and
 * count, then per entry its box and (leaves) the triangle id. Independent
 * of where the pool put the nodes. */
static uint64_t hash_node(const rt_builder *b, uint32_t n, uint64_t h, uint32_t *nodes)
{
    const rt_node_hdr *hd = &b->hdr[n];
    uint32_t head[2] = {hd->level, hd->count};
    h = fnv(h, head, sizeof head);
    ++*nodes;
    const float *s = rt_node_box(b, n);
    const uint32_t *ch = rt_node_child(b, n);
    for (int i = 0; i < hd->count; i++) {
        float e[6];
        rt_soa_get(s, b->cap, i, e);
        h = fnv(h, e, sizeof e);
        if (hd->level == 0) h = fnv(h, &ch[i], sizeof ch[i]);
        else h = hash_node(b, ch[i], h, nodes);
    }
    return h;
}

int rir_build(tt_context *ctx, const float *box, uint32_t count, const tt_rtree_options *o,
              rir_result *out)
{
    tt_rtree_options oo = *o;
    oo.M = tt_rtree_max_entries(o);
    rt_builder b;
    double t0 = rir_thread_cpu();
    tt_status st = rt_builder_init(&b, ctx, &oo, box, count);
    for (uint32_t i = 0; i < count && st == TT_OK; i++) st = rt_builder_insert_triangle(&b, i);
    double t1 = rir_thread_cpu();
    if (st == TT_OK) st = rt_builder_check(&b);
    if (st == TT_OK) {
        out->cpu_s = t1 - t0;
        out->nodes = 0;
        out->hash = hash_node(&b, b.root, 0xcbf29ce484222325ull, &out->nodes);
        out->height = b.hdr[b.root].level + 1;
    }
    rt_builder_free(&b);
    return st == TT_OK ? 0 : 1;
}

static void find_sah(void *user, const char *key, double value)
{
    if (strcmp(key, "sah_cost") == 0) *(double *)user = value;
}

double rir_sah(tt_context *ctx, const tt_scene *scene, const tt_rtree_options *o)
{
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "rtree";
    bo.rtree = *o;
    bo.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
    tt_accel *a = NULL;
    double sah = -1.0;
    if (tt_accel_build(ctx, scene, &bo, &a) == TT_OK) tt_accel_statistics(a, find_sah, &sah);
    tt_accel_destroy(a);
    return sah;
}
