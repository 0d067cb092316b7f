/* Sorting and merging of split candidates (see kd_events.h). */
#include "accel/kdtree/kd_events.h"

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
    while (i < n_a && j < n_b) out[k++] = (b[j] < a[i]) ? b[j++] : a[i++];
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

/* First index in a[0, n) whose key is greater than x. */
static size_t upper_bound(const uint64_t *a, size_t n, uint64_t x)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (a[mid] <= x) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

void kd_merge_in_place(uint64_t *run, size_t n_run, const uint64_t *b, size_t n_b)
{
    if (n_b == 0) return;
    if (n_b * 32 > n_run) {
        /* Not that short: a plain merge from the run moved to the tail (the
         * write index never passes the read index of the tail). */
        memmove(run + n_b, run, n_run * sizeof *run);
        kd_merge_events(run + n_b, n_run, b, n_b, run);
        return;
    }
    size_t hi = n_run;
    for (size_t j = n_b; j-- > 0;) {
        size_t pos = upper_bound(run, hi, b[j]);
        memmove(run + pos + j + 1, run + pos, (hi - pos) * sizeof *run);
        run[pos + j] = b[j];
        hi = pos;
    }
}
