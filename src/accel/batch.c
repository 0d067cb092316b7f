/* Batches of rays (tt_intersect, tt_occluded and their strided forms): the
 * rays are read through byte strides, checked against the ray contract one
 * by one, and traced through the structure's dispatch table on the
 * context's OpenMP threads, like the renderer's passes. The AoS calls are
 * the strided ones over tt_ray / tt_hit, so there is one loop to trust. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/accel.h"
#include "accel/packet_probe.h"
#include "accel/packets.h"
#include "accel/ray_check.h"


#define MAX_CHUNK 256u
#define TILE 16u
_Static_assert(TILE * TILE <= TT_PACKET_MAX, "a tile is one packet");

/* How the rays are cut into work items: runs of `chunk` consecutive rays,
 * or TILE x TILE tiles of an image `width` rays wide, or tiles of found
 * rows (below). An item is `rows` runs of `len` rays, `pitch` rays apart. */
typedef struct plan_tile {
    size_t row, x0; /* first row (index into starts), first column */
} plan_tile;

typedef struct plan {
    size_t n, chunk, width, tiles_x;
    long items;
    /* found rows (plan_find_rows), else NULL: row k is rays starts[k] ..
     * starts[k + 1] - 1, of rows in all; the items' tiles */
    size_t *starts, rows;
    plan_tile *tiles;
} plan;

/* Found rows. An occlusion batch without an image width is most often the
 * shadow rays of a camera's hits in image order (the misses left out):
 * runs of consecutive rays are image rows of varying length. Cut in runs
 * of 256 (a quarter row at 1024 wide), a kernel walk of 32 rays (AVX-512)
 * is 32 x 1 pixels; as 4 x 8 pixels it visits a quarter to a third fewer
 * nodes (bunny, conference shadows, the counting variant). So the rows are
 * found: from a row's first ray, the next row starts at the lag where its
 * first rays' origins come back closest (the pixels below them; searched
 * within LAG_NEAR, then 8 LAG_NEAR, of the last row's length while the best
 * lies at the window's edge, then over all lags LAG_MIN .. LAG_MAX: the
 * search was 4-5M instructions of a 1M-ray batch within 32, 1.8M now).
 * Items are FOUND_ROWS rows by FOUND_TILE columns, gathered in blocks of
 * FOUND_COLS columns by those rows. A row is a guess: a wrong one (rays of
 * no such order) only makes other items, every ray still in exactly one
 * item, answered alone. */
#define FOUND_ROWS 8u
#define FOUND_COLS 4u
#define FOUND_TILE 32u
_Static_assert(FOUND_ROWS * FOUND_TILE <= TT_PACKET_MAX, "a found tile is one packet");
#define LAG_MIN 16u
#define LAG_MAX 2048u
#define LAG_NEAR 8u
#define LAG_PROBES 4u

static const float *at_f(const float *base, ptrdiff_t stride, size_t i)
{
    return (const float *)(const void *)((const char *)base + (ptrdiff_t)i * stride);
}

static float org_dist2(const tt_ray_arrays *a, const tt_ray *aos, size_t i, size_t j)
{
    float d = 0.0f;
    for (int k = 0; k < 3; k++) {
        float x, y;
        if (aos) {
            x = aos[i].org[k], y = aos[j].org[k];
        } else {
            x = *at_f(a->org[k], a->org_stride, i);
            y = *at_f(a->org[k], a->org_stride, j);
        }
        d += (x - y) * (x - y);
    }
    return d;
}

/* The lag lo .. hi whose LAG_PROBES ray pairs from s are nearest, summed. */
static size_t lag_in(const tt_ray_arrays *a, const tt_ray *aos, size_t s, size_t lo, size_t hi)
{
    size_t best = lo;
    float bd = INFINITY;
    for (size_t lag = lo; lag <= hi; lag++) {
        float d = 0.0f;
        for (size_t q = 0; q < LAG_PROBES; q++) d += org_dist2(a, aos, s + q, s + q + lag);
        if (d < bd) bd = d, best = lag;
    }
    return best;
}

/* The length of the row from ray s, near the last one's (prev, 0: none);
 * 0 when the rays left are too few to tell. */
static size_t row_lag(const tt_ray_arrays *a, const tt_ray *aos, size_t n, size_t s, size_t prev)
{
    if (n - s < 2u * LAG_MIN + LAG_PROBES) return 0;
    size_t hi = (n - s - LAG_PROBES) / 2u;
    hi = hi < LAG_MAX ? hi : LAG_MAX;
    /* near the last row's length, wider while the best lies at an edge */
    for (size_t near = LAG_NEAR; prev && near <= 8u * LAG_NEAR; near *= 8u) {
        const size_t lo1 = prev > LAG_MIN + near ? prev - near : LAG_MIN;
        const size_t hi1 = prev + near < hi ? prev + near : hi;
        if (lo1 >= hi1) break;
        const size_t l = lag_in(a, aos, s, lo1, hi1);
        if ((l > lo1 || lo1 == LAG_MIN) && (l < hi1 || hi1 == hi)) return l;
    }
    return lag_in(a, aos, s, LAG_MIN, hi);
}

