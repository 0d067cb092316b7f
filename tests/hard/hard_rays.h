/* Targeted hard rays for a scene, derived from its own triangles: origins
 * exactly on triangles, vertices and edges; rays along edges and inside
 * triangles' planes (grazing); origins on the planes split candidates come
 * from (every vertex coordinate) with directions lying in those planes;
 * directions with zero, negative-zero, tiny and huge components; intervals
 * that start or end exactly at a hit. The bruteforce answers are what our
 * structures must reproduce, whatever they are for these rays.
 *
 * Embree is held to less (hard_mode in hard_accel.h). It is an external
 * reference with its own triangle test (Pluecker, tolerant by an ulp on the
 * edges, not watertight-identical to ours), so on rays aimed exactly at
 * edges or vertices, grazing rays, rays starting on a surface (hits at
 * t ~ 0) and exact interval ends it may legitimately decide otherwise. It
 * must agree exactly only on the families in general position, named
 * HARD_GENERIC "..." below (from around the box aimed into it; axis-parallel
 * from random points; both kept off the vertices' planes), on the framed
 * views of hard_one_structure and on its random rays where the scene is in
 * general position (hard_scene_generic);
 * on every other family, including the odd-direction families that used to
 * abort libembree, it must return without crashing and give a valid answer
 * (a miss, or a triangle in range with t in [tmin, tmax)). Rays that break
 * the ray contract (negative tmin) must be refused by every structure. */
#ifndef TT_HARD_RAYS_H
#define TT_HARD_RAYS_H

#include "hard_accel.h"

typedef struct hard_geom {
    const tt_scene *scene;
    size_t nt;
    float lo[3], hi[3], centre[3], diag;
} hard_geom;

static inline void hard_geom_init(hard_geom *g, const tt_scene *scene)
{
    g->scene = scene;
    g->nt = tt_scene_triangle_count(scene);
    tt_scene_bounds(scene, g->lo, g->hi);
    if (!(g->lo[0] <= g->hi[0]))
        for (int k = 0; k < 3; k++) g->lo[k] = -1.0f, g->hi[k] = 1.0f;
    float d2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        g->centre[k] = 0.5f * (g->lo[k] + g->hi[k]);
        d2 += (g->hi[k] - g->lo[k]) * (g->hi[k] - g->lo[k]);
    }
    g->diag = d2 > 0.0f ? sqrtf(d2) : 1.0f;
}

/* A random triangle's vertices (a zero triangle when the scene is empty). */
static inline void hard_pick(const hard_geom *g, uint32_t *x, float t[9])
{
    if (g->nt == 0) {
        memset(t, 0, 9 * sizeof(float));
        return;
    }
    tt_scene_triangle(g->scene, hard_next(x) % g->nt, t);
}

static inline void hard_random_dir(uint32_t *x, float d[3])
{
    do {
        for (int k = 0; k < 3; k++) d[k] = hard_sym(x);
    } while (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f);
}

/* A point in the scene box grown by `grow` times its size on each side. */
static inline void hard_random_point(const hard_geom *g, uint32_t *x, float grow, float p[3])
{
    for (int k = 0; k < 3; k++) {
        float e = g->hi[k] - g->lo[k];
        if (e == 0.0f) e = g->diag; /* flat scenes: leave the plane too */
        p[k] = g->centre[k] + e * (0.5f + grow) * hard_sym(x);
    }
}

/* Whether p lies on a plane through a vertex: p[k] equals some vertex's
 * coordinate k, for any axis k whose bit is set in axes. Linear in the
 * triangles: only for the few hundred generic rays. */
static inline int hard_on_vertex_planes(const hard_geom *g, const float p[3], unsigned axes)
{
    float t[9];
    for (size_t i = 0; i < g->nt; i++) {
        tt_scene_triangle(g->scene, i, t);
        for (int j = 0; j < 9; j++)
            if ((axes >> (j % 3) & 1) && t[j] == p[j % 3]) return 1;
    }
    return 0;
}

static inline int hard_is_zero(const float d[3]) { return d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f; }

