/* Camera and shadow rays against values computed by hand from the formulas
 * of ../shared/scenes/README.md (in double precision, independently of the
 * library's float code), and the cameras tt_camera_ray must refuse. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "render/camera.h" /* tt_camera_problem */

#define PI 3.14159265358979323846

static int near(double a, double b, double tol) { return fabs(a - b) <= tol * fmax(1.0, fabs(b)); }

static int dir_is(const tt_ray *r, double x, double y, double z)
{
    double l = sqrt(x * x + y * y + z * z);
    return near(r->dir[0], x / l, 1e-6) && near(r->dir[1], y / l, 1e-6) &&
           near(r->dir[2], z / l, 1e-6);
}

/* eye at the origin looking down -z, fov 90 (h = 1), a 4x2 image (a = 2):
 * the numbers below are worked out on paper. */
static void test_axis_camera(void)
{
    tt_camera c;
    memset(&c, 0, sizeof c);
    c.look[2] = -1.0f;
    c.up[1] = 1.0f;
    c.fov_deg = 90.0f;
    tt_ray r;
    /* pixel (0,0): u = (2*0.5/4 - 1) * 1 * 2 = -1.5, v = 1 - 2*0.5/2 = 0.5 */
    CHECK(tt_camera_ray(&c, 4, 2, 0, 0, &r) == TT_OK);
    CHECK(dir_is(&r, -1.5, 0.5, -1.0));
    CHECK(r.org[0] == 0.0f && r.org[1] == 0.0f && r.org[2] == 0.0f);
    CHECK(r.tmin == 0.0f && isinf(r.tmax) && r.tmax > 0);
    /* pixel (1,0): u = (2*1.5/4 - 1) * 2 = -0.5 */
    CHECK(tt_camera_ray(&c, 4, 2, 1, 0, &r) == TT_OK);
    CHECK(dir_is(&r, -0.5, 0.5, -1.0));
    /* pixel (3,1): u = (2*3.5/4 - 1) * 2 = 1.5, v = 1 - 2*1.5/2 = -0.5 */
    CHECK(tt_camera_ray(&c, 4, 2, 3, 1, &r) == TT_OK);
    CHECK(dir_is(&r, 1.5, -0.5, -1.0));
    /* a 1x1 image looks straight ahead */
    CHECK(tt_camera_ray(&c, 1, 1, 0, 0, &r) == TT_OK);
    CHECK(dir_is(&r, 0.0, 0.0, -1.0));
    /* a tall image: 2x4, pixel (0,3): a = 0.5, u = (2*0.5/2 - 1)*0.5 = -0.25,
     * v = 1 - 2*3.5/4 = -0.75 */
    CHECK(tt_camera_ray(&c, 2, 4, 0, 3, &r) == TT_OK);
    CHECK(dir_is(&r, -0.25, -0.75, -1.0));
    /* out-of-image pixels and empty images are refused */
    CHECK(tt_camera_ray(&c, 4, 2, 4, 0, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_camera_ray(&c, 4, 2, 0, 2, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_camera_ray(&c, 0, 2, 0, 0, &r) == TT_ERR_INVALID_ARGUMENT);
    CHECK(tt_camera_ray(NULL, 4, 2, 0, 0, &r) == TT_ERR_INVALID_ARGUMENT);
}

static void cross(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize(double *v)
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= l;
}

/* A tilted camera with a non-square image: every pixel against the formula
 * evaluated in double. */
static void test_general_camera(void)
{
    tt_camera c;
    memset(&c, 0, sizeof c);
    float eye[3] = {1, 2, 3}, look[3] = {4, -2, 3.5f}, up[3] = {0, 0.2f, 1};
    memcpy(c.eye, eye, sizeof eye);
    memcpy(c.look, look, sizeof look);
    memcpy(c.up, up, sizeof up);
    c.fov_deg = 60.0f;
    const uint32_t W = 7, H = 5;
    double f[3], r[3], u[3], upd[3] = {up[0], up[1], up[2]};
    for (int k = 0; k < 3; k++) f[k] = (double)look[k] - eye[k];
    normalize(f);
    cross(f, upd, r);
    normalize(r);
    cross(r, f, u);
    double h = tan(60.0 * PI / 360.0), a = (double)W / H;
    int bad = 0;
    for (uint32_t y = 0; y < H; y++) {
        for (uint32_t x = 0; x < W; x++) {
            double pu = (2.0 * (x + 0.5) / W - 1.0) * h * a, pv = (1.0 - 2.0 * (y + 0.5) / H) * h;
            double d[3];
            for (int k = 0; k < 3; k++) d[k] = f[k] + pu * r[k] + pv * u[k];
            tt_ray ray;
            CHECK(tt_camera_ray(&c, W, H, x, y, &ray) == TT_OK);
            if (!dir_is(&ray, d[0], d[1], d[2])) bad++;
            if (ray.org[0] != eye[0] || ray.org[1] != eye[1] || ray.org[2] != eye[2]) bad++;
        }
    }
    CHECK_MSG(bad == 0, "%d pixels differ from the formula", bad);
}

/* The scene is one triangle in z = 0 (normal +z) with bounds (0,0,0)-(1,1,0),
 * so eps = 1e-4 * sqrt(2). */
static void test_shadow_ray(void)
{
    tt_context *ctx = tt_test_context();
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t idx[] = {0, 1, 2};
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 3, idx, 1, &scene));
    const double eps = 1e-4 * sqrt(2.0);
    tt_camera c;
    memset(&c, 0, sizeof c);
    c.light[0] = 0.25f;
    c.light[1] = 3.25f;
    c.light[2] = 4.0f;
    c.has_light = 1;

    /* from above: the normal +z already faces the ray (dot < 0) */
    tt_ray p = {{0.25f, 0.25f, 2.0f}, 0.0f, {0, 0, -1}, INFINITY}, s;
    tt_hit h = {2.0f, 0.25f, 0.25f, 0};
    CHECK(tt_shadow_ray(scene, &c, &p, &h, &s) == 1);
    CHECK(near(s.org[0], 0.25, 1e-7) && near(s.org[1], 0.25, 1e-7));
    CHECK(near(s.org[2], eps, 1e-3));
    double to[3] = {0.0, 3.0, 4.0 - eps}, dist = sqrt(9.0 + (4.0 - eps) * (4.0 - eps));
    CHECK(dir_is(&s, to[0], to[1], to[2]));
    CHECK(near(s.tmax, dist * (1.0 - 1e-4), 1e-6));
    CHECK(s.tmin == 0.0f);
    CHECK(s.tmax < dist); /* the light itself is never an occluder */

    /* from below: the normal is flipped to -z, the origin moves below */
    tt_ray q = {{0.25f, 0.25f, -2.0f}, 0.0f, {0, 0, 1}, INFINITY};
    CHECK(tt_shadow_ray(scene, &c, &q, &h, &s) == 1);
    CHECK(near(s.org[2], -eps, 1e-3));
    dist = sqrt(9.0 + (4.0 + eps) * (4.0 + eps));
    CHECK(dir_is(&s, 0.0, 3.0, 4.0 + eps));
    CHECK(near(s.tmax, dist * (1.0 - 1e-4), 1e-6));

    /* no light, or no hit: no shadow ray, *out untouched */
    tt_ray sentinel;
    memset(&sentinel, 0x5a, sizeof sentinel);
    s = sentinel;
    c.has_light = 0;
    CHECK(tt_shadow_ray(scene, &c, &p, &h, &s) == 0);
    CHECK(memcmp(&s, &sentinel, sizeof s) == 0);
    c.has_light = 1;
    tt_hit miss = {INFINITY, 0, 0, TT_INVALID_ID};
    CHECK(tt_shadow_ray(scene, &c, &p, &miss, &s) == 0);
    CHECK(memcmp(&s, &sentinel, sizeof s) == 0);

    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
}

