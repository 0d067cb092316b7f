/* The command line of `treetrace bench`. --quick sets smaller defaults
 * first, so that explicit options given with it still win. */
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/bench_yard.h"

const bench_table_name bench_tables[] = {
    {BENCH_F1, "F1", "Feldmann Table 1: R-tree insertion strategies (primary + shadow rays)"},
    {BENCH_F2, "F2", "Feldmann Table 2: R*-treeSrfc without forced reinsert"},
    {BENCH_F3, "F3", "Feldmann Table 3: R-tree traversal algorithms"},
    {BENCH_F4, "F4", "Feldmann Table 4: R*-tree vs kd-tree"},
    {BENCH_F5, "F5", "Feldmann Table 5: construction times"},
    {BENCH_H1, "H1", "Havran & Bittner Table 1: kd-tree traversal algorithms (primary rays)"},
    {BENCH_H3, "H3", "Havran & Bittner Figure 3: interior nodes and time against d_min"},
    {BENCH_E1, "E", "Engine table: our batch calls against Embree's own loops"},
    {BENCH_D, "D", "Dynamic scenes: in-place updates against Embree's refit and rebuilds"},
};
const size_t bench_table_count = sizeof bench_tables / sizeof bench_tables[0];

const char *bench_table_title(unsigned bit)
{
    for (size_t i = 0; i < bench_table_count; i++)
        if (bench_tables[i].bit == bit) return bench_tables[i].title;
    return "";
}

void bench_print_help(FILE *f)
{
    fputs("usage: treetrace bench [options]\n"
          "\n"
          "Reproduces the tables of Feldmann 2015 (R-trees) and Havran & Bittner 2007\n"
          "(kd-trees with sparse boxes) on the shared scenes, with Embree measured beside\n"
          "every configuration, and writes results.csv, report.md and heatmaps; the\n"
          "figures (PDF + PNG) are drawn by python3 -m treetrace.plots OUT when python3\n"
          "with matplotlib is there (else it says how to draw them later).\n"
          "Each scene is loaded once, each structure built once; every render is a\n"
          "counting warm-up pass (statistics, hit buffer, heatmap) followed by K timed\n"
          "passes whose median is reported.\n"
          "\n"
          "options:\n"
          "  --scenes DIR      scenes folder with scenes.tsv and views.tsv\n"
          "                    (default: ../shared/scenes next to the build or source)\n"
          "  --out DIR         output folder (default: bench/results-YYYY-MM-DD)\n"
          "  --threads N       render threads (default: OpenMP's default)\n"
          "  --repeat K        timed passes per render after the warm-up (default 3;\n"
          "                    fewer when a pass is slow, see --budget); also the\n"
          "                    engine table's interleaved rounds (default 5)\n"
          "  --builds N        the engine table builds each structure N times and\n"
          "                    reports the fastest (default 3, 1 with --quick)\n"
          "  --ao N            ambient-occlusion rays per primary hit in the engine\n"
          "                    table (default 2)\n"
          "  --budget S        aim for at most S seconds of timed passes per render\n"
          "                    (default 3; at least one pass is always made)\n"
          "  --quick           a reduced matrix that runs in about a minute: scenes up\n"
          "                    to 100k triangles (bunny, sibenik) unless --scene names\n"
          "                    others, first view, 256x256 / 200x150, one timed pass,\n"
          "                    d_min 1,4,12\n"
          "  --only LIST       only these tables: F1,F2,F3,F4,F5 (Feldmann), H1, H3\n"
          "                    (Havran & Bittner Table 1 and Figure 3), E (the engine\n"
          "                    table: primary, shadow and AO rays through our batch\n"
          "                    calls against Embree's own rtcIntersect1/rtcOccluded1\n"
          "                    loops, default flags and robust, and its 8/16-wide\n"
          "                    packets; writes engine.csv), D (dynamic\n"
          "                    scenes, only when named: deformation, 1% edits and\n"
          "                    growth frame by frame, 512x512, tt_accel_update against\n"
          "                    Embree's REFIT / LOW / MEDIUM commits; dynamic.csv/.md)\n"
          "  --frames N        frames of each table-D sequence (default 100)\n"
          "  --scene LIST      only these scenes (by scenes.tsv name; the tiny test\n"
          "                    scenes bunny_res4 and cornell run only when named)\n"
          "  --size WxH        image size for every table\n"
          "  --rtree-size WxH  image size of the Feldmann tables (default 1024x1024)\n"
          "  --kd-size WxH     image size of the Havran & Bittner tables (default 800x600)\n"
          "  --dmin LIST       d_min values of Figure 3, e.g. 1-12 or 1,2,4,8 (default 1-12)\n"
          "  --all-views       every view of each scene (the default, but not with --quick)\n"
          "  --first-view      only the first view listed for each scene\n"
          "  --no-heatmaps     do not write heatmap PNGs\n"
          "  --device cpu|gpu  gpu: trace every configuration the GPU supports (R-tree\n"
          "                    stackless/ordered, kd-tree SLTR/HTR) on the GPU too,\n"
          "                    with the R-trees of Feldmann's Tables 1-2 also ordered as\n"
          "                    in his GPU rows; report.md gets a GPU section (default cpu)\n"
          "  -h, --help        this text\n"
          "\n"
          "Exit status: 0 done, 1 a run-time failure, 2 bad options.\n",
          f);
}

