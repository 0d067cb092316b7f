/* libFuzzer target: the saved-structure loader (tt_accel_load's path) on
 * arbitrary bytes. Input: one mode byte, then the file. Mode bit 0 set:
 * the checksums are not verified, so that mutations reach the structures'
 * own validation (rtc_io.c, rtree_packed_io.c, kd_io.c) instead of stopping
 * at the checksum as nearly every damaged file does. A file that loads is
 * traced (a small render with statistics) and checked: whatever it holds
 * must never crash, hang or read out of bounds.
 *
 * Seeds: run with FUZZ_ACCEL_SEEDS=DIR to write a valid file of every
 * structure and layout for the fuzz scene into DIR (both modes) and exit;
 * tests/fuzz/run-fuzzers.sh does so before fuzzing, so the seeds always
 * have the current format. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accel/accel.h"
#include "io/accel_file.h"
#include "treetrace/treetrace.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

static tt_context *ctx;
static tt_scene *scene;

/* A fixed scene of 200 triangles: a bumpy grid, some of them degenerate. */
static void make_scene(void)
{
    enum { G = 11 };
    float v[G * G * 3];
    uint32_t idx[(G - 1) * (G - 1) * 2 * 3];
    for (int y = 0; y < G; y++)
        for (int x = 0; x < G; x++) {
            float *p = v + 3 * (y * G + x);
            p[0] = (float)x;
            p[1] = (float)((x * 7 + y * 3) % 5) * 0.3f;
            p[2] = (float)y;
        }
    size_t n = 0;
    for (int y = 0; y + 1 < G; y++)
        for (int x = 0; x + 1 < G; x++) {
            uint32_t a = (uint32_t)(y * G + x), b = a + 1, c = a + G, d = c + 1;
            uint32_t t[6] = {a, b, c, b, d, (x == 3 && y == 3) ? b : c};
            memcpy(idx + n, t, sizeof t);
            n += 6;
        }
    if (tt_context_create(NULL, &ctx) != TT_OK ||
        tt_scene_create(ctx, v, G * G, idx, n / 3, &scene) != TT_OK)
        abort();
}

static void write_seed(const char *dir, const char *name, const tt_build_options *o)
{
    tt_accel *a = NULL;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.tta", dir, name);
    if (tt_accel_build(ctx, scene, o, &a) != TT_OK || tt_accel_save(a, path, "fuzz") != TT_OK) {
        fprintf(stderr, "fuzz_accel: %s\n", tt_context_last_error(ctx));
        exit(1);
    }
    tt_accel_destroy(a);
    FILE *f = fopen(path, "rb");
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *b = malloc((size_t)n + 1);
    if (fread(b + 1, 1, (size_t)n, f) != (size_t)n) exit(1);
    fclose(f);
    remove(path);
    for (int mode = 0; mode < 2; mode++) {
        b[0] = (uint8_t)mode;
        snprintf(path, sizeof path, "%s/%s-mode%d", dir, name, mode);
        FILE *g = fopen(path, "wb");
        fwrite(b, 1, (size_t)n + 1, g);
        fclose(g);
    }
    free(b);
}

static void write_seeds(const char *dir)
{
    tt_build_options o;
    tt_build_options_default(&o);
    write_seed(dir, "rtree-compact", &o);
    o.rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
    o.rtree.M = 4;
    write_seed(dir, "rtree-complete", &o);
    tt_build_options_default(&o);
    o.accel = "kdtree";
    write_seed(dir, "kdtree-htr", &o);
    o.kdtree.traversal = TT_KD_SLTR;
    write_seed(dir, "kdtree-sltr", &o);
    o.accel = "bruteforce";
    write_seed(dir, "bruteforce", &o);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    make_scene();
    const char *seeds = getenv("FUZZ_ACCEL_SEEDS");
    if (seeds) {
        write_seeds(seeds);
        exit(0);
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    const int verify = !(data[0] & 1);
    /* 64-byte aligned, as a mapping is */
    uint8_t *copy = aligned_alloc(64, ((size - 1) / 64 + 1) * 64);
    if (!copy) return 0;
    memcpy(copy, data + 1, size - 1);
    tt_af_file *f = calloc(1, sizeof *f);
    tt_accel *a = NULL;
    if (tt_af_open_memory(ctx, "fuzz.tta", copy, size - 1, verify, f) == TT_OK) {
        tt_af_file *owned = tt_alloc(ctx, sizeof *owned); /* the loader frees it */
        *owned = *f;
        if (tt_accel_load_opened(ctx, scene, owned, TT_ISA_AUTO, &a) == TT_OK) {
            tt_camera cam;
            tt_camera_frame_scene(scene, &cam);
            tt_render_options ro;
            tt_render_options_default(&ro);
            ro.width = ro.height = 24;
            ro.stats = 1;
            tt_render_result *r = NULL;
            if (tt_render(ctx, scene, a, &cam, &ro, &r) == TT_OK) tt_render_result_destroy(r);
            (void)tt_accel_check(a);
            tt_accel_destroy(a);
        }
    }
    free(f);
    free(copy);
    return 0;
}