/* Framing puts the whole scene in view: every corner of the box projects
 * inside the image. */
static void test_frame_scene(void)
{
    tt_context *ctx = tt_test_context();
    const float v[] = {-1, 2, 3, 5, 2, 3, -1, 4, -7};
    const uint32_t idx[] = {0, 1, 2};
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 3, idx, 1, &scene));
    tt_camera c;
    tt_camera_frame_scene(scene, &c);
    CHECK(c.has_light == 1);
    CHECK(c.fov_deg > 0.0f && c.fov_deg < 180.0f);
    double f[3], r[3], u[3], upd[3] = {c.up[0], c.up[1], c.up[2]};
    for (int k = 0; k < 3; k++) f[k] = (double)c.look[k] - c.eye[k];
    normalize(f);
    cross(f, upd, r);
    normalize(r);
    cross(r, f, u);
    double h = tan(c.fov_deg * PI / 360.0);
    for (int corner = 0; corner < 8; corner++) {
        double p[3] = {corner & 1 ? 5 : -1, corner & 2 ? 4 : 2, corner & 4 ? 3 : -7}, d[3];
        for (int k = 0; k < 3; k++) d[k] = p[k] - c.eye[k];
        double z = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
        double x = (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / z;
        double y = (d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) / z;
        CHECK_MSG(z > 0 && fabs(x) < h && fabs(y) < h, "corner %d projects to %g %g (h %g)", corner,
                  x, y, h);
    }
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
}