static void set_defaults(bench_options *o, int quick)
{
    memset(o, 0, sizeof *o);
    o->quick = quick;
    o->repeat = quick ? 1 : 3;
    o->budget_s = quick ? 1.0 : 3.0;
    o->tables = BENCH_ALL_TABLES;
    o->rtree_size = quick ? (bench_size){256, 256} : (bench_size){1024, 1024};
    o->kd_size = quick ? (bench_size){200, 150} : (bench_size){800, 600};
    o->all_views = !quick;
    o->heatmaps = 1;
    o->builds = quick ? 1 : 3;
    o->rounds = quick ? 1 : 5;
    o->ao_samples = YARD_AO_DEFAULT_SAMPLES;
    o->frames = 100;
    if (quick) {
        const int q[] = {1, 4, 12};
        memcpy(o->dmins, q, sizeof q);
        o->dmin_count = 3;
    } else {
        for (int i = 0; i < 12; i++) o->dmins[i] = i + 1;
        o->dmin_count = 12;
    }
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

static int parse_size(const char *s, bench_size *out)
{
    char *end;
    errno = 0;
    unsigned long w = strtoul(s, &end, 10);
    if (errno || end == s || (*end != 'x' && *end != 'X') || !isdigit((unsigned char)end[1]))
        return -1;
    const char *h_s = end + 1;
    unsigned long h = strtoul(h_s, &end, 10);
    if (errno || *end || w < 1 || h < 1 || w > 16384 || h > 16384) return -1;
    out->width = (uint32_t)w;
    out->height = (uint32_t)h;
    return 0;
}

static int same_ascii_nocase(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

static int parse_tables(const char *s, unsigned *out, FILE *err)
{
    unsigned bits = 0;
    char buf[256];
    if (strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        size_t i = 0;
        while (i < bench_table_count && !same_ascii_nocase(tok, bench_tables[i].id)) i++;
        if (i == bench_table_count) {
            fprintf(err,
                    "treetrace bench: --only: unknown table '%s' (tables: F1 F2 F3 F4 F5 "
                    "H1 H3 E D)\n",
                    tok);
            return -1;
        }
        bits |= bench_tables[i].bit;
    }
    if (!bits) {
        fprintf(err, "treetrace bench: --only: no table named\n");
        return -1;
    }
    *out = bits;
    return 0;
}

static int parse_dmins(const char *s, bench_options *o, FILE *err)
{
    char buf[256];
    if (strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        int a, b;
        char *dash = strchr(tok, '-');
        if (dash) {
            *dash = '\0';
            if (parse_int(tok, 1, 32, &a) || parse_int(dash + 1, 1, 32, &b) || b < a) goto bad;
        } else {
            if (parse_int(tok, 1, 32, &a)) goto bad;
            b = a;
        }
        for (int d = a; d <= b; d++) {
            if (n == (int)(sizeof o->dmins / sizeof o->dmins[0])) goto bad;
            o->dmins[n++] = d;
        }
    }
    if (n == 0) goto bad;
    o->dmin_count = n;
    return 0;
bad:
    fprintf(err,
            "treetrace bench: --dmin: expected values 1..32 like 1-12 or 1,2,4,8, got "
            "'%s'\n",
            s);
    return -1;
}

static int parse_scene_names(const char *s, bench_options *o)
{
    for (size_t i = 0; i < o->scene_name_count; i++) free(o->scene_names[i]);
    free(o->scene_names);
    o->scene_names = NULL;
    o->scene_name_count = 0;
    size_t n = 1;
    for (const char *p = s; *p; p++) n += *p == ',';
    o->scene_names = calloc(n, sizeof *o->scene_names);
    if (!o->scene_names) return -1;
    const char *p = s;
    while (*p) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len) {
            char *name = malloc(len + 1);
            if (!name) return -1;
            memcpy(name, p, len);
            name[len] = '\0';
            o->scene_names[o->scene_name_count++] = name;
        }
        p += len + (e ? 1 : 0);
    }
    return o->scene_name_count ? 0 : -1;
}

void bench_options_free(bench_options *o)
{
    for (size_t i = 0; i < o->scene_name_count; i++) free(o->scene_names[i]);
    free(o->scene_names);
    o->scene_names = NULL;
    o->scene_name_count = 0;
}

/* Options that take a value. */
static const char *const with_value[] = {"--scenes",     "--out",     "--threads", "--repeat",
                                         "--budget",     "--only",    "--scene",   "--size",
                                         "--rtree-size", "--kd-size", "--dmin",
                                         "--device",     "--builds",  "--ao",
                                         "--frames"};

