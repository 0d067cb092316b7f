/* Sorting and merging of split candidates (see kd_events.h). */
#include "accel/kdtree/build/kd_events.h"

/* Short runs are sorted by insertion first: cheaper than merging down to
 * single keys, and most nodes deep in the tree hold only a few events. */
#define RUN 16

static void insertion_sort(uint64_t *a, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint64_t x = a[i];
        size_t j = i;
        while (j > 0 && a[j - 1] > x) {
            a[j] = a[j - 1];
            j--;
        }
        a[j] = x;
    }
}

void kd_merge_events(const uint64_t *a, size_t n_a, const uint64_t *b, size_t n_b, uint64_t *out)
{
    size_t i = 0, j = 0, k = 0;
    /* Without a data-dependent branch: which run the next key comes from
     * is a coin toss on the builders' inputs. */
    while (i < n_a && j < n_b) {
        const uint64_t x = a[i], y = b[j];
        const int take_b = y < x;
        out[k++] = take_b ? y : x;
        j += take_b;
        i += !take_b;
    }
    while (i < n_a) out[k++] = a[i++];
    while (j < n_b) out[k++] = b[j++];
}

void kd_sort_events(uint64_t *keys, uint64_t *tmp, size_t n)
{
    for (size_t i = 0; i < n; i += RUN) insertion_sort(keys + i, (n - i < RUN) ? n - i : RUN);
    /* Bottom-up merge passes, ping-ponging between keys and tmp. */
    uint64_t *src = keys, *dst = tmp;
    for (size_t width = RUN; width < n; width *= 2) {
        for (size_t lo = 0; lo < n; lo += 2 * width) {
            size_t mid = lo + width < n ? lo + width : n;
            size_t hi = lo + 2 * width < n ? lo + 2 * width : n;
            kd_merge_events(src + lo, mid - lo, src + mid, hi - mid, dst + lo);
        }
        uint64_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != keys) memcpy(keys, src, n * sizeof *keys);
}

/* The sorted bits 30 .. 63 in digits of 11, 11 and 12 bits. */
#define RADIX_SHORT 256

void kd_radix_sort_events(uint64_t *keys, uint64_t *tmp, size_t n)
{
    static const int shift[3] = {30, 41, 52}, bits[3] = {11, 11, 12};
    if (n < RADIX_SHORT) {
        kd_sort_events(keys, tmp, n);
        return;
    }
    /* One histogram pass for the three digits. The counts fit 32 bits:
     * a list holds fewer than 2^32 events (2 per triangle, < 2^29). */
    uint32_t count0[1 << 11] = {0}, count1[1 << 11] = {0}, count2[1 << 12] = {0};
    uint32_t *count[3] = {count0, count1, count2};
    for (size_t i = 0; i < n; i++) {
        const uint64_t x = keys[i];
        count0[(x >> 30) & 0x7FFu]++;
        count1[(x >> 41) & 0x7FFu]++;
        count2[(x >> 52) & 0xFFFu]++;
    }
    uint64_t *src = keys, *dst = tmp;
    for (int d = 0; d < 3; d++) {
        uint32_t *c = count[d];
        const size_t buckets = (size_t)1 << bits[d];
        const uint64_t mask = buckets - 1;
        /* A digit all keys share leaves the order as it is. */
        if (c[(src[0] >> shift[d]) & mask] == n) continue;
        uint32_t sum = 0;
        for (size_t j = 0; j < buckets; j++) {
            const uint32_t t = c[j];
            c[j] = sum;
            sum += t;
        }
        for (size_t i = 0; i < n; i++) dst[c[(src[i] >> shift[d]) & mask]++] = src[i];
        uint64_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != keys) memcpy(keys, src, n * sizeof *keys);
}