/* tt_camera_ray refuses cameras that cannot make rays (they would give NaN
 * or zero directions), and tt_camera_problem names each cause; a valid
 * camera close to every limit is still accepted. */
static void test_invalid_cameras(void)
{
    const tt_camera good = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60.0f, {1, 2, 3}, 1};
    tt_ray r;
    CHECK(tt_camera_ray(&good, 4, 3, 2, 1, &r) == TT_OK && tt_camera_problem(&good) == NULL);
    struct {
        const char *what, *needle;
        tt_camera c;
    } bad[] = {
        {"NaN eye", "eye", good},          {"inf look", "look point", good},
        {"-inf up", "up", good},           {"NaN light", "light", good},
        {"NaN fov", "field of view", good}, {"fov 0", "field of view", good},
        {"fov 180", "field of view", good}, {"fov -1", "field of view", good},
        {"eye == look", "coincide", good},  {"zero up", "parallel", good},
        {"up along the view", "parallel", good}, {"eye and look 4e38 apart", "too far", good},
    };
    bad[0].c.eye[1] = NAN;
    bad[1].c.look[2] = INFINITY;
    bad[2].c.up[0] = -INFINITY;
    bad[3].c.light[2] = NAN;
    bad[4].c.fov_deg = NAN;
    bad[5].c.fov_deg = 0.0f;
    bad[6].c.fov_deg = 180.0f;
    bad[7].c.fov_deg = -1.0f;
    memcpy(bad[8].c.look, bad[8].c.eye, sizeof bad[8].c.look);
    memset(bad[9].c.up, 0, sizeof bad[9].c.up);
    bad[10].c.up[1] = 0.0f, bad[10].c.up[2] = 3.0f;
    bad[11].c.eye[0] = 2e38f, bad[11].c.look[0] = -2e38f; /* each finite, the distance not */
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const char *p = tt_camera_problem(&bad[i].c);
        CHECK_MSG(p && strstr(p, bad[i].needle), "%s: problem \"%s\"", bad[i].what,
                  p ? p : "(none)");
        memset(&r, 0, sizeof r);
        CHECK_MSG(tt_camera_ray(&bad[i].c, 4, 3, 2, 1, &r) == TT_ERR_INVALID_ARGUMENT,
                  "tt_camera_ray accepted a camera with %s", bad[i].what);
    }
    /* a non-finite light does not matter without a light */
    tt_camera c = bad[3].c;
    c.has_light = 0;
    CHECK(tt_camera_ray(&c, 4, 3, 2, 1, &r) == TT_OK);
    /* near the limits but valid: a tiny fov, a wide one, up almost along
     * the view, eye and look one ulp apart */
    c = good;
    c.fov_deg = 1e-3f;
    CHECK(tt_camera_ray(&c, 4, 3, 0, 0, &r) == TT_OK && isfinite(r.dir[0] + r.dir[1] + r.dir[2]));
    c.fov_deg = 179.9f;
    CHECK(tt_camera_ray(&c, 4, 3, 0, 0, &r) == TT_OK && isfinite(r.dir[0] + r.dir[1] + r.dir[2]));
    c = good;
    c.up[1] = 1e-3f, c.up[2] = 1.0f;
    CHECK(tt_camera_ray(&c, 4, 3, 0, 0, &r) == TT_OK && isfinite(r.dir[0] + r.dir[1] + r.dir[2]));
    c = good;
    c.look[2] = nextafterf(c.eye[2], 0.0f);
    CHECK(tt_camera_ray(&c, 4, 3, 1, 2, &r) == TT_OK && isfinite(r.dir[0] + r.dir[1] + r.dir[2]));
}

int main(void)
{
    test_axis_camera();
    test_general_camera();
    test_shadow_ray();
    test_frame_scene();
    test_invalid_cameras();
    return tt_test_finish();
}
