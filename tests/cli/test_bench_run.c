/* A whole `treetrace bench` run on a tiny scenes folder (bunny_res4 and
 * cornell, one view each, 16x12 pixels): results.csv has the expected
 * columns and exactly the expected runs (every table's configurations plus
 * the Embree runs they are compared with), each with sane figures; the
 * structures this build offers agree with Embree on every pixel; engine.csv
 * (the engine table) has every side, structure, mode and ray kind once,
 * with consistent rates, ratios, builds and answers; report.md has every
 * table's heading and the plots and heatmaps it links exist. */
#include <math.h>

#include "bench_support.h"

#define MAX_FIELDS 64
#define MAX_ROWS 256

/* clang-format off */
static const char *const columns[] = {
    "scene", "view", "width", "height", "triangles", "vertices", "load_s", "accel",
    "traversal", "options", "rays", "tables", "status", "error", "threads", "repeats",
    "build_s", "memory_bytes", "accel_stats", "primary_rays", "primary_hits", "shadow_rays",
    "shadow_occluded", "trace_min_s", "trace_median_s", "primary_min_s", "shadow_min_s",
    "mrays_per_s_median", "mrays_per_s_best", "primary_mrays_per_s", "shadow_mrays_per_s",
    "primary_nodes_per_ray", "primary_interior_per_ray", "primary_leaves_per_ray",
    "primary_boxes_per_ray", "primary_triangles_per_ray", "shadow_nodes_per_ray",
    "shadow_interior_per_ray", "shadow_leaves_per_ray", "shadow_boxes_per_ray",
    "shadow_triangles_per_ray", "all_nodes_per_ray", "all_interior_per_ray",
    "all_leaves_per_ray", "all_boxes_per_ray", "all_triangles_per_ray",
    "embree_trace_median_s", "time_vs_embree", "agree_embree_pixels", "compared_pixels",
    "agree_embree_pct", "arbitrated_pixels", "ours_match_bruteforce", "device",
    "device_name", "upload_s", "download_s"};
/* clang-format on */
#define NCOL (sizeof columns / sizeof columns[0])

typedef struct row {
    char *f[MAX_FIELDS];
    int n;
} row;

/* Splits one CSV line (RFC 4180 quoting) in place. */
static char *parse_line(char *p, row *r)
{
    r->n = 0;
    for (;;) {
        char *start = p, *w = p;
        if (*p == '"') {
            p++;
            for (;;) {
                if (*p == '"' && p[1] == '"')
                    *w++ = '"', p += 2;
                else if (*p == '"') {
                    p++;
                    break;
                } else if (!*p)
                    break;
                else
                    *w++ = *p++;
            }
        } else {
            while (*p && *p != ',' && *p != '\n') *w++ = *p++;
        }
        char end = *p;
        *w = '\0';
        if (r->n < MAX_FIELDS) r->f[r->n++] = start;
        if (end == ',') {
            p++;
            continue;
        }
        return end == '\n' ? p + 1 : p;
    }
}

static int col(const char *name)
{
    for (size_t i = 0; i < NCOL; i++)
        if (strcmp(columns[i], name) == 0) return (int)i;
    return -1;
}

static const char *get(const row *r, const char *name) { return r->f[col(name)]; }
static double num(const row *r, const char *name) { return atof(get(r, name)); }

typedef struct expect {
    const char *accel, *traversal, *rays, *opt1, *opt2;
} expect;

/* Every run one scene:view needs with equal sizes for all tables and
 * --dmin 1,2 (the default d_min, 4, is Table 1's). */