/* p of *cap elements (plus `extra` slots past them) grown to twice *cap */
static void *grow(void *p, size_t *cap, size_t extra, size_t size)
{
    void *g = realloc(p, (2u * *cap + extra) * size);
    if (g) *cap *= 2u;
    return g;
}

/* The found-row plan (see above); 0 when it cannot be made (then runs). */
static int plan_find_rows(plan *p, size_t n, const tt_ray_arrays *a, const tt_ray *aos)
{
    size_t cap = n / 256u + 64u, rows = 0;
    size_t *st = malloc((cap + 1u) * sizeof *st);
    if (!st) return 0;
    size_t prev = 0;
    for (size_t s = 0; s < n; rows++) {
        if (rows == cap) {
            /* (one slot past cap: the room for starts[rows] at the end) */
            size_t *g = grow(st, &cap, 1u, sizeof *st);
            if (!g) goto fail;
            st = g;
        }
        st[rows] = s;
        const size_t lag = row_lag(a, aos, n, s, prev);
        s = lag ? s + lag : n;
        prev = lag;
    }
    st[rows] = n;
    size_t tcap = n / FOUND_TILE + rows + 1u, count = 0;
    plan_tile *t = malloc(tcap * sizeof *t);
    if (!t) goto fail;
    for (size_t r0 = 0; r0 < rows; r0 += FOUND_ROWS) {
        size_t wide = 0;
        for (size_t r = r0; r < r0 + FOUND_ROWS && r < rows; r++)
            wide = st[r + 1] - st[r] > wide ? st[r + 1] - st[r] : wide;
        for (size_t x0 = 0; x0 < wide; x0 += FOUND_TILE) {
            if (count == tcap) {
                plan_tile *g = grow(t, &tcap, 0u, sizeof *t);
                if (!g) {
                    free(t);
                    goto fail;
                }
                t = g;
            }
            t[count++] = (plan_tile){r0, x0};
        }
    }
    p->starts = st;
    p->rows = rows;
    p->tiles = t;
    p->items = (long)count;
    p->chunk = 0;
    p->width = 0;
    return 1;
fail:
    free(st);
    return 0;
}

static void plan_make(plan *p, size_t n, const tt_batch_options *o, int threads, int cap)
{
    p->n = n;
    p->tiles = NULL;
    p->starts = NULL;
    p->rows = 0;
    p->width = o->image_width;
    if (p->width) {
        size_t rows = (n + p->width - 1) / p->width;
        p->tiles_x = (p->width + TILE - 1) / TILE;
        p->items = (long)(p->tiles_x * ((rows + TILE - 1) / TILE));
        p->chunk = 0;
        return;
    }
    size_t chunk = o->chunk;
    if (!chunk) {
        /* at least 8 items a thread, for the dynamic schedule to balance */
        chunk = n / ((size_t)threads * 8u);
        chunk = chunk < 16u ? 16u : chunk > MAX_CHUNK ? MAX_CHUNK : chunk;
    }
    /* a packet or rows call takes at most TT_PACKET_MAX rays: one item */
    if (cap && chunk > TT_PACKET_MAX) chunk = TT_PACKET_MAX;
    p->chunk = chunk;
    p->tiles_x = 0;
    p->items = (long)((n + chunk - 1) / chunk);
}

static void plan_item(const plan *p, long item, size_t *first, size_t *len, size_t *rows,
                      size_t *pitch)
{
    if (!p->width) {
        *first = (size_t)item * p->chunk;
        *len = p->chunk;
        *rows = 1;
        *pitch = 0;
        return;
    }
    size_t tx = (size_t)item % p->tiles_x, ty = (size_t)item / p->tiles_x;
    size_t x0 = tx * TILE, y0 = ty * TILE;
    *first = y0 * p->width + x0;
    *len = p->width - x0 < TILE ? p->width - x0 : TILE;
    *rows = TILE;
    *pitch = p->width;
}

/* Every ray index of one work item, in order, clipped to the batch. */
#define FOR_EACH_RAY(p, item, i)                                                               \
    size_t first_, len_, rows_, pitch_;                                                        \
    plan_item(p, item, &first_, &len_, &rows_, &pitch_);                                       \
    for (size_t r_ = 0; r_ < rows_ && first_ + r_ * pitch_ < (p)->n; r_++)                     \
        for (size_t i = first_ + r_ * pitch_, e_ = i + len_ < (p)->n ? i + len_ : (p)->n;      \
             i < e_; i++)

void tt_batch_options_default(tt_batch_options *o)
{
    if (!o) return;
    memset(o, 0, sizeof *o);
    o->start_hint = TT_INVALID_ID;
    o->stats = NULL;
    o->chunk = 0;
}

