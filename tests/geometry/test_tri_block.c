/* The triangle blocks (geometry/tri_block.h): every ISA kernel this CPU runs
 * returns bit for bit the scalar reference's answer (return value, t, u, v,
 * prim) and the same occlusion answer, on random triangles and rays, rays
 * through shared edges and vertices of meshes (axis-parallel ones on integer
 * grids give zero edge functions, which take the double-precision path),
 * tiny and huge coordinates, rays in a triangle's plane, degenerate
 * triangles, partial blocks, the [tmin, tmax) boundaries and ties at equal t
 * within and across blocks. The packer is checked too, and the packed scalar
 * answer against a plain loop over tt_intersect_triangle. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/isa.h"
#include "geometry/tri_block.h"

/* ---- randomness ---------------------------------------------------------- */

static uint64_t rng = 0x9e3779b97f4a7c15ull;

static uint32_t rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (uint32_t)(rng >> 16);
}

static float frand(float lo, float hi) { return lo + (hi - lo) * (float)(rnd() & 0xffffff) / 16777216.0f; }

/* ---- the paths under test ------------------------------------------------ */

static tt_isa isas[TT_ISA_LAST + 1];
static tt_tri_block_kernels kernels[TT_ISA_LAST + 1];
static int n_isas;

/* Per scenario: cases compared, mismatches per path, and what the cases
 * covered (so a scenario that stopped exercising its target fails). */
typedef struct tally {
    long cases, hits, zero_blocks, zero_hits, ties;
    long bad[TT_ISA_LAST + 1];
    long bad_occluded, bad_plain;
} tally;

/* Bit i: lane i of block b has a zero edge function for r (the condition
 * under which the kernels hand the block to the scalar code), computed as
 * tt_intersect_triangle does. */
static int zero_lanes(const tt_wray *r, const tt_tri_block *b)
{
    int m = 0;
    for (int i = 0; i < TT_TRI_BLOCK_W; i++) {
        float p[3][2], z[3];
        for (int k = 0; k < 3; k++) {
            const float x = b->v[3 * k + r->kx][i] - r->org[r->kx];
            const float y = b->v[3 * k + r->ky][i] - r->org[r->ky];
            z[k] = b->v[3 * k + r->kz][i] - r->org[r->kz];
            p[k][0] = x - r->sx * z[k];
            p[k][1] = y - r->sy * z[k];
        }
        const float U = p[2][0] * p[1][1] - p[2][1] * p[1][0];
        const float V = p[0][0] * p[2][1] - p[0][1] * p[2][0];
        const float W = p[1][0] * p[0][1] - p[1][1] * p[0][0];
        if (U == 0.0f || V == 0.0f || W == 0.0f) m |= 1 << i;
    }
    return m;
}

static void print_hit(const char *what, int ret, const tt_hit *h)
{
    fprintf(stderr, "    %-8s ret %d t %a u %a v %a prim %u\n", what, ret, (double)h->t,
            (double)h->u, (double)h->v, h->prim);
}

/* Every path on blocks b[0..count) for ray r on [r->tmin, tmax). */
static void check_case(tally *s, const char *name, const tt_wray *r, const tt_tri_block *b,
                       uint32_t count, float tmax)
{
    /* no hit yet: prim TT_INVALID_ID and t the ray's tmax, the kernels'
     * contract (tri_block.h); u, v -7 show whether a miss writes them */
    const tt_hit init = {tmax, -7.0f, -7.0f, TT_INVALID_ID};
    tt_hit ref = init;
    const int ret = tt_tri_blocks_intersect_scalar(r, b, count, &ref);
    const int occ = tt_tri_blocks_occluded_scalar(r, b, count, tmax);
    s->cases++;
    s->hits += ret;
    if (occ != ret) {
        if (s->bad_occluded++ < 3)
            fprintf(stderr, "%s: scalar occluded %d but intersect %d\n", name, occ, ret);
    }
    for (uint32_t j = 0; j < count; j++)
        if (zero_lanes(r, &b[j])) {
            s->zero_blocks++;
            s->zero_hits += ret;
            break;
        }
    for (int k = 0; k < n_isas; k++) {
        tt_hit h = init;
        const int rk = kernels[k].intersect(r, b, count, &h);
        const int ok = kernels[k].occluded(r, b, count, tmax);
        if (rk != ret || memcmp(&h, &ref, sizeof h) != 0 || ok != occ) {
            if (s->bad[k]++ < 3) {
                fprintf(stderr, "%s: %s differs from scalar (%u blocks, tmax %a):\n", name,
                        tt_isa_name(isas[k]), count, (double)tmax);
                print_hit("scalar", ret, &ref);
                print_hit(tt_isa_name(isas[k]), rk, &h);
                fprintf(stderr, "    occluded scalar %d %s %d\n", occ, tt_isa_name(isas[k]), ok);
            }
        }
    }
}

