/* Watertightness: rays aimed exactly at shared edges and vertices of closed
 * meshes, from many origins outside, must never slip through. Meshes: a
 * subdivided cube on an integer grid (edge points exactly representable,
 * axis-parallel rays along face grids), an icosphere (vertices at irrational
 * positions) and, when the shared scenes are present, the 948-triangle bunny
 * (not convex, so only edges whose two triangles cover both sides of the
 * edge as seen from the origin are used). Traced through bruteforce, the
 * reference, and every other structure of this build. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"

typedef struct mesh {
    float *v;
    uint32_t nv;
    uint32_t *idx;
    uint32_t nt;
    int convex; /* and centred on the origin */
} mesh;

static uint32_t add_vertex(mesh *m, float x, float y, float z)
{
    m->v = realloc(m->v, (m->nv + 1) * 3 * sizeof(float));
    m->v[3 * m->nv] = x;
    m->v[3 * m->nv + 1] = y;
    m->v[3 * m->nv + 2] = z;
    return m->nv++;
}

static void add_tri(mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    m->idx = realloc(m->idx, (m->nt + 1) * 3 * sizeof(uint32_t));
    m->idx[3 * m->nt] = a;
    m->idx[3 * m->nt + 1] = b;
    m->idx[3 * m->nt + 2] = c;
    m->nt++;
}

/* A cube [-N/2, N/2]^3 with each face an N x N grid of squares, split into
 * two triangles along alternating diagonals (so vertices have different
 * valences); grid vertices are shared between faces. */
static mesh make_cube(int n)
{
    mesh m = {0};
    m.convex = 1;
    int side = n + 1;
    uint32_t *id = malloc((size_t)side * side * side * sizeof *id);
    for (int i = 0; i < side * side * side; i++) id[i] = UINT32_MAX;
    for (int axis = 0; axis < 3; axis++) {
        for (int s = 0; s <= n; s += n) {
            for (int i = 0; i < n; i++) {
                for (int j = 0; j < n; j++) {
                    uint32_t q[4];
                    for (int k = 0; k < 4; k++) {
                        int c[3];
                        c[axis] = s;
                        c[(axis + 1) % 3] = i + (k == 1 || k == 2);
                        c[(axis + 2) % 3] = j + (k >= 2);
                        int key = (c[0] * side + c[1]) * side + c[2];
                        if (id[key] == UINT32_MAX)
                            id[key] = add_vertex(&m, (float)c[0] - n / 2.0f, (float)c[1] - n / 2.0f,
                                                 (float)c[2] - n / 2.0f);
                        q[k] = id[key];
                    }
                    if ((i + j) & 1) {
                        add_tri(&m, q[0], q[1], q[2]);
                        add_tri(&m, q[0], q[2], q[3]);
                    } else {
                        add_tri(&m, q[0], q[1], q[3]);
                        add_tri(&m, q[1], q[2], q[3]);
                    }
                }
            }
        }
    }
    free(id);
    return m;
}

/* An icosahedron subdivided `level` times, vertices pushed onto the unit
 * sphere; midpoints are shared through a table indexed by vertex pair. */
