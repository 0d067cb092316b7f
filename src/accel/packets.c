/* tt_packet_coherent (packets.h): the rule's two boxes over a sample of a
 * packet's rows, four lanes at once. Each lane keeps its own running
 * minima (a box's upper sides as minima of the negated values), so the loop
 * over a run's eight rows has no reduction across lanes and the compiler
 * vectorises it as written (square root and division included: this unit
 * is compiled with -fno-math-errno, CMakeLists.txt; nothing here reads
 * errno); the lanes are folded by halving, also a vector loop, into one
 * tt_dir_box / tt_end_box, whose tests are the header's. The boxes are the
 * ones tt_dir_box_add / tt_end_box_add grow from the same rays (the same
 * operations on the same floats). */
#include "accel/packets.h"

/* lanes: a baseline x86-64 vector of floats (a run is two steps) */
#define L 4u

/* The running minima: unit directions' lower sides and negated upper
 * sides, the ends' (org + tmax dir) likewise, the shortest tmax |dir|. */
enum { DLO = 0, DHI = 3, ELO = 6, EHI = 9, SHORT = 12, MINIMA = 13 };

typedef struct lane_boxes {
    float m[MINIMA][L];
    uint32_t open[L]; /* a tmax not below infinity (or NaN) */
} lane_boxes;

static inline float min_of(float x, float m) { return x < m ? x : m; }

static void lanes_init(lane_boxes *b)
{
    for (uint32_t l = 0; l < L; l++) {
        for (int k = 0; k < 3; k++) {
            b->m[DLO + k][l] = 2.0f, b->m[DHI + k][l] = 2.0f;
            b->m[ELO + k][l] = INFINITY, b->m[EHI + k][l] = INFINITY;
        }
        b->m[SHORT][l] = INFINITY;
        b->open[l] = 0;
    }
}

/* Rows s .. s + TT_PACKET_RUN - 1 into the lanes. */
static void lanes_add_run(lane_boxes *restrict b, const tt_packet_rays *restrict p, uint32_t s)
{
    for (uint32_t step = 0; step < TT_PACKET_RUN / L; step++)
    for (uint32_t l = 0; l < L; l++) {
        const uint32_t j = s + step * L + l;
        const float d[3] = {p->dir[0][j], p->dir[1][j], p->dir[2][j]};
        const float t = p->tmax[j];
        const float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const float inv = 1.0f / len;
        for (int k = 0; k < 3; k++) {
            const float x = d[k] * inv;
            b->m[DLO + k][l] = min_of(x, b->m[DLO + k][l]);
            b->m[DHI + k][l] = min_of(-x, b->m[DHI + k][l]);
            const float e = p->org[k][j] + t * d[k];
            b->m[ELO + k][l] = min_of(e, b->m[ELO + k][l]);
            b->m[EHI + k][l] = min_of(-e, b->m[EHI + k][l]);
        }
        b->m[SHORT][l] = min_of(t * len, b->m[SHORT][l]);
        b->open[l] |= (uint32_t)!(t < INFINITY);
    }
}

static void lanes_fold(lane_boxes *b, uint32_t rays, tt_dir_box *d, tt_end_box *e)
{
    _Static_assert(L == 4, "two halvings");
    for (int q = 0; q < MINIMA; q++) {
        for (uint32_t l = 0; l < 2; l++) b->m[q][l] = min_of(b->m[q][l + 2], b->m[q][l]);
        b->m[q][0] = min_of(b->m[q][1], b->m[q][0]);
    }
    uint32_t open = 0;
    for (uint32_t l = 0; l < L; l++) open |= b->open[l];
    for (int k = 0; k < 3; k++) {
        d->lo[k] = b->m[DLO + k][0], d->hi[k] = -b->m[DHI + k][0];
        e->lo[k] = b->m[ELO + k][0], e->hi[k] = -b->m[EHI + k][0];
    }
    d->n = rays;
    e->shortest = b->m[SHORT][0];
    e->open = open != 0;
}

int tt_packet_coherent(const tt_packet_rays *p)
{
    const uint32_t n = p->n;
    if (n < TT_PACKET_MIN) return 0;
    _Static_assert(TT_PACKET_MIN >= TT_PACKET_RUN && TT_PACKET_RUN % L == 0, "whole runs");
    lane_boxes b;
    lanes_init(&b);
    for (uint32_t r = 0; r < TT_PACKET_RUNS; r++)
        lanes_add_run(&b, p, r * (n - TT_PACKET_RUN) / (TT_PACKET_RUNS - 1));
    tt_dir_box d;
    tt_end_box e;
    lanes_fold(&b, TT_PACKET_RUN * TT_PACKET_RUNS, &d, &e);
    return tt_packet_boxes_coherent(&d, &e);
}