static void report(const char *name, const tally *s)
{
    printf("%-22s %8ld cases %8ld hits %6ld with zero edge functions (%ld hit) %ld ties\n", name,
           s->cases, s->hits, s->zero_blocks, s->zero_hits, s->ties);
    for (int k = 0; k < n_isas; k++)
        CHECK_MSG(s->bad[k] == 0, "%s: %s: %ld of %ld cases differ from scalar", name,
                  tt_isa_name(isas[k]), s->bad[k], s->cases);
    CHECK_MSG(s->bad_occluded == 0, "%s: occluded disagrees with intersect in %ld cases", name,
              s->bad_occluded);
    CHECK_MSG(s->bad_plain == 0, "%s: packed scalar differs from the plain loop in %ld cases",
              name, s->bad_plain);
}

/* ---- a set of triangles and the rays tried on it ------------------------- */

typedef struct tri_set {
    float *tri; /* 9 floats a triangle */
    uint32_t n, cap;
} tri_set;

static uint32_t set_add(tri_set *t, const float *a, const float *b, const float *c)
{
    if (t->n == t->cap) {
        t->cap = t->cap ? 2 * t->cap : 64;
        t->tri = realloc(t->tri, (size_t)t->cap * 9 * sizeof(float));
    }
    float *p = t->tri + 9 * (size_t)t->n;
    memcpy(p, a, 3 * sizeof(float));
    memcpy(p + 3, b, 3 * sizeof(float));
    memcpy(p + 6, c, 3 * sizeof(float));
    return t->n++;
}

typedef struct packed {
    uint32_t *ids, n, nb;
    tt_tri_block *blocks;
} packed;

/* The set's triangles in blocks, in a random order unless `keep_order`. */
static packed pack(const tri_set *t, int keep_order)
{
    packed p;
    p.n = t->n;
    p.ids = malloc((t->n ? t->n : 1) * sizeof(uint32_t));
    for (uint32_t i = 0; i < t->n; i++) p.ids[i] = i;
    if (!keep_order)
        for (uint32_t i = t->n; i > 1; i--) {
            const uint32_t j = rnd() % i, x = p.ids[i - 1];
            p.ids[i - 1] = p.ids[j];
            p.ids[j] = x;
        }
    p.nb = tt_tri_block_count(t->n);
    p.blocks = aligned_alloc(64, (p.nb ? p.nb : 1) * sizeof(tt_tri_block));
    tt_tri_block_pack(t->tri, p.ids, t->n, p.blocks);
    return p;
}

static void unpack(packed *p)
{
    free(p->ids);
    free(p->blocks);
}

/* Ray r on every path: all blocks, a random run of them, and the packed
 * scalar answer against tt_intersect_triangle over the triangles in packing
 * order. */