int bench_parse_options(int argc, char **argv, bench_options *out, FILE *err)
{
    int quick = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
            bench_print_help(stdout);
            return 1;
        }
        if (strcmp(argv[i], "--quick") == 0) quick = 1;
    }
    set_defaults(out, quick);
    int explicit_views = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        char name[32];
        const char *value = NULL;
        const char *eq = strchr(arg, '=');
        if (strncmp(arg, "--", 2) == 0 && eq && (size_t)(eq - arg) < sizeof name) {
            memcpy(name, arg, (size_t)(eq - arg));
            name[eq - arg] = '\0';
            value = eq + 1;
        } else {
            snprintf(name, sizeof name, "%s", arg);
        }
        int needs = 0;
        for (size_t k = 0; k < sizeof with_value / sizeof with_value[0]; k++)
            if (strcmp(name, with_value[k]) == 0) needs = 1;
        if (needs && !value) {
            if (i + 1 >= argc) {
                fprintf(err, "treetrace bench: %s needs a value (see --help)\n", name);
                goto fail;
            }
            value = argv[++i];
        } else if (!needs && value) {
            fprintf(err, "treetrace bench: %s takes no value\n", name);
            goto fail;
        }
        if (strcmp(name, "--quick") == 0) {
            /* handled above */
        } else if (strcmp(name, "--scenes") == 0) {
            out->scenes_dir = value;
        } else if (strcmp(name, "--out") == 0) {
            out->out_dir = value;
        } else if (strcmp(name, "--threads") == 0) {
            if (parse_int(value, 1, 4096, &out->threads)) {
                fprintf(err, "treetrace bench: --threads: expected a count 1..4096, got '%s'\n",
                        value);
                goto fail;
            }
        } else if (strcmp(name, "--repeat") == 0) {
            if (parse_int(value, 1, 1000, &out->repeat)) {
                fprintf(err, "treetrace bench: --repeat: expected a count 1..1000, got '%s'\n",
                        value);
                goto fail;
            }
            out->rounds = out->repeat;
        } else if (strcmp(name, "--builds") == 0) {
            if (parse_int(value, 1, 100, &out->builds)) {
                fprintf(err, "treetrace bench: --builds: expected a count 1..100, got '%s'\n",
                        value);
                goto fail;
            }
        } else if (strcmp(name, "--ao") == 0) {
            if (parse_int(value, 1, 64, &out->ao_samples)) {
                fprintf(err, "treetrace bench: --ao: expected rays per hit 1..64, got '%s'\n",
                        value);
                goto fail;
            }
        } else if (strcmp(name, "--budget") == 0) {
            char *end;
            errno = 0;
            double b = strtod(value, &end);
            if (errno || end == value || *end || !(b > 0.0 && b < 1e6)) {
                fprintf(err, "treetrace bench: --budget: expected seconds > 0, got '%s'\n", value);
                goto fail;
            }
            out->budget_s = b;
        } else if (strcmp(name, "--only") == 0) {
            if (parse_tables(value, &out->tables, err)) goto fail;
        } else if (strcmp(name, "--scene") == 0) {
            if (parse_scene_names(value, out)) {
                fprintf(err,
                        "treetrace bench: --scene: expected names like bunny,sibenik, got "
                        "'%s'\n",
                        value);
                goto fail;
            }
        } else if (strcmp(name, "--size") == 0 || strcmp(name, "--rtree-size") == 0 ||
                   strcmp(name, "--kd-size") == 0) {
            bench_size sz;
            if (parse_size(value, &sz)) {
                fprintf(err, "treetrace bench: %s: expected WxH like 800x600, got '%s'\n", name,
                        value);
                goto fail;
            }
            if (strcmp(name, "--kd-size") != 0) out->rtree_size = sz;
            if (strcmp(name, "--rtree-size") != 0) out->kd_size = sz;
        } else if (strcmp(name, "--dmin") == 0) {
            if (parse_dmins(value, out, err)) goto fail;
        } else if (strcmp(name, "--all-views") == 0 || strcmp(name, "--first-view") == 0) {
            if (explicit_views && out->all_views != (strcmp(name, "--all-views") == 0)) {
                fprintf(err, "treetrace bench: --all-views and --first-view contradict\n");
                goto fail;
            }
            explicit_views = 1;
            out->all_views = strcmp(name, "--all-views") == 0;
        } else if (strcmp(name, "--frames") == 0) {
            if (parse_int(value, 1, 100000, &out->frames)) {
                fprintf(err, "treetrace bench: --frames: expected a count 1..100000, got '%s'\n",
                        value);
                goto fail;
            }
        } else if (strcmp(name, "--no-heatmaps") == 0) {
            out->heatmaps = 0;
        } else if (strcmp(name, "--device") == 0) {
            if (strcmp(value, "cpu") == 0) {
                out->device = TT_DEVICE_CPU;
            } else if (strcmp(value, "gpu") == 0) {
                out->device = TT_DEVICE_GPU;
            } else {
                fprintf(err, "treetrace bench: --device: expected cpu or gpu, got '%s'\n", value);
                goto fail;
            }
        } else {
            fprintf(err, "treetrace bench: unknown option '%s' (see --help)\n", arg);
            goto fail;
        }
    }
    return 0;
fail:
    bench_options_free(out);
    return 2;
}