static void load_ray(const tt_ray_arrays *a, size_t i, float org[3], float dir[3], float *tmin,
                     float *tmax)
{
    for (int k = 0; k < 3; k++) {
        org[k] = *at_f(a->org[k], a->org_stride, i);
        dir[k] = *at_f(a->dir[k], a->dir_stride, i);
    }
    *tmin = a->tmin ? *at_f(a->tmin, a->tmin_stride, i) : 0.0f;
    *tmax = a->tmax ? *at_f(a->tmax, a->tmax_stride, i) : TT_INF;
}

/* Whether a batch's rays are worth finding rows for: FOUND_SAMPLE rays
 * spread evenly over the whole batch share a far end (shadow rays to one
 * light) or a direction (a distant light), by the packets' own rule
 * (packets.h). Rays in random directions (ambient occlusion, diffuse
 * bounces) fail it and keep the runs: their items go ray by ray under auto
 * anyway, and the row search, serial before the threads start, cost them
 * 4-10% of their batch (engine table, 2026-12-07: R-tree AO under auto
 * 0.91-0.96x of packets off on bunny and Cornell). */
#define FOUND_SAMPLE 32u
static int batch_converges(const tt_ray_arrays *a, size_t n)
{
    tt_dir_box d;
    tt_end_box e;
    tt_dir_box_init(&d);
    tt_end_box_init(&e);
    for (size_t k = 0; k < FOUND_SAMPLE; k++) {
        float org[3], dir[3], tmin, tmax;
        load_ray(a, k * (n - 1) / (FOUND_SAMPLE - 1), org, dir, &tmin, &tmax);
        tt_dir_box_add(&d, dir);
        tt_end_box_add(&e, org, dir, tmax);
    }
    return tt_packet_boxes_coherent(&d, &e);
}

static void store_hit(const tt_hit_arrays *h, size_t i, const tt_hit *hit)
{
    if (h->t) *(float *)(void *)((char *)h->t + (ptrdiff_t)i * h->t_stride) = hit->t;
    if (h->u) *(float *)(void *)((char *)h->u + (ptrdiff_t)i * h->u_stride) = hit->u;
    if (h->v) *(float *)(void *)((char *)h->v + (ptrdiff_t)i * h->v_stride) = hit->v;
    if (h->prim)
        *(uint32_t *)(void *)((char *)h->prim + (ptrdiff_t)i * h->prim_stride) = hit->prim;
}

/* The ray contract's common case in a few compares, inline: finite origin
 * and direction, a direction not too short (TT_RAY_DIR_MIN), 0 <= tmin and
 * tmax not NaN. Any ray
 * failing it goes to tt_ray_check, which decides (and words the cause). */
static inline tt_status check_ray(const float org[3], const float dir[3], float tmin, float tmax)
{
    /* without branches (a ray's checks were 50 instructions, a sixth of a
     * shadow ray's batch overhead): x - x is +0 for a finite x and NaN for
     * an infinite or NaN one, and a NaN survives the sum */
    const float fin = ((org[0] - org[0]) + (org[1] - org[1])) + ((org[2] - org[2]) + (dir[0] - dir[0])) +
                      ((dir[1] - dir[1]) + (dir[2] - dir[2]));
    const int ok = (fin == 0.0f) & (tmin >= 0.0f) & (tmax == tmax) &
                   ((fabsf(dir[0]) >= TT_RAY_DIR_MIN) | (fabsf(dir[1]) >= TT_RAY_DIR_MIN) |
                    (fabsf(dir[2]) >= TT_RAY_DIR_MIN));
    return ok ? TT_OK : tt_ray_check(org, dir, tmin, tmax, NULL, 0);
}

/* Ray i of the arrays into row j of a packet. */
static inline void load_row(const tt_ray_arrays *a, size_t i, tt_packet_rays *p, uint32_t j)
{
    for (int k = 0; k < 3; k++) {
        p->org[k][j] = *at_f(a->org[k], a->org_stride, i);
        p->dir[k][j] = *at_f(a->dir[k], a->dir_stride, i);
    }
    p->tmin[j] = a->tmin ? *at_f(a->tmin, a->tmin_stride, i) : 0.0f;
    p->tmax[j] = a->tmax ? *at_f(a->tmax, a->tmax_stride, i) : TT_INF;
}

/* The rays as tt_ray's (the AoS calls, tt_intersect / tt_occluded, or
 * arrays laid out the same way): their base, else NULL. A row is then
 * eight loads from one structure, not eight strided address computations
 * (the gathering was about a third of the batch's remaining work a ray,
 * callgrind, bunny primary rays). */
static const tt_ray *aos_rays_of(const tt_ray_arrays *a)
{
    const float *b = a->org[0];
    const ptrdiff_t s = (ptrdiff_t)sizeof(tt_ray);
    if (a->org_stride != s || a->dir_stride != s || a->tmin_stride != s || a->tmax_stride != s)
        return NULL;
    const float *const f = b;
#define TT_AT(field, k) (f + (offsetof(tt_ray, field) + (k) * sizeof(float)) / sizeof(float))
    if (a->org[1] != TT_AT(org, 1) || a->org[2] != TT_AT(org, 2) || a->dir[0] != TT_AT(dir, 0) ||
        a->dir[1] != TT_AT(dir, 1) || a->dir[2] != TT_AT(dir, 2) || a->tmin != TT_AT(tmin, 0) ||
        a->tmax != TT_AT(tmax, 0))
        return NULL;
#undef TT_AT
    return (const tt_ray *)(const void *)b;
}