static mesh make_icosphere(int level)
{
    mesh m = {0};
    m.convex = 1;
    const float g = 1.6180339887f;
    const float base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                               {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                               {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    const uint32_t faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int i = 0; i < 12; i++) {
        float l = sqrtf(base[i][0] * base[i][0] + base[i][1] * base[i][1] + base[i][2] * base[i][2]);
        add_vertex(&m, base[i][0] / l, base[i][1] / l, base[i][2] / l);
    }
    for (int i = 0; i < 20; i++) add_tri(&m, faces[i][0], faces[i][1], faces[i][2]);
    for (int l = 0; l < level; l++) {
        uint32_t nv = m.nv, nt = m.nt;
        uint32_t *old = m.idx;
        uint32_t *mid = malloc((size_t)nv * nv * sizeof *mid);
        for (size_t i = 0; i < (size_t)nv * nv; i++) mid[i] = UINT32_MAX;
        m.idx = NULL;
        m.nt = 0;
        for (uint32_t t = 0; t < nt; t++) {
            uint32_t c[3], e[3];
            for (int k = 0; k < 3; k++) c[k] = old[3 * t + k];
            for (int k = 0; k < 3; k++) {
                uint32_t a = c[k], b = c[(k + 1) % 3];
                size_t key = (size_t)(a < b ? a : b) * nv + (a < b ? b : a);
                if (mid[key] == UINT32_MAX) {
                    float p[3];
                    for (int q = 0; q < 3; q++) p[q] = 0.5f * (m.v[3 * a + q] + m.v[3 * b + q]);
                    float len = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                    mid[key] = add_vertex(&m, p[0] / len, p[1] / len, p[2] / len);
                }
                e[k] = mid[key];
            }
            add_tri(&m, c[0], e[0], e[2]);
            add_tri(&m, c[1], e[1], e[0]);
            add_tri(&m, c[2], e[2], e[1]);
            add_tri(&m, e[0], e[1], e[2]);
        }
        free(mid);
        free(old);
    }
    return m;
}

/* Edges with their triangles: sorted (lo, hi, tri) records. */
typedef struct edge_rec {
    uint32_t lo, hi, tri;
} edge_rec;

static int cmp_edge(const void *a, const void *b)
{
    const edge_rec *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return (x->tri > y->tri) - (x->tri < y->tri);
}

static edge_rec *edges_of(const mesh *m)
{
    edge_rec *e = malloc((size_t)m->nt * 3 * sizeof *e);
    for (uint32_t t = 0; t < m->nt; t++) {
        for (int k = 0; k < 3; k++) {
            uint32_t a = m->idx[3 * t + k], b = m->idx[3 * t + (k + 1) % 3];
            e[3 * t + k].lo = a < b ? a : b;
            e[3 * t + k].hi = a < b ? b : a;
            e[3 * t + k].tri = t;
        }
    }
    qsort(e, (size_t)m->nt * 3, sizeof *e, cmp_edge);
    return e;
}

static const float *vert(const mesh *m, uint32_t i) { return m->v + 3 * (size_t)i; }

static void sub(const float *a, const float *b, double *o)
{
    for (int k = 0; k < 3; k++) o[k] = (double)a[k] - (double)b[k];
}

static double det3(const double *a, const double *b, const double *c)
{
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
}

static double len3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* For a convex mesh centred at the origin: whether o sees triangle t's outer
 * side clearly (not grazing). */
static int faces_origin(const mesh *m, uint32_t t, const float *o)
{
    const float *a = vert(m, m->idx[3 * t]), *b = vert(m, m->idx[3 * t + 1]),
                *c = vert(m, m->idx[3 * t + 2]);
    double ab[3], ac[3], ao[3], n[3];
    sub(b, a, ab);
    sub(c, a, ac);
    sub(o, a, ao);
    n[0] = ab[1] * ac[2] - ab[2] * ac[1];
    n[1] = ab[2] * ac[0] - ab[0] * ac[2];
    n[2] = ab[0] * ac[1] - ab[1] * ac[0];
    double out = n[0] * a[0] + n[1] * a[1] + n[2] * a[2]; /* outward if > 0 */
    double side = n[0] * ao[0] + n[1] * ao[1] + n[2] * ao[2];
    if (out < 0) side = -side;
    double ln = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double lo = sqrt(ao[0] * ao[0] + ao[1] * ao[1] + ao[2] * ao[2]);
    return side > 1e-3 * ln * lo;
}

/* The third vertex of triangle t opposite edge (lo, hi). */
static const float *apex(const mesh *m, uint32_t t, uint32_t lo, uint32_t hi)
{
    for (int k = 0; k < 3; k++) {
        uint32_t i = m->idx[3 * t + k];
        if (i != lo && i != hi) return vert(m, i);
    }
    return NULL;
}

typedef struct tracer {
    const tt_accel *const *accels;
    int count;
    size_t rays, leaks, wrong;
} tracer;

/* Traces o -> p with every structure: it must hit, no farther than p, and
 * for a convex mesh at p on one of the triangles `allowed`. */
static void shoot(tracer *tr, const mesh *m, const float *o, const float *p,
                  const uint32_t *allowed, int n_allowed)
{
    tt_ray r;
    double d[3];
    sub(p, o, d);
    double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) {
        r.org[k] = o[k];
        r.dir[k] = (float)(d[k] / dist);
    }
    r.tmin = 0.0f;
    r.tmax = INFINITY;
    tr->rays++;
    for (int a = 0; a < tr->count; a++) {
        tt_hit h;
        if (tt_intersect1(tr->accels[a], &r, &h) != TT_OK || h.prim == TT_INVALID_ID) {
            if (tr->leaks++ < 5)
                fprintf(stderr, "%s: leak: org %.9g %.9g %.9g towards %.9g %.9g %.9g\n",
                        tt_accel_name(tr->accels[a]), o[0], o[1], o[2], p[0], p[1], p[2]);
            continue;
        }
        int ok = h.t <= dist * (1.0 + 1e-4);
        if (m->convex) {
            int on = 0;
            for (int i = 0; i < n_allowed; i++) on |= h.prim == allowed[i];
            ok = ok && on && fabs(h.t - dist) <= 1e-4 * dist;
        }
        if (!ok && tr->wrong++ < 5)
            fprintf(stderr, "%s: wrong hit: prim %u t %.9g, target at %.9g\n",
                    tt_accel_name(tr->accels[a]), h.prim, h.t, dist);
    }
}