static void try_ray(tally *s, const char *name, const tri_set *t, const packed *p,
                    const float *org, const float *dir, float tmin, float tmax)
{
    tt_wray r;
    tt_wray_init(&r, org, dir, tmin, tmax);
    check_case(s, name, &r, p->blocks, p->nb, tmax);
    if (p->nb > 1) {
        const uint32_t j0 = rnd() % p->nb, cnt = 1 + rnd() % (p->nb - j0);
        check_case(s, name, &r, p->blocks + j0, cnt, tmax);
    }
    tt_hit ref = {tmax, -7.0f, -7.0f, TT_INVALID_ID}, plain = ref;
    const int ret = tt_tri_blocks_intersect_scalar(&r, p->blocks, p->nb, &ref);
    int found = 0, first = -1;
    for (uint32_t i = 0; i < p->n; i++) {
        const float *v = t->tri + 9 * (size_t)p->ids[i];
        float th, u, w;
        /* the kernels' rule (tri_block.h): the nearest t, and at equal t the
         * smaller triangle id, whatever the lane order */
        const float bound = found ? nextafterf(plain.t, INFINITY) : plain.t;
        if (tt_intersect_triangle(&r, v, v + 3, v + 6, bound, &th, &u, &w) &&
            (th < plain.t || !found || p->ids[i] < plain.prim)) {
            plain.t = th;
            plain.u = u;
            plain.v = w;
            plain.prim = p->ids[i];
            found = 1;
        }
    }
    /* A tie: a second triangle at exactly the winning t. */
    if (found)
        for (uint32_t i = 0; i < p->n; i++) {
            const float *v = t->tri + 9 * (size_t)p->ids[i];
            float th, u, w;
            if (tt_intersect_triangle(&r, v, v + 3, v + 6, INFINITY, &th, &u, &w) &&
                th == plain.t && p->ids[i] != plain.prim && first < 0) {
                first = (int)i;
                s->ties++;
            }
        }
    if (ret != found || memcmp(&ref, &plain, sizeof ref) != 0) {
        if (s->bad_plain++ < 3) {
            fprintf(stderr, "%s: packed scalar differs from the plain loop:\n", name);
            print_hit("packed", ret, &ref);
            print_hit("plain", found, &plain);
        }
    }
}

/* A ray from `org` aimed at `target`. */
static void try_toward(tally *s, const char *name, const tri_set *t, const packed *p,
                       const float *org, const float *target)
{
    const float d[3] = {target[0] - org[0], target[1] - org[1], target[2] - org[2]};
    try_ray(s, name, t, p, org, d, 0.0f, INFINITY);
}

static void random_point(float *o, float r)
{
    for (int k = 0; k < 3; k++) o[k] = frand(-r, r);
}

/* ---- scenarios ----------------------------------------------------------- */

/* Random triangles of random sizes, rays from random origins aimed at one of
 * them (so most rays hit something and many hit several), 1 to 6 blocks
 * with a random number of used lanes. */
static void test_random(void)
{
    tally s = {0};
    tri_set t = {0};
    for (int set = 0; set < 25000; set++) {
        t.n = 0;
        const uint32_t n = 1 + rnd() % 48;
        const float size = (rnd() & 1) ? 0.3f : 2.0f;
        for (uint32_t i = 0; i < n; i++) {
            float a[3], b[3], c[3];
            random_point(a, 1.0f);
            for (int k = 0; k < 3; k++) {
                b[k] = a[k] + frand(-size, size);
                c[k] = a[k] + frand(-size, size);
            }
            set_add(&t, a, b, c);
        }
        packed p = pack(&t, 0);
        for (int ray = 0; ray < 8; ray++) {
            float o[3], target[3];
            random_point(o, 3.0f);
            const float *v = t.tri + 9 * (size_t)(rnd() % n);
            float u = frand(0, 1), w = frand(0, 1);
            if (u + w > 1) u = 1 - u, w = 1 - w;
            for (int k = 0; k < 3; k++)
                target[k] = v[k] + u * (v[3 + k] - v[k]) + w * (v[6 + k] - v[k]);
            const float tmin = (ray & 3) == 3 ? frand(0.0f, 1.0f) : 0.0f;
            const float tmax = (ray & 7) == 5 ? frand(0.5f, 1.5f) : INFINITY;
            const float d[3] = {target[0] - o[0], target[1] - o[1], target[2] - o[2]};
            try_ray(&s, "random", &t, &p, o, d, tmin, tmax);
        }
        unpack(&p);
    }
    free(t.tri);
    report("random", &s);
    CHECK(s.hits > s.cases / 2);
}

/* A grid of n x n unit squares on integer coordinates (split along
 * alternating diagonals) in the plane axis = level, optionally moved by a
 * rotation and offset (shared vertices stay shared: vertices are
 * transformed, not triangles). */