/* The results as tt_hit's, likewise: their base, else NULL. */
static tt_hit *aos_hits_of(const tt_hit_arrays *h)
{
    if (!h) return NULL;
    const ptrdiff_t s = (ptrdiff_t)sizeof(tt_hit);
    if (h->t_stride != s || h->u_stride != s || h->v_stride != s || h->prim_stride != s)
        return NULL;
    float *const f = h->t;
    if (h->u != f + 1 || h->v != f + 2 || (void *)h->prim != (void *)(f + 3)) return NULL;
    return (tt_hit *)(void *)f;
}

/* Ray i of tt_ray's into row j. */
static inline void load_row_aos(const tt_ray *r, tt_packet_rays *p, uint32_t j)
{
    for (int k = 0; k < 3; k++) {
        p->org[k][j] = r->org[k];
        p->dir[k][j] = r->dir[k];
    }
    p->tmin[j] = r->tmin;
    p->tmax[j] = r->tmax;
}

/* Rays r[0..4) of tt_ray's into rows j .. j + 3: with SSE (x86-64's
 * baseline) each ray's two halves (org, tmin / dir, tmax) are two loads
 * and four rays' halves two 4 x 4 transposes, instead of eight scalar
 * copies a ray (callgrind: a found tile's gathering was about a tenth of
 * a shadow batch's instructions). The same floats land in the same rows. */
static inline int load4_rows_aos(const tt_ray *r, tt_packet_rays *p, uint32_t j)
{
#if defined(__SSE2__)
    _Static_assert(sizeof(tt_ray) == 32 && offsetof(tt_ray, tmin) == 12 &&
                       offsetof(tt_ray, dir) == 16 && offsetof(tt_ray, tmax) == 28,
                   "tt_ray: two halves of four floats");
    const float *f = (const float *)(const void *)r;
    __m128 o0 = _mm_loadu_ps(f), o1 = _mm_loadu_ps(f + 8), o2 = _mm_loadu_ps(f + 16),
           o3 = _mm_loadu_ps(f + 24);
    __m128 d0 = _mm_loadu_ps(f + 4), d1 = _mm_loadu_ps(f + 12), d2 = _mm_loadu_ps(f + 20),
           d3 = _mm_loadu_ps(f + 28);
    _MM_TRANSPOSE4_PS(o0, o1, o2, o3);
    _MM_TRANSPOSE4_PS(d0, d1, d2, d3);
    _mm_storeu_ps(p->org[0] + j, o0);
    _mm_storeu_ps(p->org[1] + j, o1);
    _mm_storeu_ps(p->org[2] + j, o2);
    _mm_storeu_ps(p->tmin + j, o3);
    _mm_storeu_ps(p->dir[0] + j, d0);
    _mm_storeu_ps(p->dir[1] + j, d1);
    _mm_storeu_ps(p->dir[2] + j, d2);
    _mm_storeu_ps(p->tmax + j, d3);
    /* check_rows' quick test of the four, on the registers: x - x is 0
     * for every finite x and NaN otherwise, so the sum is 0 exactly when
     * all six are finite */
    const __m128 zero = _mm_setzero_ps(), sign = _mm_set1_ps(-0.0f),
                 dmin = _mm_set1_ps(TT_RAY_DIR_MIN);
    const __m128 fin = _mm_add_ps(
        _mm_add_ps(_mm_add_ps(_mm_sub_ps(o0, o0), _mm_sub_ps(o1, o1)),
                   _mm_add_ps(_mm_sub_ps(o2, o2), _mm_sub_ps(d0, d0))),
        _mm_add_ps(_mm_sub_ps(d1, d1), _mm_sub_ps(d2, d2)));
    const __m128 dir_ok = _mm_or_ps(_mm_or_ps(_mm_cmpge_ps(_mm_andnot_ps(sign, d0), dmin),
                                              _mm_cmpge_ps(_mm_andnot_ps(sign, d1), dmin)),
                                    _mm_cmpge_ps(_mm_andnot_ps(sign, d2), dmin));
    const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmpeq_ps(fin, zero), _mm_cmpge_ps(o3, zero)),
                                 _mm_and_ps(_mm_cmpeq_ps(d3, d3), dir_ok));
    return _mm_movemask_ps(ok) == 15;
#else
    for (uint32_t q = 0; q < 4; q++) load_row_aos(&r[q], p, j + q);
    return 0; /* (check_rows decides) */
#endif
}

/* Found tile `item` of the plan into rows, in blocks of FOUND_COLS columns
 * by its rows (a kernel walk of 16 or 32 rays is then 4 x 4 or 4 x 8
 * pixels), each row's rays as far as the row goes; their indices into idx.
 * Returns the rows' count. */