static const expect expected[] = {
    {"rtree", "stackless", "primary+shadow", "strategy=minVolume ", "reinsert=1"},
    {"rtree", "stackless", "primary+shadow", "strategy=minSurface ", "reinsert=1"},
    {"rtree", "stackless", "primary+shadow", "strategy=minOverlap ", "reinsert=1"},
    {"rtree", "stackless", "primary+shadow", "strategy=R*-tree ", "reinsert=1"},
    {"rtree", "stackless", "primary+shadow", "strategy=R*-treeSrfc ", "reinsert=1"},
    {"rtree", "stackless", "primary+shadow", "strategy=R*-treeSrfc ", "reinsert=0"},
    {"rtree", "ordered", "primary+shadow", "strategy=R*-treeSrfc ", "reinsert=1"},
    {"rtree", "stack", "primary+shadow", "strategy=R*-treeSrfc ", "reinsert=1"},
    {"rtree", "stack", "primary", "strategy=R*-treeSrfc ", "reinsert=1"},
    {"kdtree", "HTR", "primary+shadow", "builder=nlog2n ", "dmin=-1 "},
    {"kdtree", "HTR", "primary", "builder=nlog2n ", "dmin=-1 "},
    {"kdtree", "HTR", "primary", "builder=nlogn ", "dmin=-1 "},
    {"kdtree", "BTR", "primary", "builder=nlogn ", "dmin=4 "},
    {"kdtree", "SLTR", "primary", "builder=nlogn ", "dmin=4 "},
    {"kdtree", "SEQ", "primary", "builder=nlogn ", "dmin=-1 "},
    {"kdtree", "BTR", "primary", "builder=nlogn ", "dmin=1 "},
    {"kdtree", "SLTR", "primary", "builder=nlogn ", "dmin=1 "},
    {"kdtree", "BTR", "primary", "builder=nlogn ", "dmin=2 "},
    {"kdtree", "SLTR", "primary", "builder=nlogn ", "dmin=2 "},
    {"embree", "-", "primary+shadow", "quality=high", ""},
    {"embree", "-", "primary", "", ""},
    /* the engine table (E) is not rendered: engine.csv, checked below */
};
#define NEXPECT (sizeof expected / sizeof expected[0])

static int matches(const row *r, const char *scene, const expect *e)
{
    return strcmp(get(r, "scene"), scene) == 0 && strcmp(get(r, "accel"), e->accel) == 0 &&
           strcmp(get(r, "traversal"), e->traversal) == 0 && strcmp(get(r, "rays"), e->rays) == 0 &&
           strstr(get(r, "options"), e->opt1) && strstr(get(r, "options"), e->opt2);
}

static void check_row(const row *r)
{
    const char *acc = get(r, "accel");
    int ok = strcmp(get(r, "status"), "ok") == 0;
    /* without --device gpu every run is on the CPU, with no copy times */
    CHECK(strcmp(get(r, "device"), "cpu") == 0 && get(r, "upload_s")[0] == '\0');
    CHECK_MSG(ok == tt_test_has_accel(acc), "%s %s: status %s (%s)", acc, get(r, "traversal"),
              get(r, "status"), get(r, "error"));
    if (!ok) {
        CHECK(strcmp(get(r, "status"), "skipped") == 0);
        return;
    }
    int shadows = strcmp(get(r, "rays"), "primary+shadow") == 0;
    CHECK(num(r, "width") == 16 && num(r, "height") == 12);
    CHECK(num(r, "primary_rays") == 192);
    CHECK(num(r, "primary_hits") > 0 && num(r, "primary_hits") <= 192);
    CHECK(shadows ? num(r, "shadow_rays") == num(r, "primary_hits") : num(r, "shadow_rays") == 0);
    CHECK(num(r, "trace_median_s") > 0.0 && num(r, "trace_min_s") <= num(r, "trace_median_s"));
    CHECK(num(r, "repeats") >= 1 && num(r, "repeats") <= 2);
    CHECK(num(r, "build_s") > 0.0 && num(r, "memory_bytes") > 0); /* a build takes time */
    CHECK(num(r, "threads") == 2);
    if (strcmp(acc, "embree") == 0) {
        /* Embree cannot be instrumented: no per-ray counts, no comparison */
        CHECK(num(r, "primary_nodes_per_ray") == 0.0);
        CHECK(get(r, "agree_embree_pct")[0] == '\0');
        return;
    }
    CHECK(num(r, "primary_nodes_per_ray") > 0.0 && num(r, "primary_triangles_per_ray") > 0.0);
    CHECK(num(r, "embree_trace_median_s") > 0.0 && num(r, "time_vs_embree") > 0.0);
    CHECK(num(r, "compared_pixels") == 192);
    CHECK(num(r, "arbitrated_pixels") == 192 - num(r, "agree_embree_pixels"));
    CHECK_MSG(num(r, "agree_embree_pixels") == 192, "%s %s %s: %s of 192 pixels agree", acc,
              get(r, "traversal"), get(r, "options"), get(r, "agree_embree_pixels"));
}

