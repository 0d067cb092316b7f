/* Pixel agreement of two hit buffers, per ../shared/scenes/README.md: 12
 * bytes a pixel (uint32 triangle id, float32 t, uint32 shadow flag, all
 * little-endian); two pixels agree when both miss, or hit the same triangle,
 * or hit with t within 1e-4 relative (a shared edge), and their shadow flags
 * are equal. */
#include <math.h>
#include <string.h>

#include "bench/bench.h"

static uint32_t le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float le_float(const uint8_t *p)
{
    uint32_t u = le32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

int bench_pixel_agrees(const uint8_t *a, const uint8_t *b)
{
    if (le32(a + 8) != le32(b + 8)) return 0; /* shadow flags */
    uint32_t pa = le32(a), pb = le32(b);
    int ma = pa == 0xFFFFFFFFu, mb = pb == 0xFFFFFFFFu;
    if (ma || mb) return ma && mb;
    if (pa == pb) return 1;
    float ta = le_float(a + 4), tb = le_float(b + 4);
    return fabsf(ta - tb) <= 1e-4f * fmaxf(fabsf(ta), fabsf(tb));
}

uint64_t bench_agree_count(const uint8_t *a, const uint8_t *b, uint64_t pixels)
{
    uint64_t n = 0;
    for (uint64_t i = 0; i < pixels; i++) n += (uint64_t)bench_pixel_agrees(a + 12 * i, b + 12 * i);
    return n;
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

void bench_bruteforce_pixel(const tt_scene *scene, const tt_accel *bruteforce,
                            const tt_camera *camera, bench_size size, uint32_t x, uint32_t y,
                            int shadows, uint8_t out[12])
{
    tt_ray r, sr;
    tt_hit h;
    int occluded = 0;
    h.prim = TT_INVALID_ID;
    h.t = INFINITY;
    if (tt_camera_ray(camera, size.width, size.height, x, y, &r) == TT_OK &&
        tt_intersect1(bruteforce, &r, &h) == TT_OK && shadows &&
        tt_shadow_ray(scene, camera, &r, &h, &sr))
        tt_occluded1(bruteforce, &sr, &occluded);
    uint32_t tbits;
    float t = h.prim == TT_INVALID_ID ? INFINITY : h.t;
    memcpy(&tbits, &t, sizeof tbits);
    put32(out, h.prim);
    put32(out + 4, tbits);
    put32(out + 8, (uint32_t)occluded);
}