static void add_grid(tri_set *t, int n, int axis, float level, const float *rot, const float *off)
{
    float *v = malloc((size_t)(n + 1) * (n + 1) * 3 * sizeof(float));
    for (int i = 0; i <= n; i++)
        for (int j = 0; j <= n; j++) {
            float p[3];
            p[axis] = level;
            p[(axis + 1) % 3] = (float)(i - n / 2);
            p[(axis + 2) % 3] = (float)(j - n / 2);
            float *q = v + 3 * (i * (n + 1) + j);
            for (int k = 0; k < 3; k++)
                q[k] = rot ? rot[3 * k] * p[0] + rot[3 * k + 1] * p[1] + rot[3 * k + 2] * p[2] + off[k]
                           : p[k];
        }
#define V(i, j) (v + 3 * ((i) * (n + 1) + (j)))
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            if ((i + j) & 1) {
                set_add(t, V(i, j), V(i + 1, j), V(i + 1, j + 1));
                set_add(t, V(i, j), V(i + 1, j + 1), V(i, j + 1));
            } else {
                set_add(t, V(i, j), V(i + 1, j), V(i, j + 1));
                set_add(t, V(i + 1, j), V(i + 1, j + 1), V(i, j + 1));
            }
        }
#undef V
    free(v);
}

/* A random rotation (from two random unit-ish vectors). */
static void random_rotation(float *m)
{
    float a[3], b[3];
    random_point(a, 1.0f);
    random_point(b, 1.0f);
    float la = sqrtf(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; k++) a[k] /= la;
    const float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for (int k = 0; k < 3; k++) b[k] -= d * a[k];
    float lb = sqrtf(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    for (int k = 0; k < 3; k++) b[k] /= lb;
    const float c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                        a[0] * b[1] - a[1] * b[0]};
    for (int k = 0; k < 3; k++) {
        m[3 * k] = a[k];
        m[3 * k + 1] = b[k];
        m[3 * k + 2] = c[k];
    }
}

/* Rays through the vertices and edge midpoints of grids: axis-parallel ones
 * on the integer grid (zero edge functions: the double path), oblique ones
 * from random origins, and the same on rotated grids. A ray through an
 * interior vertex or edge must hit (watertight through the blocks). */
static void test_grids(void)
{
    tally s = {0};
    long interior = 0, interior_missed = 0;
    tri_set t = {0};
    for (int g = 0; g < 60; g++) {
        t.n = 0;
        const int n = 2 + g % 5, axis = g % 3, rotated = g >= 30;
        float rot[9], off[3];
        random_rotation(rot);
        random_point(off, 5.0f);
        add_grid(&t, n, axis, 0.0f, rotated ? rot : NULL, off);
        packed p = pack(&t, 0);
        for (int i = 0; i <= 2 * n; i++)
            for (int j = 0; j <= 2 * n; j++) {
                /* Vertices (both even) and edge midpoints, in grid units. */
                float q[3];
                q[axis] = 0.0f;
                q[(axis + 1) % 3] = 0.5f * (float)i - (float)(n / 2);
                q[(axis + 2) % 3] = 0.5f * (float)j - (float)(n / 2);
                float target[3];
                for (int k = 0; k < 3; k++)
                    target[k] = rotated ? rot[3 * k] * q[0] + rot[3 * k + 1] * q[1] +
                                              rot[3 * k + 2] * q[2] + off[k]
                                        : q[k];
                const int inside = i > 0 && j > 0 && i < 2 * n && j < 2 * n;
                for (int side = -1; side <= 1; side += 2) {
                    float o[3], d[3] = {0, 0, 0};
                    if (!rotated) {
                        /* Straight down the grid's normal. */
                        memcpy(o, target, sizeof o);
                        o[axis] = 3.0f * (float)side;
                        d[axis] = -(float)side;
                        tt_wray r;
                        tt_wray_init(&r, o, d, 0.0f, INFINITY);
                        tt_hit h = {INFINITY, 0, 0, TT_INVALID_ID};
                        const int hit = tt_tri_blocks_intersect_scalar(&r, p.blocks, p.nb, &h);
                        if (inside) {
                            interior++;
                            interior_missed += !hit;
                        }
                        try_ray(&s, "grids", &t, &p, o, d, 0.0f, INFINITY);
                        /* And slightly tilted, along an axis of the grid. */
                        d[(axis + 1) % 3] = side * 0.125f;
                        try_ray(&s, "grids", &t, &p, o, d, 0.0f, INFINITY);
                    }
                    for (int k = 0; k < 2; k++) {
                        random_point(o, 8.0f);
                        try_toward(&s, "grids", &t, &p, o, target);
                    }
                }
            }
        unpack(&p);
    }
    free(t.tri);
    report("grids", &s);
    CHECK(s.zero_blocks > 1000 && s.zero_hits > 500);
    CHECK(s.ties > 100);
    CHECK_MSG(interior_missed == 0, "%ld of %ld rays through interior grid points missed",
              interior_missed, interior);
}