/* Adds about `per_family` rays of each family. */
static inline void hard_rays_targeted(hard_rays *s, const tt_scene *scene, size_t per_family,
                                      uint32_t seed)
{
    hard_geom g;
    hard_geom_init(&g, scene);
    uint32_t x = seed ? seed : 1, y = x ^ 0x9e3779b9u;
    const float inf = INFINITY;
    float t[9], o[3], d[3];
    for (size_t i = 0; i < per_family; i++) {
        /* origin exactly on a triangle (its float barycentric point), on a
         * vertex and on an edge's midpoint, any direction */
        hard_pick(&g, &x, t);
        float u = hard_unit(&x), v = hard_unit(&x);
        if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
        for (int k = 0; k < 3; k++) o[k] = t[k] + u * (t[3 + k] - t[k]) + v * (t[6 + k] - t[k]);
        hard_random_dir(&x, d);
        hard_rays_add(s, "origin on a triangle", o, d, 0.0f, inf);
        hard_rays_add(s, "origin on a vertex", t + 3 * (hard_next(&x) % 3), d, 0.0f, inf);
        for (int k = 0; k < 3; k++) o[k] = 0.5f * (t[k] + t[3 + k]);
        hard_rays_add(s, "origin on an edge", o, d, 0.0f, inf);

        /* along the normal from a point on the triangle, both ways */
        hard_pick(&g, &x, t);
        float e1[3], e2[3], n[3];
        for (int k = 0; k < 3; k++) e1[k] = t[3 + k] - t[k], e2[k] = t[6 + k] - t[k];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        if (!hard_is_zero(n) && isfinite(n[0] + n[1] + n[2])) {
            for (int k = 0; k < 3; k++) o[k] = (t[k] + t[3 + k] + t[6 + k]) / 3.0f;
            hard_rays_add(s, "normal from a triangle's centroid", o, n, 0.0f, inf);
            float m[3] = {-n[0], -n[1], -n[2]};
            hard_rays_add(s, "normal from a triangle's centroid", o, m, 0.0f, inf);
        }

        /* grazing: along an edge's line (through both its vertices), and
         * inside the triangle's plane through its centroid */
        hard_pick(&g, &x, t);
        int a = (int)(hard_next(&x) % 3), b = (a + 1) % 3;
        for (int k = 0; k < 3; k++) {
            d[k] = t[3 * b + k] - t[3 * a + k];
            o[k] = t[3 * a + k] - 0.5f * d[k];
        }
        if (!hard_is_zero(d)) hard_rays_add(s, "along an edge", o, d, 0.0f, inf);
        float c[3];
        for (int k = 0; k < 3; k++) {
            c[k] = (t[k] + t[3 + k] + t[6 + k]) / 3.0f;
            d[k] = c[k] - t[3 * a + k];
            o[k] = c[k] - 3.0f * d[k];
        }
        if (!hard_is_zero(d)) hard_rays_add(s, "in a triangle's plane", o, d, 0.0f, inf);

        /* aimed exactly at a vertex from outside */
        hard_pick(&g, &x, t);
        hard_random_point(&g, &x, 1.0f, o);
        const float *p = t + 3 * (hard_next(&x) % 3);
        for (int k = 0; k < 3; k++) d[k] = p[k] - o[k];
        if (!hard_is_zero(d)) hard_rays_add(s, "aimed at a vertex", o, d, 0.0f, inf);

        /* origin on split-candidate planes: each coordinate copied from some
         * vertex; the direction has zero components along 0, 1 or 2 of the
         * copied axes, so the ray lies in those planes */
        for (int k = 0; k < 3; k++) {
            hard_pick(&g, &x, t);
            o[k] = t[3 * (hard_next(&x) % 3) + k];
        }
        hard_random_dir(&x, d);
        int zeros = (int)(hard_next(&x) % 3);
        int axis = (int)(hard_next(&x) % 3);
        for (int z = 0; z < zeros; z++) d[(axis + z) % 3] = 0.0f;
        if (hard_is_zero(d)) d[(axis + 2) % 3] = 1.0f;
        hard_rays_add(s, "on split-candidate planes", o, d, 0.0f, inf);

        /* axis-parallel from outside the box through vertex coordinates:
         * along box edges, faces and shared edges of axis-aligned scenes */
        axis = (int)(hard_next(&x) % 3);
        hard_pick(&g, &x, t);
        for (int k = 0; k < 3; k++) o[k] = t[3 * (hard_next(&x) % 3) + k];
        int sign = (hard_next(&x) & 1) ? 1 : -1;
        o[axis] = sign > 0 ? g.lo[axis] - 0.25f * g.diag : g.hi[axis] + 0.25f * g.diag;
        d[0] = d[1] = d[2] = 0.0f;
        d[axis] = (float)sign;
        hard_rays_add(s, "axis-parallel through vertex coordinates", o, d, 0.0f, inf);
        /* ... and the same with a negative zero in the other components
         * (1/-0 is -inf: the slab test must not flip) */
        float nd[3] = {-0.0f, -0.0f, -0.0f};
        nd[axis] = (float)sign;
        hard_rays_add(s, "axis-parallel with -0 components", o, nd, 0.0f, inf);

        /* zero, tiny, denormal and huge direction components from random
         * origins inside and around the box */
        hard_random_point(&g, &x, 0.25f, o);
        hard_random_dir(&x, d);
        static const float odd[6] = {0.0f, -0.0f, 1e-35f, -1e-40f, 1e-20f, 1e30f};
        float q = odd[hard_next(&x) % 6];
        d[hard_next(&x) % 3] = q;
        if (hard_is_zero(d)) d[0] = 1.0f;
        hard_rays_add(s, "odd direction component", o, d, 0.0f, inf);
        float sc = (hard_next(&x) & 1) ? 1e-20f : 1e20f;
        float ds[3] = {d[0] * sc, d[1] * sc, d[2] * sc};
        if (!hard_is_zero(ds) && isfinite(ds[0] + ds[1] + ds[2]))
            hard_rays_add(s, "direction scaled by 1e-20 or 1e20", o, ds, 0.0f, inf);

        /* from far away, aimed at the scene */
        float fd[3];
        hard_random_dir(&x, fd);
        float fl = sqrtf(fd[0] * fd[0] + fd[1] * fd[1] + fd[2] * fd[2]);
        hard_random_point(&g, &x, 0.0f, c);
        for (int k = 0; k < 3; k++) {
            o[k] = c[k] + fd[k] / fl * 1000.0f * g.diag;
            d[k] = c[k] - o[k];
        }
        if (!hard_is_zero(d)) hard_rays_add(s, "from far away", o, d, 0.0f, inf);

        /* from 1e37 away with a short direction: org * rcp overflows on
         * every axis (the FMA box tests' offsets; such a ray once followed
         * an unused child's reference in the R-tree's AVX2 kernel) */
        for (int k = 0; k < 3; k++) {
            o[k] = c[k] + fd[k] / fl * 1e37f;
            d[k] = -fd[k] / fl * 1e-2f;
        }
        if (!hard_is_zero(d)) hard_rays_add(s, "from 1e37 away, direction of length 0.01", o, d, 0.0f, inf);

        /* The families in general position (what an external reference is
         * held to exactly). Their own random sequence, so the families above
         * keep their rays. Random points are tested against the vertices'
         * coordinates: on a scene far from the origin (coarse float grid) a
         * random coordinate often equals one, which puts an axis-parallel
         * ray in a box face's plane or aims a ray exactly at a vertex. */
        /* from around the box, aimed at a point in it */
        hard_random_point(&g, &y, 0.5f, o);
        hard_random_point(&g, &y, 0.0f, c);
        for (int k = 0; k < 3; k++) d[k] = c[k] - o[k];
        if (!hard_is_zero(d) && !hard_on_vertex_planes(&g, c, 0x7))
            hard_rays_add(s, HARD_GENERIC "from around the box, aimed into it", o, d, 0.0f, inf);
        /* axis-parallel from random points outside the box: away from
         * edges and vertices, unlike the axis-parallel families above */
        axis = (int)(hard_next(&y) % 3);
        sign = (hard_next(&y) & 1) ? 1 : -1;
        hard_random_point(&g, &y, 0.0f, o);
        o[axis] = sign > 0 ? g.lo[axis] - 0.25f * g.diag : g.hi[axis] + 0.25f * g.diag;
        d[0] = d[1] = d[2] = 0.0f;
        d[axis] = (float)sign;
        if (!hard_on_vertex_planes(&g, o, 0x7 & ~(1 << axis)))
            hard_rays_add(s, HARD_GENERIC "axis-parallel from a random point", o, d, 0.0f, inf);
    }
}

