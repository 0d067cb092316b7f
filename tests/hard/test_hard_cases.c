/* Minimal reproductions of disagreements and crashes the hard tests found
 * in the structures, kept as one ray each so that they are easy to debug
 * and can never silently come back. Every case is traced by every
 * registered structure in every variant (hard_accel.h) and compared with
 * bruteforce (Embree, an external reference, only where a case says so;
 * elsewhere it must give a valid answer). Each structure runs in a child process, so that a crash is
 * reported as one (with the case) and the other cases still run. */
#include <math.h>
#include <sys/wait.h>
#include <unistd.h>

#include "hard_accel.h"

typedef struct hard_case {
    const char *name;
    void (*scene)(hard_mesh *m);
    tt_ray ray;
    /* Whether an external reference (Embree) must agree exactly too. Only
     * for rays in general position: Embree's own triangle test is not held
     * to our answers on rays aimed at edges and vertices (hard_rays.h); on
     * the other cases it must just return a valid answer. */
    int external_exact;
    /* The pinned answer, so that bruteforce itself is held to something
     * from outside the library: the triangle (TT_INVALID_ID for a miss)
     * and t's exact bits (written %.9g, which reads back exactly), or
     * refused = 1 for a ray the contract refuses. Checked by hand: rays
     * aimed at a vertex as org + dir hit at t = 1 (the cube corner one ulp
     * short: org + dir rounds past it), the grid ray from x = 9.5 meets the
     * cubes' face x = 7 at 2.5, the tilted triangle's vertex c lies 1.3507
     * along -x, and the 7e19 ray passes beside the triangle. */
    uint32_t prim;
    float t;
    int refused;
} hard_case;

static void single_unit(hard_mesh *m)
{
    static const float a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    m->name = "single triangle (0,0,0) (1,0,0) (0,1,0)";
    hard_triangle(m, a, b, c);
}

static void single_tilted(hard_mesh *m) { hard_gen_identical(m, 1); }
static void cubes(hard_mesh *m) { hard_gen_cubes(m, 4); }
static void coplanar_y(hard_mesh *m) { hard_gen_coplanar(m, 1, 8, 100, 99u); }
static void soup(hard_mesh *m) { hard_gen_soup(m, "soup", 600, 0.1f, 98u); }

static const hard_case cases[] = {
    /* kdtree sltr/seq: a ray aimed exactly at a vertex on the root cell's
     * corner is missed */
    {"aimed exactly at vertex (0,0,0)", single_unit,
     {{0.445451379f, 0.140150547f, 1.96029592f}, 0.0f, {-0.445451379f, -0.140150547f, -1.96029592f}, INFINITY}, 0, 0u, 1.0f, 0},
    {"aimed exactly at a cube corner", cubes,
     {{0.962139368f, 3.09453249f, -1.25380087f}, 0.0f, {6.03786087f, -0.0945324898f, 5.25380087f}, INFINITY}, 0, 432u, 0.999999881f, 0},
    /* rtree (and geometry/aabb.h's tt_ray_box): a ray with a zero direction
     * component lying in the plane of a box face is culled: (hi - org) *
     * 1e30 = 0 makes the slab [-1e30, 0] */
    {"axis-parallel, in the box's top face plane, through vertex c", single_tilted,
     {{1.7506938f, 1.10000002f, -0.200000003f}, 0.0f, {-1.0f, 0.0f, 0.0f}, INFINITY}, 0, 0u, 1.35069382f, 0},
    {"axis-parallel along cube faces (grid ray)", cubes,
     {{9.5f, 0.0f, 1.0f}, 0.0f, {-1.0f, 0.0f, 0.0f}, INFINITY}, 0, 394u, 2.5f, 0},
    /* kdtree sltr/seq: the same at a vertex of a flat scene, with the hit
     * exactly at tmin, and past a nearer hit */
    {"vertex hit exactly at tmin in a flat scene", coplanar_y,
     {{0.723845243f, 6.9951725f, -1.53833556f}, 1.0f, {-0.223845243f, -6.4951725f, 2.03833556f}, INFINITY}, 0, 74u, 1.0f, 0},
    {"vertex hit past a nearer hit (tmin after it)", soup,
     {{0.158875614f, -0.110523582f, 1.12881899f}, 0.63800776f, {0.418489546f, 0.538118958f, -0.4319942f}, INFINITY}, 0, 292u, 1.0f, 0},
    /* embree: libembree asserts ray.valid() (components below 1.8e19) and
     * aborts the process; both rays are in general position, so Embree must
     * give bruteforce's answer */
    {"direction components of 7e19", single_tilted,
     {{0.67672205f, -0.0608524084f, 0.392681003f}, 0.0f, {7.39144933e+19f, -0.0f, -3.94822619e+19f}, INFINITY}, 1, TT_INVALID_ID, INFINITY, 0},
    {"a tiny direction (1e-40, 6.3e-21, 6.5e-22)", coplanar_y,
     {{1.93726909f, -2.96994305f, 1.13657498f}, 0.0f, {9.9999461e-41f, 6.32239305e-21f, 6.54464957e-22f}, INFINITY}, 1, 110u, 5.48833843e+20f, 0},
    /* the ray it was found with had tmin = -inf, which the ray contract now
     * refuses (every structure must) */
    {"tmin = -inf with a tiny direction (refused)", coplanar_y,
     {{1.93726909f, -2.96994305f, 1.13657498f}, -INFINITY, {9.9999461e-41f, 6.32239305e-21f, 6.54464957e-22f}, INFINITY}, 1, TT_INVALID_ID, 0.0f, 1},
};

