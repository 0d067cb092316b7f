/* `treetrace render` end to end on the scene of support/known_scene.h: the
 * hit buffer it writes is checked pixel by pixel against the construction,
 * the PNG and heatmap files are real PNGs of the right size, the text and
 * JSON outputs carry every documented key with the known counts. Also the
 * bundled default scene. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "cli_run.h"
#include "io/heatmap.h"
#include "json.h"
#include "known_scene.h"

/* The keys every render reports. */
static const char *const render_keys[] = {
    "scene", "triangles", "vertices", "load_s", "build_s", "accel", "accel_bytes", "threads",
    "width", "height", "primary_rays", "primary_hits", "shadow_rays", "shadow_occluded",
    "primary_s", "shadow_s", "trace_s", "trace_median_s", "mrays_per_s", "primary_mrays_per_s",
    "shadow_mrays_per_s", "peak_rss_mb", "view", "eye", "look", "up", "fov", "light", "repeat",
    "shadows"};
static const char *const stats_keys[] = {
    "primary_nodes_per_ray", "primary_interior_per_ray", "primary_leaves_per_ray",
    "primary_boxes_per_ray", "primary_triangles_per_ray", "shadow_nodes_per_ray",
    "shadow_interior_per_ray", "shadow_leaves_per_ray", "shadow_boxes_per_ray",
    "shadow_triangles_per_ray", "all_nodes_per_ray", "all_interior_per_ray",
    "all_leaves_per_ray", "all_boxes_per_ray", "all_triangles_per_ray"};

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* A PNG signature and an IHDR chunk of w x h, 8-bit RGB. */
static void check_png(const char *path, uint32_t w, uint32_t h)
{
    long size = 0;
    unsigned char *png = tt_test_read_file(path, &size);
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    CHECK_MSG(png && size > 33, "%s: missing or too short", path);
    if (!png || size <= 33) {
        free(png);
        return;
    }
    CHECK(memcmp(png, sig, 8) == 0);
    CHECK(be32(png + 8) == 13 && memcmp(png + 12, "IHDR", 4) == 0);
    CHECK_MSG(be32(png + 16) == w && be32(png + 20) == h, "%s: %ux%u, expected %ux%u", path,
              be32(png + 16), be32(png + 20), w, h);
    CHECK(png[24] == 8 && png[25] == 2); /* 8-bit, RGB */
    free(png);
}

static int has_key(char (*keys)[64], int n, const char *key)
{
    for (int i = 0; i < n; i++)
        if (strcmp(keys[i], key) == 0) return 1;
    return 0;
}

static double number(const char *json, const char *key)
{
    double v = -1;
    CHECK_MSG(tt_json_get_number(json, key, &v), "no number '%s' in the JSON", key);
    return v;
}

/* The value of "key: value" in text output, or NULL. */
static const char *text_value(const char *out, const char *key, char *buf, size_t size)
{
    size_t n = strlen(key);
    for (const char *line = out; line && *line; line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        if (strncmp(line, key, n) == 0 && line[n] == ':' && line[n + 1] == ' ') {
            const char *v = line + n + 2, *end = strchr(v, '\n');
            size_t len = end ? (size_t)(end - v) : strlen(v);
            if (len >= size) len = size - 1;
            memcpy(buf, v, len);
            buf[len] = '\0';
            return buf;
        }
    }
    return NULL;
}