/* Origins on a sphere around the mesh (Fibonacci spiral), plus for the cube
 * the axis-parallel rays straight onto each face grid. */
static void origins_on_sphere(float *o, int n, float radius)
{
    for (int i = 0; i < n; i++) {
        float z = 1.0f - 2.0f * ((float)i + 0.5f) / (float)n;
        float r = sqrtf(1.0f - z * z), phi = 2.39996323f * (float)i;
        o[3 * i] = radius * r * cosf(phi);
        o[3 * i + 1] = radius * r * sinf(phi);
        o[3 * i + 2] = radius * z;
    }
}

static void trace_mesh(tracer *tr, const mesh *m, int n_origins, float radius, const float *centre)
{
    float *origins = malloc((size_t)n_origins * 3 * sizeof *origins);
    origins_on_sphere(origins, n_origins, radius);
    for (int i = 0; i < n_origins; i++)
        for (int k = 0; k < 3; k++) origins[3 * i + k] += centre[k];
    edge_rec *e = edges_of(m);
    size_t ne = (size_t)m->nt * 3;
    static const float fractions[] = {0.5f, 0.25f, 0.8f};
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && e[j].lo == e[i].lo && e[j].hi == e[i].hi) j++;
        if (j - i == 2) { /* a manifold edge */
            const float *a = vert(m, e[i].lo), *b = vert(m, e[i].hi);
            uint32_t tris[2] = {e[i].tri, e[i + 1].tri};
            for (int oi = 0; oi < n_origins; oi++) {
                const float *o = origins + 3 * oi;
                int usable;
                if (m->convex) {
                    usable = faces_origin(m, tris[0], o) && faces_origin(m, tris[1], o);
                } else {
                    double oa[3], ob[3], oc1[3], oc2[3];
                    sub(a, o, oa);
                    sub(b, o, ob);
                    sub(apex(m, tris[0], e[i].lo, e[i].hi), o, oc1);
                    sub(apex(m, tris[1], e[i].lo, e[i].hi), o, oc2);
                    /* the determinants normalized by the lengths: the sine
                     * of each apex's angle off the plane (o, a, b), kept
                     * clear of zero so that the rounded direction still
                     * passes between the two triangles, not beside a
                     * triangle seen edge-on */
                    double s1 = det3(oa, ob, oc1) / (len3(oa) * len3(ob) * len3(oc1));
                    double s2 = det3(oa, ob, oc2) / (len3(oa) * len3(ob) * len3(oc2));
                    const double margin = 1e-5;
                    usable = (s1 > margin && s2 < -margin) || (s1 < -margin && s2 > margin);
                }
                if (!usable) continue;
                for (size_t f = 0; f < sizeof fractions / sizeof fractions[0]; f++) {
                    float p[3];
                    for (int k = 0; k < 3; k++) p[k] = a[k] + fractions[f] * (b[k] - a[k]);
                    shoot(tr, m, o, p, tris, 2);
                }
            }
        }
        i = j;
    }
    if (m->convex) { /* vertices: every triangle around one must face the origin */
        uint32_t *around = malloc(m->nt * sizeof *around);
        for (uint32_t vi = 0; vi < m->nv; vi++) {
            int n = 0;
            for (uint32_t t = 0; t < m->nt; t++)
                if (m->idx[3 * t] == vi || m->idx[3 * t + 1] == vi || m->idx[3 * t + 2] == vi)
                    around[n++] = t;
            for (int oi = 0; oi < n_origins; oi++) {
                int usable = n > 0;
                for (int k = 0; k < n && usable; k++) usable = faces_origin(m, around[k], origins + 3 * oi);
                if (usable) shoot(tr, m, origins + 3 * oi, vert(m, vi), around, n);
            }
        }
        free(around);
    }
    free(e);
    free(origins);
}

