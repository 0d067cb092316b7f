/* Split candidates ("events", Wald & Havran 2006) packed into one 64-bit key
 * so that sorting the integers sorts by (position, type):
 *
 *   bits 63..32  the position, its float bits mapped to an order-preserving
 *                unsigned integer
 *   bits 31..30  the type: END < PLANAR < START, the order the sweep needs
 *                at equal positions
 *   bits 29..0   the triangle id
 *
 * The triangle id only makes the order total (deterministic); no decision
 * depends on it. */
#ifndef TT_ACCEL_KDTREE_KD_EVENTS_H
#define TT_ACCEL_KDTREE_KD_EVENTS_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define KD_END 0u
#define KD_PLANAR 1u
#define KD_START 2u
#define KD_TRI_MASK ((1u << 30) - 1u)
/* A leaf's reference count has 29 bits (kd_layout.h). */
#define KD_MAX_TRIANGLES ((1u << 29) - 1u)

static inline uint32_t kd_float_key(float f)
{
    uint32_t u;
    f += 0.0f; /* -0 becomes +0: equal positions must get equal keys */
    memcpy(&u, &f, sizeof u);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

static inline float kd_key_float(uint32_t k)
{
    uint32_t u = (k & 0x80000000u) ? (k & 0x7FFFFFFFu) : ~k;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline uint64_t kd_event(float pos, uint32_t type, uint32_t tri)
{
    return ((uint64_t)kd_float_key(pos) << 32) | ((uint64_t)type << 30) | tri;
}

static inline uint32_t kd_event_poskey(uint64_t e) { return (uint32_t)(e >> 32); }
static inline float kd_event_pos(uint64_t e) { return kd_key_float((uint32_t)(e >> 32)); }
static inline uint32_t kd_event_type(uint64_t e) { return (uint32_t)(e >> 30) & 3u; }
static inline uint32_t kd_event_tri(uint64_t e) { return (uint32_t)e & KD_TRI_MASK; }

/* Appends the events of a triangle whose clipped bounds on one axis are
 * [lo, hi]: one PLANAR event if flat, else START and END. Returns the count. */
static inline size_t kd_events_of(uint64_t *out, float lo, float hi, uint32_t tri)
{
    if (lo == hi) {
        out[0] = kd_event(lo, KD_PLANAR, tri);
        return 1;
    }
    out[0] = kd_event(lo, KD_START, tri);
    out[1] = kd_event(hi, KD_END, tri);
    return 2;
}

/* Comparison sort (O(n log n), stable merge sort; tmp holds n keys). The
 * O(N log^2 N) builder calls it at every node; the O(N log N) builder
 * reaches it through kd_radix_sort_events for the short lists of the
 * re-clipped triangles of each split. */
void kd_sort_events(uint64_t *keys, uint64_t *tmp, size_t n);

/* Stable LSD radix sort on the position and type bits only (3 passes of a
 * counting sort; tmp holds n keys): events with the same position and type
 * keep their input order. So on events listed in triangle order (as the
 * builders generate them) it gives exactly kd_sort_events' order, and on
 * any input the order kd_sweep depends on. Short inputs go to
 * kd_sort_events. */
void kd_radix_sort_events(uint64_t *keys, uint64_t *tmp, size_t n);

/* Merges two sorted runs into out (n_a + n_b keys). */
void kd_merge_events(const uint64_t *a, size_t n_a, const uint64_t *b, size_t n_b, uint64_t *out);

#endif
