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

static int pixel_agrees(const uint8_t *a, const uint8_t *b)
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
    for (uint64_t i = 0; i < pixels; i++) n += (uint64_t)pixel_agrees(a + 12 * i, b + 12 * i);
    return n;
}