#define NCASES (sizeof cases / sizeof cases[0])

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Bruteforce on each case against the pinned answer. */
static void check_pinned(const hard_case *c)
{
    tt_context *ctx = tt_test_context();
    hard_mesh m = {0};
    c->scene(&m);
    tt_scene *scene = hard_scene(ctx, &m);
    tt_accel *bf = tt_test_build_default(ctx, scene, "bruteforce");
    tt_hit h = {0};
    tt_status st = tt_intersect1(bf, &c->ray, &h);
    if (c->refused) {
        CHECK_MSG(st == TT_ERR_INVALID_ARGUMENT, "case \"%s\": bruteforce did not refuse it (%s)",
                  c->name, tt_strerror(st));
    } else {
        CHECK_MSG(st == TT_OK && h.prim == c->prim && (c->prim == TT_INVALID_ID || same_bits(h.t, c->t)),
                  "case \"%s\": bruteforce gives prim %u t %.9g, pinned prim %u t %.9g (%s)",
                  c->name, h.prim, h.t, c->prim, c->t, tt_strerror(st));
    }
    tt_accel_destroy(bf);
    tt_scene_destroy(scene);
    hard_mesh_free(&m);
    tt_context_destroy(ctx);
}

/* In the child: every variant of `name` on the case; exit status = the
 * number of variants that disagree (capped). */
static int run_structure(const hard_case *c, const char *name)
{
    tt_context *ctx = tt_test_context();
    hard_mesh m = {0};
    c->scene(&m);
    tt_scene *scene = hard_scene(ctx, &m);
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "bruteforce";
    tt_accel *ref = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &bo, &ref));
    hard_rays rays = {0};
    hard_rays_add(&rays, c->name, c->ray.org, c->ray.dir, c->ray.tmin, c->ray.tmax);
    hard_rays_reference(&rays, ref);
    static hard_variant v[HARD_MAX_VARIANTS];
    size_t nv = hard_variants(name, v);
    const hard_mode mode =
        hard_is_external_reference(name) && !c->external_exact ? HARD_EXTERNAL : HARD_EXACT;
    int bad = 0;
    for (size_t i = 0; i < nv; i++) {
        tt_accel *acc = NULL;
        if (tt_accel_build(ctx, scene, &v[i].opt, &acc) != TT_OK) {
            fprintf(stderr, "%s: build failed: %s\n", v[i].label, tt_context_last_error(ctx));
            bad++;
            continue;
        }
        if (hard_compare(m.name, v[i].label, acc, &rays, tt_scene_triangle_count(scene), mode)) bad++;
        tt_accel_destroy(acc);
    }
    hard_rays_free(&rays);
    tt_accel_destroy(ref);
    tt_scene_destroy(scene);
    hard_mesh_free(&m);
    tt_context_destroy(ctx);
    return bad > 100 ? 100 : bad;
}

int main(void)
{
    for (size_t k = 0; k < NCASES; k++) check_pinned(&cases[k]);
    for (size_t k = 0; k < NCASES; k++) {
        for (const char *const *name = tt_accel_names(); *name; name++) {
            fflush(stdout);
            fflush(stderr);
            pid_t pid = fork();
            if (pid < 0) {
                perror("fork");
                return 1;
            }
            if (pid == 0) _exit(run_structure(&cases[k], *name));
            int status = 0;
            waitpid(pid, &status, 0);
            if (WIFSIGNALED(status)) {
                CHECK_MSG(0, "case \"%s\": %s crashed (signal %d)", cases[k].name, *name,
                          WTERMSIG(status));
            } else {
                int bad = WEXITSTATUS(status);
                CHECK_MSG(bad == 0, "case \"%s\": %d %s variant(s) %s", cases[k].name, bad,
                          *name,
                          hard_is_external_reference(*name) && !cases[k].external_exact
                              ? "gave an invalid answer (external reference)"
                              : "disagree with bruteforce");
            }
        }
    }
    int structures = 0;
    for (const char *const *name = tt_accel_names(); *name; name++) structures++;
    printf("%zu cases x %d structures\n", NCASES, structures);
    return tt_test_finish();
}