/* Fans: k triangles around a centre vertex, rays at the centre and along the
 * spokes, the fan in random planes and at random scales. */
static void test_fans(void)
{
    tally s = {0};
    tri_set t = {0};
    for (int f = 0; f < 400; f++) {
        t.n = 0;
        const int k = 3 + f % 22;
        float centre[3], rot[9];
        random_point(centre, 4.0f);
        random_rotation(rot);
        const float radius = (f & 1) ? 1.0f : frand(0.001f, 100.0f);
        float *rim = malloc((size_t)k * 3 * sizeof(float));
        for (int i = 0; i < k; i++) {
            const float a = 6.2831853f * (float)i / (float)k, x = radius * cosf(a), y = radius * sinf(a);
            for (int c = 0; c < 3; c++) rim[3 * i + c] = centre[c] + rot[3 * c] * x + rot[3 * c + 1] * y;
        }
        for (int i = 0; i < k; i++) set_add(&t, centre, rim + 3 * i, rim + 3 * ((i + 1) % k));
        packed p = pack(&t, 0);
        for (int ray = 0; ray < 40; ray++) {
            float o[3], target[3];
            random_point(o, 10.0f);
            if (ray % 2 == 0) memcpy(target, centre, sizeof target);
            else {
                const float *e = rim + 3 * (rnd() % k);
                const float w = frand(0, 1);
                for (int c = 0; c < 3; c++) target[c] = centre[c] + w * (e[c] - centre[c]);
            }
            try_toward(&s, "fans", &t, &p, o, target);
        }
        free(rim);
        unpack(&p);
    }
    free(t.tri);
    report("fans", &s);
    CHECK(s.hits > s.cases / 2 && s.ties > 1000);
}

/* Tiny and huge coordinates (products underflow to zero or overflow to
 * infinity), far offsets, and axis-parallel rays at random triangles. */
static void test_scales(void)
{
    tally s = {0};
    tri_set t = {0};
    static const float scales[] = {1e-38f, 1e-30f, 1e-20f, 1e-6f, 1.0f, 1e6f, 1e12f, 1e18f, 1e25f, 1e35f};
    const int ns = (int)(sizeof scales / sizeof scales[0]);
    for (int set = 0; set < 3000; set++) {
        t.n = 0;
        const float sc = scales[set % ns];
        const float far = (set / ns) % 3 == 1 ? 1e4f * sc : 0.0f;
        const uint32_t n = 1 + rnd() % 24;
        for (uint32_t i = 0; i < n; i++) {
            float a[3], b[3], c[3];
            for (int k = 0; k < 3; k++) {
                a[k] = far + sc * frand(-1, 1);
                b[k] = a[k] + sc * frand(-1, 1);
                c[k] = a[k] + sc * frand(-1, 1);
            }
            set_add(&t, a, b, c);
        }
        packed p = pack(&t, 0);
        for (int ray = 0; ray < 16; ray++) {
            float o[3], d[3] = {0, 0, 0}, target[3];
            const float *v = t.tri + 9 * (size_t)(rnd() % n);
            float u = frand(0, 1), w = frand(0, 1);
            if (u + w > 1) u = 1 - u, w = 1 - w;
            for (int k = 0; k < 3; k++)
                target[k] = v[k] + u * (v[3 + k] - v[k]) + w * (v[6 + k] - v[k]);
            if (ray & 1) {
                const int axis = rnd() % 3;
                memcpy(o, target, sizeof o);
                o[axis] = far + 4.0f * sc * ((rnd() & 1) ? 1.0f : -1.0f);
                d[axis] = o[axis] > target[axis] ? -1.0f : 1.0f;
                if (ray & 2) d[axis] *= sc; /* a direction of the scene's scale */
                try_ray(&s, "scales", &t, &p, o, d, 0.0f, INFINITY);
            } else {
                for (int k = 0; k < 3; k++) o[k] = far + 4.0f * sc * frand(-1, 1);
                try_toward(&s, "scales", &t, &p, o, target);
            }
        }
        unpack(&p);
    }
    free(t.tri);
    report("scales", &s);
    CHECK(s.hits > s.cases / 4);
}