/* Axis-parallel rays onto the cube's face grids: exactly along grid lines
 * seen end-on, through vertices and edge midpoints. */
static void trace_cube_axis_rays(tracer *tr, const mesh *m, int n)
{
    float h = n / 2.0f;
    for (int axis = 0; axis < 3; axis++) {
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            for (int i = 0; i <= 2 * n; i++) {
                for (int j = 0; j <= 2 * n; j++) {
                    float p[3], o[3];
                    p[axis] = (float)sgn * h;
                    p[(axis + 1) % 3] = -h + 0.5f * (float)i;
                    p[(axis + 2) % 3] = -h + 0.5f * (float)j;
                    /* the face's border belongs to two faces; skip it here */
                    if (i == 0 || j == 0 || i == 2 * n || j == 2 * n) continue;
                    memcpy(o, p, sizeof o);
                    o[axis] = (float)sgn * (h + 5.0f);
                    /* every triangle of this face containing p is allowed */
                    uint32_t allowed[8];
                    int na = 0;
                    for (uint32_t t = 0; t < m->nt && na < 8; t++) {
                        const float *a = vert(m, m->idx[3 * t]);
                        const float *b = vert(m, m->idx[3 * t + 1]);
                        const float *c = vert(m, m->idx[3 * t + 2]);
                        if (a[axis] != p[axis] || b[axis] != p[axis] || c[axis] != p[axis]) continue;
                        float lo0 = fminf(a[(axis + 1) % 3], fminf(b[(axis + 1) % 3], c[(axis + 1) % 3]));
                        float hi0 = fmaxf(a[(axis + 1) % 3], fmaxf(b[(axis + 1) % 3], c[(axis + 1) % 3]));
                        float lo1 = fminf(a[(axis + 2) % 3], fminf(b[(axis + 2) % 3], c[(axis + 2) % 3]));
                        float hi1 = fmaxf(a[(axis + 2) % 3], fmaxf(b[(axis + 2) % 3], c[(axis + 2) % 3]));
                        if (p[(axis + 1) % 3] >= lo0 && p[(axis + 1) % 3] <= hi0 &&
                            p[(axis + 2) % 3] >= lo1 && p[(axis + 2) % 3] <= hi1)
                            allowed[na++] = t;
                    }
                    shoot(tr, m, o, p, allowed, na);
                }
            }
        }
    }
}

static void build_all(tt_context *ctx, const tt_scene *scene, tt_accel **accels, int *count)
{
    *count = 0;
    for (const char *const *n = tt_accel_names(); *n && *count < 8; n++) {
        tt_build_options opt;
        tt_build_options_default(&opt);
        opt.accel = *n;
        if (strcmp(*n, "bruteforce") != 0 && strcmp(*n, "rtree") != 0 && strcmp(*n, "kdtree") != 0)
            continue; /* optional back ends are checked by their own tests */
        REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &opt, &accels[*count]));
        (*count)++;
    }
}