static void check_csv(const char *path)
{
    char *text = read_text(path);
    CHECK_MSG(text != NULL, "no %s", path);
    if (!text) return;
    static row rows[MAX_ROWS];
    int nrows = 0;
    row header;
    char *p = parse_line(text, &header);
    CHECK(header.n == (int)NCOL);
    for (int i = 0; i < header.n && i < (int)NCOL; i++)
        CHECK_MSG(strcmp(header.f[i], columns[i]) == 0, "column %d is '%s', expected '%s'", i,
                  header.f[i], columns[i]);
    while (*p && nrows < MAX_ROWS) {
        p = parse_line(p, &rows[nrows]);
        CHECK_MSG(rows[nrows].n == (int)NCOL, "row %d has %d fields", nrows + 1, rows[nrows].n);
        if (rows[nrows].n == (int)NCOL) nrows++;
    }
    CHECK_MSG(nrows == 2 * (int)NEXPECT, "%d rows, expected %d", nrows, 2 * (int)NEXPECT);
    const char *scenes[2] = {"bunny_res4", "cornell"};
    for (int s = 0; s < 2; s++) {
        for (size_t e = 0; e < NEXPECT; e++) {
            int found = 0;
            for (int i = 0; i < nrows; i++) {
                if (!matches(&rows[i], scenes[s], &expected[e])) continue;
                found++;
                check_row(&rows[i]);
            }
            CHECK_MSG(found == 1, "%s %s %s %s %s%s: %d rows", scenes[s], expected[e].accel,
                      expected[e].traversal, expected[e].rays, expected[e].opt1, expected[e].opt2,
                      found);
        }
    }
    free(text);
}

/* ------------------------------------------------------------ engine.csv */

/* clang-format off */
static const char *const ecolumns[] = {
    "scene", "view", "width", "height", "triangles", "threads", "rounds", "engine", "config",
    "accel", "options", "is_default", "mode", "flags", "kind", "rays", "best_s", "mrays_per_s",
    "x_embree", "x_embree_robust", "x_embree_p8", "x_embree_p16", "x_packets_off", "status",
    "error", "isa", "packets_offered", "build_s", "builds", "memory_bytes", "x_embree_build",
    "x_embree_memory", "agree_embree", "agree_embree_pct", "bruteforce_checked",
    "bruteforce_equal", "same_as_reference", "packets_mismatch", "nodes_per_ray",
    "triangles_per_ray", "sah_cost"};
/* clang-format on */
#define NECOL (sizeof ecolumns / sizeof ecolumns[0])
#define AO_SAMPLES 3 /* --ao 3 */

static const char *eget(const row *r, const char *name)
{
    for (size_t i = 0; i < NECOL; i++)
        if (strcmp(ecolumns[i], name) == 0) return r->f[i];
    fprintf(stderr, "no engine.csv column %s\n", name);
    exit(1);
}

static double enumber(const row *r, const char *name)
{
    const char *v = eget(r, name);
    return *v ? atof(v) : -1.0; /* empty: -1, which every check below refuses */
}

static int eempty(const row *r, const char *name) { return eget(r, name)[0] == '\0'; }

static int near(double a, double b) { return a > 0.0 && b > 0.0 && fabs(a - b) <= 2e-3 * b; }

typedef struct etable {
    row rows[MAX_ROWS];
    int n;
} etable;

/* The one row with these fields; NULL (and a failed check when want) if
 * there is none or more than one. */
static const row *erow(const etable *t, const char *scene, const char *engine, const char *config,
                       const char *mode, const char *flags, const char *kind, int want)
{
    const row *found = NULL;
    int count = 0;
    for (int i = 0; i < t->n; i++) {
        const row *r = &t->rows[i];
        if (strcmp(eget(r, "scene"), scene) || strcmp(eget(r, "engine"), engine) ||
            strcmp(eget(r, "config"), config) || strcmp(eget(r, "mode"), mode) ||
            strcmp(eget(r, "flags"), flags) || strcmp(eget(r, "kind"), kind))
            continue;
        found = r;
        count++;
    }
    CHECK_MSG(count == (want ? 1 : 0), "engine.csv: %s %s %s %s %s %s: %d rows, expected %d",
              scene, engine, config, mode, flags, kind, count, want ? 1 : 0);
    return count == 1 ? found : NULL;
}

static const char *const kinds[3] = {"primary", "shadow", "ao"};
static const char *const engine_configs[4] = {"rtree sah, compact", "kdtree nlogn, htr",
                                              "kdtree binned, htr",
                                              "rtree insert, complete (Feldmann)"};

/* What every row shares: the run's settings, a rate that is rays over the
 * fastest pass, and rays as many as the view has of that kind. */