/* Rays in a triangle's plane (the grid's own plane), from outside and from
 * inside the grid. */
static void test_in_plane(void)
{
    tally s = {0};
    tri_set t = {0};
    for (int g = 0; g < 30; g++) {
        t.n = 0;
        const int axis = g % 3;
        float rot[9], off[3];
        random_rotation(rot);
        random_point(off, 3.0f);
        add_grid(&t, 3, axis, g < 15 ? 0.0f : 0.5f, g >= 15 ? rot : NULL, off);
        packed p = pack(&t, 0);
        for (int ray = 0; ray < 200; ray++) {
            float o[3], d[3];
            const float *v = t.tri + 9 * (size_t)(rnd() % t.n);
            const float *q = t.tri + 9 * (size_t)(rnd() % t.n) + 3 * (rnd() % 3);
            const float w = frand(-2, 2);
            for (int k = 0; k < 3; k++) {
                o[k] = v[k] + w * (v[3 + k] - v[k]);
                d[k] = q[k] - o[k];
            }
            try_ray(&s, "in plane", &t, &p, o, d, 0.0f, INFINITY);
        }
        unpack(&p);
    }
    free(t.tri);
    report("in plane", &s);
    CHECK(s.cases > 10000);
}

/* Degenerate triangles (coincident or collinear vertices, also sharing
 * vertices with proper ones) among proper triangles: the packer gives them
 * NaN vertices, no path hits them, and the packed answer is that of the
 * plain loop (which refuses them). */
static void test_degenerate(void)
{
    tally s = {0};
    tri_set t = {0};
    long dead_lanes = 0;
    for (int set = 0; set < 2000; set++) {
        t.n = 0;
        const uint32_t n = 2 + rnd() % 30;
        for (uint32_t i = 0; i < n; i++) {
            float a[3], b[3], c[3];
            random_point(a, 1.0f);
            random_point(b, 1.0f);
            switch (rnd() % 4) {
            case 0: memcpy(c, a, sizeof c); break;                  /* coincident */
            case 1:                                                  /* collinear */
                for (int k = 0; k < 3; k++) c[k] = a[k] + 2.0f * (b[k] - a[k]);
                break;
            case 2: /* on a previous triangle's edge */
                if (i > 0) {
                    const float *v = t.tri + 9 * (size_t)(rnd() % i);
                    memcpy(a, v, sizeof a);
                    memcpy(b, v + 3, sizeof b);
                    memcpy(c, v + 3, sizeof c);
                    break;
                }
                /* fall through */
            default: random_point(c, 1.0f); break;
            }
            set_add(&t, a, b, c);
        }
        packed p = pack(&t, 0);
        for (uint32_t i = 0; i < n; i++) {
            const tt_tri_block *b = &p.blocks[i / TT_TRI_BLOCK_W];
            const int lane = (int)(i % TT_TRI_BLOCK_W);
            const float *v = t.tri + 9 * (size_t)p.ids[i];
            const int dead = tt_tri_is_degenerate(v, v + 3, v + 6);
            int nan = 1, same = 1;
            for (int k = 0; k < 9; k++) {
                nan &= isnan(b->v[k][lane]) != 0;
                same &= memcmp(&b->v[k][lane], &v[k], sizeof(float)) == 0;
            }
            dead_lanes += dead;
            CHECK(b->prim[lane] == p.ids[i]);
            CHECK(dead ? nan : same);
        }
        for (int ray = 0; ray < 16; ray++) {
            float o[3], target[3];
            random_point(o, 3.0f);
            const float *v = t.tri + 9 * (size_t)(rnd() % n);
            memcpy(target, v + 3 * (rnd() % 3), sizeof target); /* a vertex */
            if (ray & 1)
                for (int k = 0; k < 3; k++) target[k] = 0.5f * (v[k] + v[3 + k]);
            try_toward(&s, "degenerate", &t, &p, o, target);
        }
        unpack(&p);
    }
    free(t.tri);
    report("degenerate", &s);
    CHECK(dead_lanes > 1000 && s.hits > 1000);
}

/* The packer: n = 0..40 triangles, used lanes copied exactly with their ids,
 * unused lanes NaN with TT_INVALID_ID; and partial blocks (1..7 lanes used)
 * through every path. */