static uint32_t gather_found_tile(const plan *p, long item, const tt_ray_arrays *rays,
                                  const tt_ray *aos, tt_packet_rays *pr, size_t *idx, int *quick)
{
    const plan_tile *t = &p->tiles[item];
    const size_t r1 = t->row + FOUND_ROWS < p->rows ? t->row + FOUND_ROWS : p->rows;
    uint32_t np = 0;
    int ok = 1;
    for (size_t x0 = t->x0; x0 < t->x0 + FOUND_TILE; x0 += FOUND_COLS)
        for (size_t r = t->row; r < r1; r++) {
            const size_t first = p->starts[r] + x0, end = p->starts[r + 1];
            if (aos && FOUND_COLS == 4u && first + 4u <= end) {
                ok &= load4_rows_aos(&aos[first], pr, np);
                for (uint32_t q = 0; q < 4u; q++) idx[np + q] = first + q;
                np += 4u;
                continue;
            }
            for (size_t i = first; i < end && i < first + FOUND_COLS; i++) {
                if (aos) load_row_aos(&aos[i], pr, np);
                else load_row(rays, i, pr, np);
                idx[np++] = i;
                ok = 0;
            }
        }
    /* 1: every row came through load4_rows_aos and passed its quick test */
    *quick = ok;
    return np;
}

/* An image tile (image_width given) whose TILE x TILE rays all lie in the
 * batch. */
static inline int image_tile_whole(const plan *p, long item)
{
    if (!p->width) return 0;
    const size_t tx = (size_t)item % p->tiles_x, ty = (size_t)item / p->tiles_x;
    return (tx + 1u) * TILE <= p->width && (ty + 1u) * TILE * p->width <= p->n;
}

/* A whole image tile into rows (image_tile_whole) in blocks of IMAGE_COLS
 * columns by its TILE rows, four rays at a time (load4_rows_aos), instead
 * of row by row with a scalar copy a float. A kernel walk of 16 or 32 rays
 * is then 4 x 4 or 4 x 8 pixels instead of one or two image rows of 16:
 * the kd-tree's packet walks visit 4-15% fewer nodes (the counting
 * variant, primary rays of bunny, sibenik, conference; 4 columns fewer than
 * 8 on AVX2, level on AVX-512). The R-tree's packets take the whole tile
 * at once: the same visits, only the faster gathering. */
#define IMAGE_COLS 4u
_Static_assert(IMAGE_COLS % 4u == 0 && TILE % IMAGE_COLS == 0, "blocks of four rays");
static uint32_t gather_image_tile(const plan *p, long item, const tt_ray *aos,
                                  tt_packet_rays *pr, size_t *idx, int *quick)
{
    size_t first, len, rows, pitch;
    plan_item(p, item, &first, &len, &rows, &pitch);
    uint32_t np = 0;
    int ok = 1;
    for (size_t x0 = 0; x0 < TILE; x0 += IMAGE_COLS)
        for (size_t r = 0; r < TILE; r++)
            for (size_t q0 = 0; q0 < IMAGE_COLS; q0 += 4u) {
                const size_t i = first + r * pitch + x0 + q0;
                ok &= load4_rows_aos(&aos[i], pr, np);
                for (uint32_t q = 0; q < 4u; q++) idx[np + q] = i + q;
                np += 4u;
            }
    /* 1: every row passed load4_rows_aos's quick test */
    *quick = ok;
    return np;
}

/* check_ray's quick test over a packet's rows at once, in a loop the
 * compiler vectorises: 1 when every ray passes it (the common case; a ray
 * failing it may still be valid, and check_ray decides). */
static inline int check_rows(const tt_packet_rays *p)
{
    uint32_t fail = 0;
    for (uint32_t j = 0; j < p->n; j++) {
        const float fin =
            ((p->org[0][j] - p->org[0][j]) + (p->org[1][j] - p->org[1][j])) +
            ((p->org[2][j] - p->org[2][j]) + (p->dir[0][j] - p->dir[0][j])) +
            ((p->dir[1][j] - p->dir[1][j]) + (p->dir[2][j] - p->dir[2][j]));
        const int ok = (fin == 0.0f) & (p->tmin[j] >= 0.0f) & (p->tmax[j] == p->tmax[j]) &
                       ((fabsf(p->dir[0][j]) >= TT_RAY_DIR_MIN) |
                        (fabsf(p->dir[1][j]) >= TT_RAY_DIR_MIN) |
                        (fabsf(p->dir[2][j]) >= TT_RAY_DIR_MIN));
        fail |= (uint32_t)!ok;
    }
    return fail == 0;
}

static int arrays_ok(const tt_ray_arrays *a)
{
    return a && a->org[0] && a->org[1] && a->org[2] && a->dir[0] && a->dir[1] && a->dir[2];
}

static int threads_of(const tt_accel *accel)
{
    return tt_context_team(accel->ctx);
}

/* After the batch: the context's message names the first bad ray, in the
 * single-ray calls' words, prefixed by its index. */
