/* Stable LSD radix sort of (key, value) pairs for the bulk loaders: 11-bit
 * digits (3 passes for 32-bit keys, 6 for 63-bit Hilbert keys), a pass
 * skipped when every key has the same digit. With several threads each pass
 * histograms and scatters contiguous chunks; the chunks' outputs are placed
 * in chunk order, so the (stable) result is the same for any thread count. */
#include <omp.h>
#include <string.h>

#include "accel/rtree/build/rtree_bulk.h"

#define DIGIT_BITS 11
#define BUCKETS (1u << DIGIT_BITS)
#define SMALL 32

static void insertion_sort(uint64_t *key, uint32_t *val, size_t n, uint64_t mask)
{
    for (size_t i = 1; i < n; i++) {
        uint64_t k = key[i];
        uint32_t v = val[i];
        size_t j = i;
        while (j > 0 && (key[j - 1] & mask) > (k & mask)) {
            key[j] = key[j - 1];
            val[j] = val[j - 1];
            j--;
        }
        key[j] = k;
        val[j] = v;
    }
}

tt_status rt_radix_sort(tt_context *ctx, uint64_t *key, uint32_t *val, uint64_t *tk, uint32_t *tv,
                        size_t n, int key_bits, int threads)
{
    const uint64_t mask = key_bits >= 64 ? ~(uint64_t)0 : (((uint64_t)1 << key_bits) - 1);
    if (n <= SMALL) {
        insertion_sort(key, val, n, mask);
        return TT_OK;
    }
    int chunks = n >= RT_BULK_PARALLEL_MIN ? threads : 1;
    if (chunks < 1) chunks = 1;
    if (chunks > 64) chunks = 64;
    uint32_t local[BUCKETS];
    uint32_t *hist = local;
    if (chunks > 1) {
        hist = tt_alloc_array(ctx, (size_t)chunks, BUCKETS * sizeof *hist);
        if (!hist) return tt_error(ctx, TT_ERR_OUT_OF_MEMORY, "rtree: out of memory (radix sort)");
    }
    uint64_t *k_in = key, *k_out = tk;
    uint32_t *v_in = val, *v_out = tv;
    for (int shift = 0; shift < key_bits; shift += DIGIT_BITS) {
        memset(hist, 0, (size_t)chunks * BUCKETS * sizeof *hist);
#pragma omp parallel for schedule(static, 1) num_threads(chunks) if (chunks > 1)
        for (int c = 0; c < chunks; c++) {
            uint32_t *h = hist + (size_t)c * BUCKETS;
            const size_t lo = n * (size_t)c / (size_t)chunks, hi = n * (size_t)(c + 1) / (size_t)chunks;
            for (size_t i = lo; i < hi; i++) h[(k_in[i] >> shift) & (BUCKETS - 1)]++;
        }
        /* exclusive offsets: by digit, then by chunk (stable) */
        uint32_t sum = 0;
        int one_digit = 0;
        for (uint32_t d = 0; d < BUCKETS; d++) {
            uint32_t total = 0;
            for (int c = 0; c < chunks; c++) {
                uint32_t x = hist[(size_t)c * BUCKETS + d];
                hist[(size_t)c * BUCKETS + d] = sum + total;
                total += x;
            }
            if (total == n) one_digit = 1;
            sum += total;
        }
        if (one_digit) continue; /* every key has this digit: order unchanged */
#pragma omp parallel for schedule(static, 1) num_threads(chunks) if (chunks > 1)
        for (int c = 0; c < chunks; c++) {
            uint32_t *h = hist + (size_t)c * BUCKETS;
            const size_t lo = n * (size_t)c / (size_t)chunks, hi = n * (size_t)(c + 1) / (size_t)chunks;
            for (size_t i = lo; i < hi; i++) {
                uint32_t p = h[(k_in[i] >> shift) & (BUCKETS - 1)]++;
                k_out[p] = k_in[i];
                v_out[p] = v_in[i];
            }
        }
        uint64_t *kt = k_in;
        k_in = k_out;
        k_out = kt;
        uint32_t *vt = v_in;
        v_in = v_out;
        v_out = vt;
    }
    if (k_in != key) {
        memcpy(key, k_in, n * sizeof *key);
        memcpy(val, v_in, n * sizeof *val);
    }
    if (hist != local) tt_free(ctx, hist);
    return TT_OK;
}