static void check_common(const row *r, double rays)
{
    CHECK(num(r, "width") == 16 && num(r, "height") == 12);
    CHECK(enumber(r, "threads") == 2 && enumber(r, "rounds") == 2);
    CHECK_MSG(strcmp(eget(r, "status"), "ok") == 0, "%s %s %s: %s", eget(r, "config"),
              eget(r, "mode"), eget(r, "kind"), eget(r, "error"));
    CHECK_MSG(enumber(r, "rays") == rays, "%s %s %s: %s rays, expected %.0f", eget(r, "config"),
              eget(r, "mode"), eget(r, "kind"), eget(r, "rays"), rays);
    const double best = enumber(r, "best_s"), rate = enumber(r, "mrays_per_s");
    CHECK(best > 0.0 && best < 10.0);
    CHECK_MSG(near(rate, rays / best * 1e-6), "%s: %g Mrays/s for %.0f rays in %g s",
              eget(r, "config"), rate, rays, best);
    CHECK(enumber(r, "build_s") > 0.0 && enumber(r, "builds") == 2);
    CHECK(enumber(r, "memory_bytes") > 0.0);
}

static void check_scene_engine(const etable *t, const char *scene)
{
    /* Embree: single rays (default flags, every kind), robust, p8, p16 */
    const row *e[3];
    for (int k = 0; k < 3; k++) e[k] = erow(t, scene, "embree", "Embree 3 (medium)", "single", "default", kinds[k], 1);
    if (!e[0] || !e[1] || !e[2]) return;
    const double rays[3] = {enumber(e[0], "rays"), enumber(e[1], "rays"), enumber(e[2], "rays")};
    CHECK(rays[0] == 192);
    /* every view has a light: a shadow ray per primary hit; AO: --ao 3 */
    CHECK(rays[1] > 0 && rays[1] <= 192);
    CHECK_MSG(rays[2] == AO_SAMPLES * rays[1], "%s: %.0f AO rays for %.0f hits", scene, rays[2],
              rays[1]);
    const struct {
        const char *mode, *flags;
    } sides[4] = {{"single", "default"}, {"single", "robust"}, {"p8", "default"}, {"p16", "default"}};
    double erate[4][3];
    for (int s = 0; s < 4; s++) {
        for (int k = 0; k < 3; k++) {
            /* Embree's AO rays: single rays, default flags only */
            const row *r = erow(t, scene, "embree", "Embree 3 (medium)", sides[s].mode,
                                sides[s].flags, kinds[k], s == 0 || k < 2);
            erate[s][k] = r ? enumber(r, "mrays_per_s") : -1.0;
            if (!r) continue;
            check_common(r, rays[k]);
            CHECK(strcmp(eget(r, "accel"), "embree") == 0);
            CHECK(eempty(r, "nodes_per_ray") && eempty(r, "agree_embree"));
        }
    }
    for (int k = 0; k < 3; k++) CHECK(enumber(e[k], "x_embree") == 1.0);
    CHECK(eempty(e[2], "x_embree_p16") && !eempty(e[0], "x_embree_p16"));
    const row *rob = erow(t, scene, "embree", "Embree 3 (medium)", "single", "robust", "primary", 1);
    if (rob) CHECK(near(enumber(rob, "x_embree"), erate[1][0] / erate[0][0]));

    /* ours: each structure; off and on only where it offers packets */
    for (int c = 0; c < 4; c++) {
        const char *cf = engine_configs[c];
        const row *a = erow(t, scene, "treetrace", cf, "auto", "", "primary", 1);
        if (!a) continue;
        const int offered = (int)enumber(a, "packets_offered");
        CHECK(offered == 0 || offered == 1);
        for (int m = 0; m < 3; m++) {
            static const char *const modes[3] = {"auto", "off", "on"};
            for (int k = 0; k < 3; k++) {
                const int want = m == 0 || (offered && !(m == 2 && k == 2));
                const row *r = erow(t, scene, "treetrace", cf, modes[m], "", kinds[k], want);
                if (!r) continue;
                check_common(r, rays[k]);
                CHECK(strcmp(eget(r, "is_default"), c < 2 ? "1" : "0") == 0);
                CHECK(eget(r, "isa")[0] != '\0');
                CHECK(enumber(r, "packets_offered") == offered);
                const double rate = enumber(r, "mrays_per_s");
                CHECK_MSG(near(enumber(r, "x_embree"), rate / erate[0][k]),
                          "%s %s %s: x_embree %s for %g over %g", cf, modes[m], kinds[k],
                          eget(r, "x_embree"), rate, erate[0][k]);
                if (k < 2) {
                    CHECK(near(enumber(r, "x_embree_robust"), rate / erate[1][k]));
                    CHECK(near(enumber(r, "x_embree_p8"), rate / erate[2][k]));
                    CHECK(near(enumber(r, "x_embree_p16"), rate / erate[3][k]));
                    CHECK(enumber(r, "nodes_per_ray") > 0.0);
                    CHECK(enumber(r, "triangles_per_ray") >= (k == 0 ? 0.5 : 0.0));
                } else {
                    CHECK(eempty(r, "x_embree_robust") && eempty(r, "x_embree_p16"));
                    CHECK(eempty(r, "nodes_per_ray"));
                }
                CHECK(eempty(r, "x_packets_off") == !offered);
                CHECK(near(enumber(r, "x_embree_build"),
                           enumber(r, "build_s") / enumber(e[0], "build_s")));
                CHECK(near(enumber(r, "x_embree_memory"),
                           enumber(r, "memory_bytes") / enumber(e[0], "memory_bytes")));
                /* answers: Embree's test is not watertight, so a few may
                 * differ from it; never from bruteforce or the default
                 * R-tree, nor between packet modes */
                const double agree = enumber(r, "agree_embree");
                CHECK(agree >= 0.9 * rays[k] && agree <= rays[k]);
                CHECK(near(enumber(r, "agree_embree_pct"), 100.0 * agree / rays[k]));
                const double bf = enumber(r, "bruteforce_checked");
                CHECK_MSG(bf >= (rays[k] < 128 ? rays[k] : 128) &&
                              enumber(r, "bruteforce_equal") == bf,
                          "%s %s %s: %s of %s equal to bruteforce", cf, modes[m], kinds[k],
                          eget(r, "bruteforce_equal"), eget(r, "bruteforce_checked"));
                CHECK_MSG(enumber(r, "same_as_reference") == rays[k],
                          "%s %s %s: %s of %.0f as the default R-tree", cf, modes[m], kinds[k],
                          eget(r, "same_as_reference"), rays[k]);
                CHECK(enumber(r, "packets_mismatch") == 0.0);
            }
        }
    }
}