static tt_status report_bad(const tt_accel *accel, const tt_ray_arrays *a, size_t n, size_t bad,
                            size_t bad_count, const char *call)
{
    if (bad_count == 0) return TT_OK;
    float org[3], dir[3], tmin, tmax;
    char why[160];
    load_ray(a, bad, org, dir, &tmin, &tmax);
    tt_ray_check(org, dir, tmin, tmax, why, sizeof why);
    return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT, "%s: ray %zu of %zu: %s (%zu bad ray%s)",
                    call, bad, n, why, bad_count, bad_count == 1 ? "" : "s");
}

static tt_status check_call(const tt_accel *accel, const tt_batch_options *o, const char *call)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    if (o && o->chunk > (1u << 30))
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT, "%s: chunk %u is too large", call,
                        o->chunk);
    if (o && o->packets > TT_PACKETS_ON)
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: packets %u is not TT_PACKETS_AUTO, _OFF or _ON", call, o->packets);
    if (o && o->image_width > (1u << 30))
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT, "%s: image_width %u is too large",
                        call, o->image_width);
    return TT_OK;
}

/* Whether this batch may use packets at all: the structure offers them and
 * the option allows them. A start hint only speeds a single ray's walk (the
 * answer is the closest hit either way, ties included: the smaller id
 * wins), so packets, which start at the root, ignore it. */
static int packets_allowed(const tt_accel *accel, const tt_accel_vtable *vt,
                           const tt_batch_options *o, int closest)
{
    if (o->packets == TT_PACKETS_OFF) return 0;
    if (vt->packets_for && !vt->packets_for(accel)) return 0;
    return closest ? vt->intersect_packet != NULL : vt->occluded_packet != NULL;
}

/* The loop both calls share: each thread takes the plan's items, checks
 * and traces their rays, and stores a hit (hits != NULL: closest hits) or
 * an occlusion byte. The choice is one predictable branch a ray, which
 * costs nothing beside a traversal and keeps one copy of the loop.
 *
 * With packets, an item's valid rays (at most TILE x TILE = MAX_CHUNK =
 * TT_PACKET_MAX) are gathered as rows (tt_packet_rays) and handed to the
 * structure's packet entry in one call (TT_PACKETS_ON), or when coherent
 * (TT_PACKETS_AUTO:
 * tt_packet_coherent, per item, so a batch mixing camera rays and
 * ambient-occlusion rays gets each kind its way). */