static void test_known_json(const char *scene, const char *accel)
{
    const char *hits = tt_cli_tmp("known.hits"), *png = tt_cli_tmp("known.png"),
               *heat = tt_cli_tmp("heat.png");
    tt_cli_result r;
    tt_cli_run(&r, "render '%s' --accel %s %s --size 16x12 --hits '%s' --png '%s' --heatmap '%s' "
                   "--heatmap-metric triangles --stats --repeat 2 --threads 2 --json",
               scene, accel, TT_KNOWN_CLI_CAMERA, hits, png, heat);
    CHECK_MSG(r.status == 0, "%s: exit %d: %s", accel, r.status, r.err);
    char keys[128][64];
    int n = tt_json_object_keys(r.out, keys, 128);
    CHECK_MSG(n > 0, "%s: --json output is not one JSON object:\n%s", accel, r.out);
    for (size_t i = 0; i < COUNT(render_keys); i++)
        CHECK_MSG(has_key(keys, n, render_keys[i]), "%s: no key %s", accel, render_keys[i]);
    for (size_t i = 0; i < COUNT(stats_keys); i++)
        CHECK_MSG(has_key(keys, n, stats_keys[i]), "%s: no key %s", accel, stats_keys[i]);
    if (n > 0) {
        CHECK(number(r.out, "triangles") == TT_KNOWN_TRIANGLES);
        CHECK(number(r.out, "vertices") == TT_KNOWN_VERTICES);
        CHECK(number(r.out, "width") == TT_KNOWN_W && number(r.out, "height") == TT_KNOWN_H);
        CHECK(number(r.out, "primary_rays") == TT_KNOWN_W * TT_KNOWN_H);
        CHECK(number(r.out, "primary_hits") == TT_KNOWN_W * TT_KNOWN_H / 2);
        CHECK(number(r.out, "shadow_rays") == TT_KNOWN_W * TT_KNOWN_H / 2);
        CHECK(number(r.out, "shadow_occluded") == TT_KNOWN_W * TT_KNOWN_H / 4);
        CHECK(number(r.out, "threads") == 2 && number(r.out, "repeat") == 2);
        CHECK(number(r.out, "trace_median_s") >= number(r.out, "trace_s"));
        CHECK(number(r.out, "fov") == 90);
        char s[256];
        CHECK(tt_json_get_string(r.out, "accel", s, sizeof s) && strcmp(s, accel) == 0);
        CHECK(tt_json_get_string(r.out, "view", s, sizeof s) && strcmp(s, "explicit") == 0);
        CHECK(tt_json_get_string(r.out, "heatmap_metric", s, sizeof s) && strcmp(s, "triangles") == 0);
        if (strcmp(accel, "bruteforce") == 0) {
            CHECK(number(r.out, "primary_triangles_per_ray") == TT_KNOWN_TRIANGLES);
            CHECK(number(r.out, "primary_nodes_per_ray") == 0);
        }
    }
    long size = 0;
    unsigned char *buf = tt_test_read_file(hits, &size);
    int bad = tt_known_check_hits(accel, buf, buf ? (size_t)size : 0, 1);
    CHECK_MSG(bad == 0, "%s: %d pixels of the CLI's hit buffer are wrong", accel, bad);
    free(buf);
    check_png(png, TT_KNOWN_W, TT_KNOWN_H);
    check_png(heat, TT_KNOWN_W + tt_heat_panel_width(TT_KNOWN_H), TT_KNOWN_H);
    tt_cli_result_free(&r);
}

/* Text output has the same keys as JSON, one `key: value` a line. */
static void test_known_text(const char *scene)
{
    tt_cli_result r;
    tt_cli_run(&r, "render '%s' --accel bruteforce %s --size 16x12 --stats", scene,
               TT_KNOWN_CLI_CAMERA);
    CHECK_MSG(r.status == 0, "exit %d: %s", r.status, r.err);
    char v[256];
    for (size_t i = 0; i < COUNT(render_keys); i++)
        CHECK_MSG(text_value(r.out, render_keys[i], v, sizeof v), "no line '%s: '", render_keys[i]);
    for (size_t i = 0; i < COUNT(stats_keys); i++)
        CHECK_MSG(text_value(r.out, stats_keys[i], v, sizeof v), "no line '%s: '", stats_keys[i]);
    CHECK(text_value(r.out, "shadow_occluded", v, sizeof v) && strcmp(v, "48") == 0);
    CHECK(text_value(r.out, "light", v, sizeof v) && strcmp(v, "-10,0,-0.5") == 0);
    CHECK(text_value(r.out, "shadows", v, sizeof v) && strcmp(v, "yes") == 0);
    /* every line is key: value */
    int lines = 0, bad = 0;
    for (const char *l = r.out; *l; l = strchr(l, '\n') + 1) {
        const char *nl = strchr(l, '\n'), *colon = strstr(l, ": ");
        if (!nl) {
            bad++;
            break;
        }
        lines++;
        bad += !colon || colon > nl;
    }
    CHECK(lines >= (int)(COUNT(render_keys) + COUNT(stats_keys)) && bad == 0);
    tt_cli_result_free(&r);
}