static void test_pack_and_partial(void)
{
    tally s = {0};
    tri_set t = {0};
    CHECK(tt_tri_block_count(0) == 0 && tt_tri_block_count(1) == 1);
    CHECK(tt_tri_block_count(8) == 1 && tt_tri_block_count(9) == 2);
    CHECK(sizeof(tt_tri_block) == 320);
    for (uint32_t n = 0; n <= 40; n++) {
        t.n = 0;
        for (uint32_t i = 0; i < n; i++) {
            float a[3], b[3], c[3];
            random_point(a, 1.0f);
            random_point(b, 1.0f);
            random_point(c, 1.0f);
            set_add(&t, a, b, c);
        }
        packed p = pack(&t, n & 1);
        CHECK(p.nb == (n + 7) / 8);
        for (uint32_t j = 0; j < p.nb; j++)
            for (uint32_t i = 0; i < TT_TRI_BLOCK_W; i++) {
                const uint32_t k = j * TT_TRI_BLOCK_W + i;
                if (k < n) {
                    CHECK(p.blocks[j].prim[i] == p.ids[k]);
                    int same = 1;
                    for (int c = 0; c < 9; c++)
                        same &= p.blocks[j].v[c][i] == t.tri[9 * (size_t)p.ids[k] + c];
                    CHECK(same);
                } else {
                    CHECK(p.blocks[j].prim[i] == TT_INVALID_ID);
                    int nan = 1;
                    for (int c = 0; c < 9; c++) nan &= isnan(p.blocks[j].v[c][i]) != 0;
                    CHECK(nan);
                }
            }
        for (int ray = 0; ray < 2000 && n > 0; ray++) {
            float o[3], target[3];
            random_point(o, 3.0f);
            const float *v = t.tri + 9 * (size_t)(rnd() % n);
            for (int k = 0; k < 3; k++) target[k] = (v[k] + v[3 + k] + v[6 + k]) / 3.0f;
            try_toward(&s, "partial blocks", &t, &p, o, target);
        }
        unpack(&p);
    }
    free(t.tri);
    report("partial blocks", &s);
    CHECK(s.hits > s.cases / 2);
}

/* [tmin, tmax): with t found on an unbounded ray, tmax = t misses and
 * tmin = t hits, on every path, also the neighbouring floats. */
static void test_bounds(void)
{
    tally s = {0};
    tri_set t = {0};
    long boundary = 0;
    for (int set = 0; set < 3000; set++) {
        t.n = 0;
        const uint32_t n = 1 + rnd() % 20;
        for (uint32_t i = 0; i < n; i++) {
            float a[3], b[3], c[3];
            random_point(a, 1.0f);
            random_point(b, 1.0f);
            random_point(c, 1.0f);
            set_add(&t, a, b, c);
        }
        packed p = pack(&t, 0);
        for (int ray = 0; ray < 4; ray++) {
            float o[3], target[3];
            random_point(o, 3.0f);
            const float *v = t.tri + 9 * (size_t)(rnd() % n);
            for (int k = 0; k < 3; k++) target[k] = (v[k] + v[3 + k] + v[6 + k]) / 3.0f;
            const float d[3] = {target[0] - o[0], target[1] - o[1], target[2] - o[2]};
            tt_wray r;
            tt_wray_init(&r, o, d, 0.0f, INFINITY);
            tt_hit h = {INFINITY, 0, 0, TT_INVALID_ID};
            if (!tt_tri_blocks_intersect_scalar(&r, p.blocks, p.nb, &h)) continue;
            const float th = h.t;
            /* t exactly at tmax: that triangle is out (another may be nearer). */
            tt_wray_init(&r, o, d, 0.0f, th);
            tt_hit h2 = {th, 0, 0, TT_INVALID_ID};
            tt_tri_blocks_intersect_scalar(&r, p.blocks, p.nb, &h2);
            CHECK(h2.t < th || h2.prim == TT_INVALID_ID);
            /* t exactly at tmin: hit, at that very t. */
            tt_wray_init(&r, o, d, th, INFINITY);
            tt_hit h3 = {INFINITY, 0, 0, TT_INVALID_ID};
            CHECK(tt_tri_blocks_intersect_scalar(&r, p.blocks, p.nb, &h3) && h3.t == th);
            boundary++;
            const float ts[] = {th, nextafterf(th, 0.0f), nextafterf(th, INFINITY)};
            for (int a = 0; a < 3; a++) {
                try_ray(&s, "bounds", &t, &p, o, d, 0.0f, ts[a]);
                try_ray(&s, "bounds", &t, &p, o, d, ts[a], INFINITY);
                try_ray(&s, "bounds", &t, &p, o, d, ts[a], ts[a]);
            }
        }
        unpack(&p);
    }
    free(t.tri);
    report("bounds", &s);
    CHECK(boundary > 5000);
}