static void check_engine_csv(const char *path)
{
    char *text = read_text(path);
    CHECK_MSG(text != NULL, "no %s", path);
    if (!text) return;
    static etable t;
    row header;
    char *p = parse_line(text, &header);
    CHECK(header.n == (int)NECOL);
    for (int i = 0; i < header.n && i < (int)NECOL; i++)
        CHECK_MSG(strcmp(header.f[i], ecolumns[i]) == 0, "engine.csv column %d is '%s', expected '%s'",
                  i, header.f[i], ecolumns[i]);
    t.n = 0;
    while (*p && t.n < MAX_ROWS) {
        p = parse_line(p, &t.rows[t.n]);
        CHECK_MSG(t.rows[t.n].n == (int)NECOL, "engine.csv row %d has %d fields", t.n + 1,
                  t.rows[t.n].n);
        if (t.rows[t.n].n == (int)NECOL) t.n++;
    }
    /* per scene: 9 Embree rows, and per structure 3 (auto) or 8 (packets) */
    int expect = 0;
    for (int i = 0; i < t.n; i++)
        if (strcmp(eget(&t.rows[i], "mode"), "auto") == 0 &&
            strcmp(eget(&t.rows[i], "kind"), "primary") == 0)
            expect += enumber(&t.rows[i], "packets_offered") == 1.0 ? 8 : 3;
    CHECK_MSG(t.n == 2 * 9 + expect, "engine.csv: %d rows, expected %d", t.n, 2 * 9 + expect);
    check_scene_engine(&t, "bunny_res4");
    check_scene_engine(&t, "cornell");
    free(text);
}

static int exists(const char *dir, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, R_OK) == 0;
}