static void test_known_variants(const char *scene)
{
    const char *hits = tt_cli_tmp("variant.hits");
    tt_cli_result r;
    long size;
    unsigned char *buf;
    /* no shadow rays: every flag 0 */
    tt_cli_run(&r, "render '%s' --accel bruteforce %s --size 16x12 --no-shadows --hits '%s' --json",
               scene, TT_KNOWN_CLI_CAMERA, hits);
    CHECK_MSG(r.status == 0, "exit %d: %s", r.status, r.err);
    CHECK(number(r.out, "shadow_rays") == 0 && number(r.out, "primary_hits") == 96);
    buf = tt_test_read_file(hits, &size);
    CHECK(tt_known_check_hits("--no-shadows", buf, buf ? (size_t)size : 0, 0) == 0);
    free(buf);
    tt_cli_result_free(&r);
    /* no light: no shadow rays either; --opt=value works like --opt value */
    tt_cli_run(&r, "render '%s' --accel=bruteforce --eye=0,0,0 --look=0,0,-1 --fov=90 --size=16x12 "
                   "--hits='%s' --json",
               scene, hits);
    CHECK_MSG(r.status == 0, "exit %d: %s", r.status, r.err);
    char s[64];
    CHECK(tt_json_get_string(r.out, "light", s, sizeof s) && strcmp(s, "none") == 0);
    CHECK(number(r.out, "shadow_rays") == 0);
    buf = tt_test_read_file(hits, &size);
    CHECK(tt_known_check_hits("no light", buf, buf ? (size_t)size : 0, 0) == 0);
    free(buf);
    tt_cli_result_free(&r);
    /* a views file: the same camera by name */
    const char *views = tt_cli_tmp("views.tsv");
    FILE *fp = fopen(views, "w");
    if (fp) {
        fputs("scene\tview\teye\tlook\tup\tfov_deg\tlight\n"
              "known\tmain\t0,0,0\t0,0,-1\t0,1,0\t90\t-10,0,-0.5\n", fp);
        fclose(fp);
    }
    tt_cli_run(&r, "render '%s' --accel bruteforce --view known:main --size 16x12 --hits '%s'",
               scene, hits);
    CHECK_MSG(r.status == 0, "--view beside the scene: exit %d: %s", r.status, r.err);
    buf = tt_test_read_file(hits, &size);
    CHECK(tt_known_check_hits("--view", buf, buf ? (size_t)size : 0, 1) == 0);
    free(buf);
    tt_cli_result_free(&r);
}

/* Without SCENE the bundled data/bunny.ply is rendered. */
static void test_default_scene(void)
{
    const char *png = tt_cli_tmp("default.png"), *hits = tt_cli_tmp("default.hits");
    tt_cli_result r;
    tt_cli_run(&r, "render --size 24x16 --png '%s' --hits '%s' --json", png, hits);
    CHECK_MSG(r.status == 0, "default scene: exit %d: %s", r.status, r.err);
    char s[4096];
    CHECK(tt_json_get_string(r.out, "scene", s, sizeof s) && strstr(s, "data/bunny.ply"));
    CHECK(number(r.out, "triangles") > 0 && number(r.out, "primary_hits") > 0);
    check_png(png, 24, 16);
    long size = 0;
    unsigned char *buf = tt_test_read_file(hits, &size);
    CHECK(buf && size == 24 * 16 * 12);
    free(buf);
    tt_cli_result_free(&r);
}

int main(void)
{
    char scene[512]; /* a copy: tt_cli_tmp's strings are reused */
    snprintf(scene, sizeof scene, "%s", tt_cli_tmp("known.ply"));
    if (tt_known_write_ply(scene) != 0) {
        fprintf(stderr, "cannot write %s\n", scene);
        return 1;
    }
    for (const char *const *n = tt_accel_names(); *n; n++) test_known_json(scene, *n);
    test_known_text(scene);
    test_known_variants(scene);
    test_default_scene();
    return tt_test_finish();
}