/* Ties: exact copies of a triangle in several lanes and blocks (equal t, u,
 * v); the copy with the smallest triangle id must win on every path (the
 * kernels' tie rule, tri_block.h: no answer depends on lane order), whether the
 * copies share a block, sit in the two blocks of one AVX-512 pair or in
 * different pairs. */
static void test_ties(void)
{
    tally s = {0};
    tri_set t = {0};
    long checked = 0;
    for (int set = 0; set < 3000; set++) {
        t.n = 0;
        const uint32_t n = 2 + rnd() % 40;
        for (uint32_t i = 0; i < n; i++) {
            float a[3], b[3], c[3];
            random_point(a, 1.0f);
            random_point(b, 1.0f);
            random_point(c, 1.0f);
            set_add(&t, a, b, c);
        }
        /* Copies of triangle 0 over other triangles. */
        const int copies = 1 + rnd() % 4;
        for (int k = 0; k < copies; k++) memcpy(t.tri + 9 * (size_t)(1 + rnd() % (n - 1)), t.tri, 9 * sizeof(float));
        packed p = pack(&t, 0);
        uint32_t first = UINT32_MAX;
        for (uint32_t i = 0; i < n; i++)
            if (memcmp(t.tri + 9 * (size_t)p.ids[i], t.tri, 9 * sizeof(float)) == 0 &&
                p.ids[i] < first)
                first = p.ids[i];
        for (int ray = 0; ray < 8; ray++) {
            float o[3], target[3];
            random_point(o, 3.0f);
            float u = frand(0, 1), w = frand(0, 1);
            if (u + w > 1) u = 1 - u, w = 1 - w;
            for (int k = 0; k < 3; k++)
                target[k] = t.tri[k] + u * (t.tri[3 + k] - t.tri[k]) + w * (t.tri[6 + k] - t.tri[k]);
            try_toward(&s, "ties", &t, &p, o, target);
            /* Whenever triangle 0's copies win, the first copy is the answer. */
            const float d[3] = {target[0] - o[0], target[1] - o[1], target[2] - o[2]};
            tt_wray r;
            tt_wray_init(&r, o, d, 0.0f, INFINITY);
            float tc, uc, vc;
            if (!tt_intersect_triangle(&r, t.tri, t.tri + 3, t.tri + 6, INFINITY, &tc, &uc, &vc))
                continue;
            for (int k = 0; k < n_isas; k++) {
                tt_hit h = {INFINITY, 0, 0, TT_INVALID_ID};
                kernels[k].intersect(&r, p.blocks, p.nb, &h);
                if (h.t == tc && memcmp(t.tri + 9 * (size_t)h.prim, t.tri, 9 * sizeof(float)) == 0) {
                    CHECK_MSG(h.prim == first, "%s: tie went to %u, not the smallest id %u",
                              tt_isa_name(isas[k]), h.prim, first);
                    checked++;
                }
            }
        }
        unpack(&p);
    }
    free(t.tri);
    report("ties", &s);
    CHECK(s.ties > 5000 && checked > 5000);
}

int main(void)
{
    for (int i = TT_ISA_FIRST; i <= TT_ISA_LAST; i++)
        if (tt_test_isa_runs((tt_isa)i)) {
            isas[n_isas] = (tt_isa)i;
            kernels[n_isas++] = tt_tri_block_kernels_for((tt_isa)i);
            printf("path: %s\n", tt_isa_name((tt_isa)i));
        }
    test_pack_and_partial();
    test_random();
    test_grids();
    test_fans();
    test_scales();
    test_in_plane();
    test_degenerate();
    test_bounds();
    test_ties();
    return tt_test_finish();
}