static void run(tt_context *ctx, const char *name, mesh *m, int n_origins, float radius,
                const float *centre, int cube_n, size_t min_rays)
{
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, m->v, m->nv, m->idx, m->nt, &scene));
    tt_accel *accels[8];
    int count;
    build_all(ctx, scene, accels, &count);
    tracer tr = {(const tt_accel *const *)accels, count, 0, 0, 0};
    trace_mesh(&tr, m, n_origins, radius, centre);
    if (cube_n) trace_cube_axis_rays(&tr, m, cube_n);
    printf("%s: %u triangles, %zu rays x %d structures, %zu leaks, %zu wrong hits\n", name, m->nt,
           tr.rays, count, tr.leaks, tr.wrong);
    CHECK_MSG(tr.rays >= min_rays, "%s: only %zu rays were usable", name, tr.rays);
    CHECK_MSG(tr.leaks == 0, "%s: %zu rays slipped through", name, tr.leaks);
    CHECK_MSG(tr.wrong == 0, "%s: %zu rays hit the wrong place", name, tr.wrong);
    for (int a = 0; a < count; a++) tt_accel_destroy(accels[a]);
    tt_scene_destroy(scene);
}

/* The closed mesh check itself: every edge of the generated meshes has
 * exactly two triangles (else the test would prove nothing). */
static int is_closed(const mesh *m)
{
    edge_rec *e = edges_of(m);
    size_t ne = (size_t)m->nt * 3;
    int closed = 1;
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && e[j].lo == e[i].lo && e[j].hi == e[i].hi) j++;
        closed &= j - i == 2;
        i = j;
    }
    free(e);
    return closed;
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    const float origin[3] = {0, 0, 0};

    mesh cube = make_cube(4);
    CHECK(cube.nt == 6 * 16 * 2);
    CHECK(is_closed(&cube));
    run(ctx, "cube", &cube, 64, 12.0f, origin, 4, 20000);
    free(cube.v);
    free(cube.idx);

    mesh sphere = make_icosphere(2);
    CHECK(sphere.nt == 320 && sphere.nv == 162);
    CHECK(is_closed(&sphere));
    run(ctx, "icosphere", &sphere, 64, 4.0f, origin, 0, 20000);
    free(sphere.v);
    free(sphere.idx);

    char path[4096];
    snprintf(path, sizeof path, "%s/bun_zipper_res4.ply", TT_SCENES_DIR);
    if (access(path, R_OK) == 0) {
        tt_scene *s = tt_test_load_scene(ctx, "bun_zipper_res4.ply");
        mesh bunny = {0};
        bunny.nv = (uint32_t)tt_scene_vertex_count(s);
        bunny.nt = (uint32_t)tt_scene_triangle_count(s);
        bunny.v = malloc((size_t)bunny.nv * 3 * sizeof(float));
        bunny.idx = malloc((size_t)bunny.nt * 3 * sizeof(uint32_t));
        /* rebuild the indexed mesh from the scene's triangles: vertices are
         * matched by position, so shared edges are found whatever the file's
         * vertex order */
        uint32_t nv = 0;
        for (uint32_t t = 0; t < bunny.nt; t++) {
            float tri[9];
            tt_scene_triangle(s, t, tri);
            for (int k = 0; k < 3; k++) {
                uint32_t found = UINT32_MAX;
                for (uint32_t i = 0; i < nv && found == UINT32_MAX; i++)
                    if (memcmp(bunny.v + 3 * i, tri + 3 * k, 3 * sizeof(float)) == 0) found = i;
                if (found == UINT32_MAX) {
                    memcpy(bunny.v + 3 * nv, tri + 3 * k, 3 * sizeof(float));
                    found = nv++;
                }
                bunny.idx[3 * t + k] = found;
            }
        }
        bunny.nv = nv;
        float lo[3], hi[3], centre[3];
        tt_scene_bounds(s, lo, hi);
        for (int k = 0; k < 3; k++) centre[k] = 0.5f * (lo[k] + hi[k]);
        float radius = 3.0f * sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                    (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                    (hi[2] - lo[2]) * (hi[2] - lo[2]));
        run(ctx, "bunny_res4", &bunny, 24, radius, centre, 0, 20000);
        free(bunny.v);
        free(bunny.idx);
        tt_scene_destroy(s);
    } else {
        printf("bunny_res4 skipped: %s is not present\n", path);
    }
    tt_context_destroy(ctx);
    return tt_test_finish();
}