static void check_report(const char *out)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/report.md", out);
    char *md = read_text(path);
    CHECK_MSG(md != NULL, "no %s", path);
    if (!md) return;
    const char *headings[] = {
        "## Machine and settings",
        "## Agreement with Embree",
        "### Feldmann Table 1: R-tree insertion strategies",
        "### Feldmann Table 2: R*-treeSrfc without forced reinsert",
        "### Feldmann Table 3: R-tree traversal algorithms",
        "### Feldmann Table 4: R*-tree vs kd-tree",
        "### Feldmann Table 5: construction times",
        "### Havran & Bittner Table 1: kd-tree traversal algorithms",
        "### Havran & Bittner Figure 3: interior nodes and time against d_min",
        "### Engine table: our batch calls against Embree's own loops",
        "| rtree sah, compact **(default)** |",
        "| kdtree nlogn, htr **(default)** |",
        "Summary, the default structures with packets=auto",
        "| **all views** |",
        "| Embree rtcIntersect1/rtcOccluded1, default flags |",
        "| Embree, ROBUST flag |",
        "| Embree rtcIntersect16/rtcOccluded16, coherent | 4x4 |",
        "#### cornell:main (36 triangles; 192 primary,",
    };
    for (size_t i = 0; i < sizeof headings / sizeof headings[0]; i++)
        CHECK_MSG(strstr(md, headings[i]) != NULL, "report.md lacks '%s'", headings[i]);
    /* the papers' numbers are beside ours (Table 1's Bunny minOverlap, H&B's arena SEQ N_I) */
    CHECK(strstr(md, "53.00 s") != NULL);
    CHECK(strstr(md, "246.97") != NULL);
    CHECK(strstr(md, "| CPU |") != NULL && strstr(md, "| compiler |") != NULL);
    /* every linked image exists */
    for (const char *p = md; (p = strstr(p, "](")); p += 2) {
        const char *end = strchr(p + 2, ')');
        if (!end || end - p > 300) continue;
        char name[320];
        snprintf(name, sizeof name, "%.*s", (int)(end - p - 2), p + 2);
        if (strstr(name, ".png")) CHECK_MSG(exists(out, name), "%s is linked but missing", name);
    }
    /* the figures: drawn by python3 -m treetrace.plots where matplotlib is, else the
     * report says how to draw them (never a link to a file that is not there) */
    if (strstr(md, "no figures were drawn")) {
        CHECK(strstr(md, "python3 -m treetrace.plots") != NULL);
        CHECK(!exists(out, "fig3-cornell-main.png"));
    } else {
        CHECK(exists(out, "fig3-bunny_res4-main.png") && exists(out, "fig3-bunny_res4-main.pdf"));
        CHECK(exists(out, "fig3-cornell-main.png") && exists(out, "fig3-cornell-main.pdf"));
        CHECK(exists(out, "engine.pdf") && exists(out, "feldmann-strategies.pdf"));
        CHECK(exists(out, "figures.md"));
        CHECK(strstr(md, "(fig3-cornell-main.pdf)") != NULL);
    }
    if (tt_test_has_accel("kdtree"))
        CHECK(exists(out, "heatmaps/cornell-main-kdtree-SLTR-dmin4-16x12.png"));
    if (tt_test_has_accel("rtree"))
        CHECK(exists(out, "heatmaps/cornell-main-rtree-ordered-16x12.png"));
    /* structures missing from this build are named as skipped */
    if (!tt_test_has_accel("rtree")) CHECK(strstr(md, "rtree: not in this build") != NULL);
    if (!tt_test_has_accel("kdtree")) CHECK(strstr(md, "kdtree: not in this build") != NULL);
    free(md);
}

int main(void)
{
    if (!tt_test_has_accel("embree")) {
        printf("skipped: this build has no Embree, the benchmark's reference\n");
        return 77;
    }
    const char *scenes = make_tiny_scenes();
    char out[600], log[600], args[2048];
    snprintf(out, sizeof out, "%s/out", scenes);
    snprintf(log, sizeof log, "%s/log.txt", scenes);
    snprintf(args, sizeof args,
             "--scenes '%s' --scene bunny_res4,cornell --out '%s' --size 16x12 --repeat 2 "
             "--dmin 1,2 --threads 2 --builds 2 --ao 3",
             scenes, out);
    int rc = run_bench(args, log);
    char *text = read_text(log);
    CHECK_MSG(rc == 0, "exit %d: %s", rc, text ? text : "");
    free(text);
    char csv[700];
    snprintf(csv, sizeof csv, "%s/results.csv", out);
    check_csv(csv);
    snprintf(csv, sizeof csv, "%s/engine.csv", out);
    check_engine_csv(csv);
    check_report(out);
    remove_tree(scenes);
    return tt_test_finish();
}