/* Rays whose interval starts or ends exactly where bruteforce hits: the
 * half-open [tmin, tmax) must be honoured at both ends by every structure,
 * also when tmin == tmax or tmin > tmax (empty intervals). A negative tmin
 * (-inf too) breaks the ray contract (treetrace.h: rays start at their
 * origin): those rays are kept, and every structure must refuse them with
 * TT_ERR_INVALID_ARGUMENT (hard_ray_check). Built from the hits of `base`
 * (already traced); diag is the scene's size (hard_geom.diag). */
static inline void hard_rays_intervals(hard_rays *s, const hard_rays *base, float diag, size_t max)
{
    size_t added = 0;
    for (size_t i = 0; i < base->n && added < max; i++) {
        const tt_hit *h = &base->hit[i];
        const tt_ray *r = &base->ray[i];
        if (h->prim == TT_INVALID_ID || !(h->t > 0.0f)) continue;
        /* Only hits at a real distance: a ray starting on a surface "hits"
         * it at a t that is rounding noise (1e-8 for a unit scene, exactly 0
         * in real arithmetic), and no box test can bound that noise without
         * knowing the triangle test's error; such rays are in the targeted
         * families with tmin = 0, where every answer must agree. */
        float len = sqrtf(r->dir[0] * r->dir[0] + r->dir[1] * r->dir[1] + r->dir[2] * r->dir[2]);
        if (!(h->t * len > 1e-3f * diag)) continue;
        hard_rays_add(s, "tmax exactly at the hit", r->org, r->dir, 0.0f, h->t);
        hard_rays_add(s, "tmin exactly at the hit", r->org, r->dir, h->t, INFINITY);
        hard_rays_add(s, "tmin == tmax == the hit", r->org, r->dir, h->t, h->t);
        hard_rays_add(s, "tmin > tmax", r->org, r->dir, h->t, 0.5f * h->t);
        hard_rays_add(s, "tmin just past the hit", r->org, r->dir, nextafterf(h->t, INFINITY), INFINITY);
        /* the ray reversed, starting past the hit, looking behind its
         * origin: refused by the contract, as is tmin = -inf */
        float back[3] = {-r->dir[0], -r->dir[1], -r->dir[2]};
        float o[3];
        for (int k = 0; k < 3; k++) o[k] = r->org[k] + 2.0f * h->t * r->dir[k];
        hard_rays_add(s, "negative tmin (refused: ray contract)", o, back, -4.0f * h->t, INFINITY);
        hard_rays_add(s, "tmin = -inf (refused: ray contract)", r->org, r->dir, -INFINITY, INFINITY);
        added++;
    }
}

#endif
