/* Agreement of the engine table's answers: with Embree as raybench counts
 * it (the same triangle or both miss; the same occluded flag), with our
 * default R-tree bit for bit, and with bruteforce on a sample of rays plus
 * those where Embree answered otherwise. */
#include <stdlib.h>
#include <string.h>

#include "bench/bench_yard.h"

uint64_t yard_agree_hits(const tt_hit *a, const tt_hit *b, size_t n)
{
    uint64_t k = 0;
    for (size_t i = 0; i < n; i++) k += a[i].prim == b[i].prim;
    return k;
}

uint64_t yard_agree_flags(const uint8_t *a, const uint8_t *b, size_t n)
{
    uint64_t k = 0;
    for (size_t i = 0; i < n; i++) k += a[i] == b[i];
    return k;
}

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

uint64_t yard_same_hits(const tt_hit *a, const tt_hit *b, size_t n)
{
    uint64_t k = 0;
    for (size_t i = 0; i < n; i++)
        k += a[i].prim == b[i].prim && same_bits(a[i].t, b[i].t) && same_bits(a[i].u, b[i].u) &&
             same_bits(a[i].v, b[i].v);
    return k;
}

static int cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return x < y ? -1 : x > y;
}

size_t yard_pick_rays(size_t n, const uint8_t *disagree, size_t *idx, size_t cap)
{
    size_t m = 0;
    if (!n) return 0;
    const size_t step = n > YARD_BRUTEFORCE_SAMPLE ? n / YARD_BRUTEFORCE_SAMPLE : 1;
    for (size_t i = step / 2; i < n && m < cap && m < YARD_BRUTEFORCE_SAMPLE; i += step) idx[m++] = i;
    size_t extra = 0;
    for (size_t i = 0; disagree && i < n && m < cap && extra < YARD_BRUTEFORCE_DISAGREE; i++)
        if (disagree[i]) idx[m++] = i, extra++;
    qsort(idx, m, sizeof *idx, cmp_size);
    size_t u = 0;
    for (size_t i = 0; i < m; i++)
        if (!u || idx[u - 1] != idx[i]) idx[u++] = idx[i];
    return u;
}

tt_status yard_bruteforce(const tt_accel *bf, const tt_ray *rays, const size_t *idx, size_t m,
                          tt_hit *hits, uint8_t *flags)
{
    tt_ray *picked = malloc((m ? m : 1) * sizeof *picked);
    if (!picked) return TT_ERR_OUT_OF_MEMORY;
    for (size_t i = 0; i < m; i++) picked[i] = rays[idx[i]];
    tt_status st = hits ? tt_intersect(bf, picked, m, hits, NULL, NULL)
                        : tt_occluded(bf, picked, m, flags, NULL, NULL);
    free(picked);
    return st;
}
