/* `treetrace info`: counts, bounding box, times, memory, every statistic
 * of the structure and its check, as text and as JSON. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "cli_run.h"
#include "json.h"
#include "known_scene.h"

static const char *const info_keys[] = {"scene",  "triangles", "vertices",    "bbox_min",
                                        "bbox_max", "scene_bytes", "load_s",   "accel",
                                        "build_s", "accel_bytes", "statistics", "check",
                                        "peak_rss_mb"};

/* The statistics the library reports for a structure, as "statistics.KEY". */
typedef struct stat_list {
    char keys[64][64];
    int n;
} stat_list;

static void collect(void *user, const char *key, double value)
{
    stat_list *l = user;
    (void)value;
    if (l->n < 64) snprintf(l->keys[l->n++], 64, "%s", key);
}

static void test_structure(const char *scene, const char *accel)
{
    tt_context *ctx = tt_test_context();
    tt_scene *s;
    REQUIRE_OK(ctx, tt_scene_create(ctx, tt_known_vertices, TT_KNOWN_VERTICES, tt_known_indices,
                                    TT_KNOWN_TRIANGLES, &s));
    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = accel;
    tt_accel *a;
    REQUIRE_OK(ctx, tt_accel_build(ctx, s, &bo, &a));
    stat_list stats = {.n = 0};
    tt_accel_statistics(a, collect, &stats);
    tt_accel_destroy(a);
    tt_scene_destroy(s);
    tt_context_destroy(ctx);

    tt_cli_result r;
    tt_cli_run(&r, "info '%s' --accel %s --json", scene, accel);
    CHECK_MSG(r.status == 0, "%s: exit %d: %s", accel, r.status, r.err);
    char keys[64][64];
    int n = tt_json_object_keys(r.out, keys, 64);
    CHECK_MSG(n > 0, "%s: not one JSON object:\n%s", accel, r.out);
    for (size_t i = 0; i < sizeof info_keys / sizeof info_keys[0]; i++) {
        int found = 0;
        for (int k = 0; k < n; k++) found |= strcmp(keys[k], info_keys[i]) == 0;
        CHECK_MSG(found, "%s: no key %s", accel, info_keys[i]);
    }
    double v = 0;
    CHECK(tt_json_get_number(r.out, "triangles", &v) && v == TT_KNOWN_TRIANGLES);
    char check[32];
    CHECK(tt_json_get_string(r.out, "check", check, sizeof check) && strcmp(check, "ok") == 0);
    /* every statistic appears in the nested object ... */
    for (int i = 0; i < stats.n; i++) {
        char quoted[80];
        snprintf(quoted, sizeof quoted, "\"%s\":", stats.keys[i]);
        CHECK_MSG(strstr(r.out, quoted) != NULL, "%s: statistic %s missing", accel, stats.keys[i]);
    }
    tt_cli_result_free(&r);

    /* ... and as statistics.KEY lines in text */
    tt_cli_run(&r, "info '%s' --accel %s", scene, accel);
    CHECK(r.status == 0);
    CHECK(strstr(r.out, "bbox_min: -6,-3,-2\n") != NULL);
    CHECK(strstr(r.out, "bbox_max: 0,5,-1.5\n") != NULL);
    CHECK(strstr(r.out, "check: ok\n") != NULL);
    for (int i = 0; i < stats.n; i++) {
        char line[96];
        snprintf(line, sizeof line, "\nstatistics.%s: ", stats.keys[i]);
        CHECK_MSG(strstr(r.out, line) != NULL, "%s: line statistics.%s missing", accel,
                  stats.keys[i]);
    }
    tt_cli_result_free(&r);
}

int main(void)
{
    char scene[512]; /* a copy: tt_cli_tmp's strings are reused */
    snprintf(scene, sizeof scene, "%s", tt_cli_tmp("known.ply"));
    if (tt_known_write_ply(scene) != 0) return 1;
    for (const char *const *n = tt_accel_names(); *n; n++) test_structure(scene, *n);
    /* the R-tree's builders: each named in the output with its quality
     * figures, the insertion-only options only for insert */
    static const char *const builds[] = {"insert", "str", "hilbert", "sah"};
    for (int b = 0; b < 4 && tt_test_has_accel("rtree"); b++) {
        tt_cli_result r;
        tt_cli_run(&r, "info '%s' --accel rtree --build %s --M 8 --m 3", scene, builds[b]);
        char line[64];
        snprintf(line, sizeof line, "\nbuild: %s\n", builds[b]);
        CHECK_MSG(r.status == 0 && strstr(r.out, line) && strstr(r.out, "\nM: 8\n") &&
                      strstr(r.out, "statistics.sah_cost: ") &&
                      strstr(r.out, "statistics.leaf_fill: ") &&
                      strstr(r.out, "statistics.interior_fill: ") &&
                      strstr(r.out, "check: ok\n") &&
                      (strstr(r.out, "\nstrategy: ") != NULL) == (b == 0),
                  "info --build %s: exit %d: %s%s", builds[b], r.status, r.out, r.err);
        tt_cli_result_free(&r);
    }
    return tt_test_finish();
}