static tt_status run_batch(const tt_accel *accel, const tt_ray_arrays *rays, size_t n,
                           const tt_batch_options *options, const char *call,
                           const tt_hit_arrays *hits, uint8_t *occluded, ptrdiff_t occluded_stride,
                           tt_status *ray_status)
{
    tt_batch_options def;
    tt_batch_options_default(&def);
    const tt_batch_options *o = options ? options : &def;
    const tt_accel_vtable *vt = accel->vt;
    const int threads = threads_of(accel);
    const int use_packets = packets_allowed(accel, vt, o, hits != NULL);
    /* the counting variants trace when either count is asked for */
    const int counting = o->stats != NULL || o->packet_stats != NULL;
    /* single rays through the structure's rows entry where it has one (the
     * counting variants keep their per-ray calls): items that are not
     * packets, and the few rays of a packet item too small to be one
     * (the rows entry answers as the single-ray one does either way) */
    const int use_rows =
        !counting && (hits ? vt->intersect_rows != NULL : vt->occluded_rows != NULL);
    /* TT_PACKETS_AUTO: an item's rows are gathered first (every item's
     * are, for one path or the other) and judged after the check
     * (tt_packet_coherent, packets.h) */
    const int judge = use_packets && o->packets == TT_PACKETS_AUTO;
    /* ... and asks the structure whether packets pay (packet_probe.h); the
     * counting variants take the same path, their counts the probes' too */
    const tt_ray *const aos = aos_rays_of(rays);
    tt_hit *const hits_aos = aos_hits_of(hits);
    tt_status entered = tt_accel_trace_enter(accel, call);
    if (entered != TT_OK) return entered;
    plan p;
    plan_make(&p, n, o, threads, use_packets || use_rows);
    /* occlusion packets without an image width: rows found (plan_find_rows) */
    const int found = !hits && use_packets && !o->image_width && !o->chunk &&
                      n >= 4u * TILE * TILE && batch_converges(rays, n) &&
                      plan_find_rows(&p, n, rays, aos);
    size_t bad = SIZE_MAX, bad_count = 0;
#pragma omp parallel num_threads(threads) reduction(min : bad) reduction(+ : bad_count)
    {
        tt_ray_stats local;
        memset(&local, 0, sizeof local);
        tt_packet_stats plocal;
        memset(&plocal, 0, sizeof plocal);
        tt_packet_rays prows;
        tt_packet_rays *const pr = &prows;
        tt_hit ph[TT_PACKET_MAX];
        uint8_t pocc[TT_PACKET_MAX];
        size_t pidx[TT_PACKET_MAX];
        tt_packet_probe pp;
        tt_packet_probe_init(&pp, accel, hits != NULL);
#pragma omp for schedule(dynamic)
        for (long c = 0; c < p.items; c++) {
            int packet = use_packets;
            int rows = use_rows;
            if (packet || rows) {
                /* the item's rays straight into rows; the kernel derives
                 * reciprocals, shear and octants itself */
                uint32_t np = 0;
                int quick = 0;
                if (found) {
                    np = gather_found_tile(&p, c, rays, aos, pr, pidx, &quick);
                } else if (aos && image_tile_whole(&p, c)) {
                    np = gather_image_tile(&p, c, aos, pr, pidx, &quick);
                } else if (aos) {
                    FOR_EACH_RAY(&p, c, i) {
                        /* runs (no image width): the ray 128 ahead
                         * (4 KiB) asked for now. An item's rays are a
                         * fresh stretch of the array (the threads take
                         * turns), where the hardware's streaming starts
                         * late: shadow batches spent a fifth of their time
                         * waiting for these loads (perf). */
                        if (!p.width) __builtin_prefetch(&aos[i + 128u < p.n ? i + 128u : i]);
                        load_row_aos(&aos[i], pr, np);
                        pidx[np++] = i;
                    }
                } else {
                    FOR_EACH_RAY(&p, c, i) {
                        load_row(rays, i, pr, np);
                        pidx[np++] = i;
                    }
                }
                pr->n = np;
                if (quick || check_rows(pr)) {
                    if (ray_status)
                        for (uint32_t j = 0; j < np; j++) ray_status[pidx[j]] = TT_OK;
                } else {
                    /* some ray fails the quick test: each such ray to
                     * tt_ray_check, the bad ones out of the rows */
                    uint32_t keep = 0;
                    for (uint32_t j = 0; j < np; j++) {
                        const size_t i = pidx[j];
                        const float org[3] = {pr->org[0][j], pr->org[1][j], pr->org[2][j]};
                        const float dir[3] = {pr->dir[0][j], pr->dir[1][j], pr->dir[2][j]};
                        const tt_status rs = check_ray(org, dir, pr->tmin[j], pr->tmax[j]);
                        if (ray_status) ray_status[i] = rs;
                        if (rs == TT_OK) {
                            tt_packet_ray_set(pr, keep, org, dir, pr->tmin[j], pr->tmax[j]);
                            pidx[keep++] = i;
                            continue;
                        }
                        if (i < bad) bad = i;
                        bad_count++;
                        if (hits) {
                            tt_hit h;
                            tt_hit_clear(&h);
                            store_hit(hits, i, &h);
                        } else {
                            occluded[(ptrdiff_t)i * occluded_stride] = 0;
                        }
                    }
                    pr->n = np = keep;
                }
                if (judge) packet = tt_packet_coherent(pr);
                if (packet && judge &&
                    tt_packet_probe_trace(&pp, accel, pr, hits ? ph : NULL, pocc, &packet,
                                          counting ? &plocal : NULL)) {
                    /* traced by the probe */
                } else if (packet && (np >= TT_PACKET_MIN || o->packets == TT_PACKETS_ON)) {
                    if (hits && counting) vt->intersect_packet_stats(accel, pr, ph, &plocal);
                    else if (hits) vt->intersect_packet(accel, pr, ph);
                    else if (counting) vt->occluded_packet_stats(accel, pr, pocc, &plocal);
                    else vt->occluded_packet(accel, pr, pocc);
                } else if (rows) {
                    /* single rays in the structure's kernel unit: no
                     * per-ray preparation or calls through pointers here */
                    if (hits) vt->intersect_rows(accel, pr, o->start_hint, ph);
                    else vt->occluded_rows(accel, pr, o->start_hint, pocc);
                } else {
                    for (uint32_t j = 0; j < np; j++) {
                        tt_trace_args args = {o->start_hint, TT_INVALID_ID,
                                              counting ? &local : NULL};
                        tt_wray w;
                        tt_packet_ray_wray(pr, j, &w);
                        if (hits && counting) vt->intersect_stats(accel, &w, &ph[j], &args, &local);
                        else if (hits) vt->intersect(accel, &w, &ph[j], &args);
                        else if (counting)
                            pocc[j] = (uint8_t)(vt->occluded_stats(accel, &w, &args, &local) != 0);
                        else pocc[j] = (uint8_t)(vt->occluded(accel, &w, &args) != 0);
                    }
                }
                if (hits_aos)
                    for (uint32_t j = 0; j < np; j++) hits_aos[pidx[j]] = ph[j];
                else if (hits)
                    for (uint32_t j = 0; j < np; j++) store_hit(hits, pidx[j], &ph[j]);
                else if (quick && occluded_stride == 1)
                    /* a found tile of whole blocks: four consecutive rays
                     * at every fourth row, one 4-byte copy each */
                    for (uint32_t j = 0; j < np; j += 4u) memcpy(occluded + pidx[j], pocc + j, 4);
                else
                    for (uint32_t j = 0; j < np; j++)
                        occluded[(ptrdiff_t)pidx[j] * occluded_stride] = pocc[j];
                continue;
            }
            FOR_EACH_RAY(&p, c, i) {
                float org[3], dir[3], tmin, tmax;
                tt_hit h;
                int occ = 0;
                load_ray(rays, i, org, dir, &tmin, &tmax);
                tt_status rs = check_ray(org, dir, tmin, tmax);
                if (rs == TT_OK) {
                    tt_wray w;
                    tt_trace_args args = {o->start_hint, TT_INVALID_ID, counting ? &local : NULL};
                    tt_wray_init(&w, org, dir, tmin, tmax);
                    if (hits && counting) vt->intersect_stats(accel, &w, &h, &args, &local);
                    else if (hits) vt->intersect(accel, &w, &h, &args);
                    else if (counting) occ = vt->occluded_stats(accel, &w, &args, &local);
                    else occ = vt->occluded(accel, &w, &args);
                } else {
                    if (hits) tt_hit_clear(&h);
                    if (i < bad) bad = i;
                    bad_count++;
                }
                if (ray_status) ray_status[i] = rs;
                if (hits) store_hit(hits, i, &h);
                else occluded[(ptrdiff_t)i * occluded_stride] = (uint8_t)(occ != 0);
            }
        }
        if (counting) {
            tt_ray_stats_add(&local, &plocal.rays);
#pragma omp critical(tt_batch_stats)
            {
                if (o->stats) tt_ray_stats_add(o->stats, &local);
                if (o->packet_stats) {
                    o->packet_stats->packets += plocal.packets;
                    o->packet_stats->node_visits += plocal.node_visits;
                    o->packet_stats->active_lanes += plocal.active_lanes;
                    o->packet_stats->fallback_rays += plocal.fallback_rays;
                }
            }
        }
    }
    free(p.tiles);
    free(p.starts);
    tt_accel_trace_leave(accel);
    return report_bad(accel, rays, n, bad, bad_count, call);
}

tt_status tt_intersect_arrays(const tt_accel *accel, const tt_ray_arrays *rays, size_t n,
                              const tt_hit_arrays *hits, tt_status *ray_status,
                              const tt_batch_options *options)
{
    static const char call[] = "tt_intersect";
    tt_status st = check_call(accel, options, call);
    if (st != TT_OK) return st;
    if (n == 0) return TT_OK;
    if (!arrays_ok(rays) || !hits)
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: %zu rays but no ray or result arrays", call, n);
    return run_batch(accel, rays, n, options, call, hits, NULL, 0, ray_status);
}

tt_status tt_occluded_arrays(const tt_accel *accel, const tt_ray_arrays *rays, size_t n,
                             uint8_t *occluded, ptrdiff_t occluded_stride,
                             tt_status *ray_status, const tt_batch_options *options)
{
    static const char call[] = "tt_occluded";
    tt_status st = check_call(accel, options, call);
    if (st != TT_OK) return st;
    if (n == 0) return TT_OK;
    if (!arrays_ok(rays) || !occluded)
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: %zu rays but no ray or result arrays", call, n);
    if (occluded_stride == 0) occluded_stride = 1;
    return run_batch(accel, rays, n, options, call, NULL, occluded, occluded_stride, ray_status);
}

/* The AoS forms: the same loops over tt_ray's and tt_hit's own layout. */
static void aos_rays(const tt_ray *rays, tt_ray_arrays *a)
{
    memset(a, 0, sizeof *a);
    for (int k = 0; k < 3; k++) {
        a->org[k] = &rays[0].org[k];
        a->dir[k] = &rays[0].dir[k];
    }
    a->org_stride = a->dir_stride = a->tmin_stride = a->tmax_stride = (ptrdiff_t)sizeof(tt_ray);
    a->tmin = &rays[0].tmin;
    a->tmax = &rays[0].tmax;
}

tt_status tt_intersect(const tt_accel *accel, const tt_ray *rays, size_t n, tt_hit *hits,
                       tt_status *ray_status, const tt_batch_options *options)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    if (n > 0 && (!rays || !hits))
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_intersect: %zu rays but no ray or hit array", n);
    if (n == 0) return check_call(accel, options, "tt_intersect");
    tt_ray_arrays a;
    aos_rays(rays, &a);
    const ptrdiff_t s = (ptrdiff_t)sizeof(tt_hit);
    tt_hit_arrays h = {&hits[0].t, s, &hits[0].u, s, &hits[0].v, s, &hits[0].prim, s};
    return tt_intersect_arrays(accel, &a, n, &h, ray_status, options);
}

tt_status tt_occluded(const tt_accel *accel, const tt_ray *rays, size_t n, uint8_t *occluded,
                      tt_status *ray_status, const tt_batch_options *options)
{
    if (!accel) return TT_ERR_INVALID_ARGUMENT;
    if (n > 0 && (!rays || !occluded))
        return tt_error(accel->ctx, TT_ERR_INVALID_ARGUMENT,
                        "tt_occluded: %zu rays but no ray or result array", n);
    if (n == 0) return check_call(accel, options, "tt_occluded");
    tt_ray_arrays a;
    aos_rays(rays, &a);
    return tt_occluded_arrays(accel, &a, n, occluded, 1, ray_status, options);
}
