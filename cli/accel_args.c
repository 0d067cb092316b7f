#include "accel_args.h"

#include <string.h>

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

/* Names in enum order, for parsing and for output alike. */
static const char *const strategies[] = {"min-volume", "min-surface", "min-overlap", "rstar",
                                         "rstar-surface", "rrstar"};
static const char *const splits[] = {"rstar", "quadratic"};
static const char *const rtree_builds[] = {"insert", "str", "hilbert", "sah"};
static const char *const rtree_traversals[] = {"auto", "stackless", "ordered", "stack"};
static const char *const rtree_layouts[] = {"complete", "compact"};
static const char *const kd_builders[] = {"nlogn", "nlog2n", "binned"};
static const char *const kd_traversals[] = {"htr", "btr", "sltr", "seq"};
static const char *const on_off[] = {"off", "on"};
static const char *const reinsert_modes[] = {"close", "far"};
static const char *const shadow_hints[] = {"primary", "caster"};
static const char *const embree_qualities[] = {"high", "medium", "low"};

void cli_accel_args_init(cli_accel_args *x)
{
    memset(x, 0, sizeof *x);
    tt_build_options_default(&x->build);
}

static int is_registered(const char *name)
{
    for (const char *const *n = tt_accel_names(); *n; n++)
        if (strcmp(*n, name) == 0) return 1;
    return 0;
}

static int parse_rtree(cli_args *a, cli_accel_args *x, const char *opt, const char *v)
{
    const char *cmd = a->cmd;
    tt_rtree_options *r = &x->build.rtree;
    int k, st;
    /* the options of insertion, refused with a bulk loader (finish) */
    static const char *const insert_only[] = {"--strategy", "--reinsert", "--reinsert-fraction",
                                              "--reinsert-mode", "--split"};
    for (int i = 0; i < COUNT(insert_only) && !x->insert_opt; i++)
        if (strcmp(opt, insert_only[i]) == 0) x->insert_opt = opt;
    if (strcmp(opt, "--build") == 0) {
        st = cli_parse_choice(cmd, opt, v, rtree_builds, COUNT(rtree_builds), &k);
        r->build = (tt_rtree_build)k;
    } else if (strcmp(opt, "--strategy") == 0) {
        st = cli_parse_choice(cmd, opt, v, strategies, COUNT(strategies), &k);
        r->strategy = (tt_rtree_strategy)k;
    } else if (strcmp(opt, "--m") == 0) {
        st = cli_parse_int(cmd, opt, v, 2, 8, &r->m);
        x->m_given = 1;
    } else if (strcmp(opt, "--M") == 0) {
        st = cli_parse_int(cmd, opt, v, 4, 16, &r->M);
        x->M_given = 1;
    } else if (strcmp(opt, "--reinsert") == 0) {
        st = cli_parse_choice(cmd, opt, v, on_off, COUNT(on_off), &r->reinsert);
    } else if (strcmp(opt, "--reinsert-fraction") == 0) {
        st = cli_parse_float(cmd, opt, v, 0.0, 1, 1.0, 1, &r->reinsert_fraction);
    } else if (strcmp(opt, "--layout") == 0) {
        st = cli_parse_choice(cmd, opt, v, rtree_layouts, COUNT(rtree_layouts), &k);
        r->layout = (tt_rtree_layout)k;
    } else if (strcmp(opt, "--split-budget") == 0) {
        st = cli_parse_float(cmd, opt, v, 0.0, 0, 4.0, 0, &r->split_budget);
    } else if (strcmp(opt, "--reinsert-mode") == 0) {
        st = cli_parse_choice(cmd, opt, v, reinsert_modes, COUNT(reinsert_modes), &r->reinsert_far);
    } else {
        st = cli_parse_choice(cmd, opt, v, splits, COUNT(splits), &k);
        r->split = (tt_rtree_split)k;
    }
    if (!x->rtree_opt) x->rtree_opt = opt;
    if (!x->rtree_opt_not_M && strcmp(opt, "--M") != 0) x->rtree_opt_not_M = opt;
    return st;
}

static int parse_kdtree(cli_args *a, cli_accel_args *x, const char *opt, const char *v)
{
    const char *cmd = a->cmd;
    tt_kdtree_options *kd = &x->build.kdtree;
    int k, st;
    if (strcmp(opt, "--kd-build") == 0) {
        st = cli_parse_choice(cmd, opt, v, kd_builders, COUNT(kd_builders), &k);
        kd->builder = (tt_kd_builder)k;
    } else if (strcmp(opt, "--dmin") == 0) {
        if (strcmp(v, "none") == 0) {
            kd->dmin = -1;
            st = CLI_OK;
        } else if (strcmp(v, "auto") == 0) {
            kd->dmin = 0;
            st = CLI_OK;
        } else {
            st = cli_parse_int(cmd, opt, v, 1, 64, &kd->dmin);
        }
    } else if (strcmp(opt, "--ct") == 0) {
        st = cli_parse_float(cmd, opt, v, 0.0, 1, 1e6, 0, &kd->cost_traversal);
    } else if (strcmp(opt, "--ci") == 0) {
        st = cli_parse_float(cmd, opt, v, 0.0, 1, 1e6, 0, &kd->cost_intersect);
    } else if (strcmp(opt, "--empty-bonus") == 0) {
        st = cli_parse_float(cmd, opt, v, 0.0, 0, 1.0, 1, &kd->empty_bonus);
    } else if (strcmp(opt, "--max-depth") == 0) {
        st = cli_parse_int(cmd, opt, v, 0, 64, &kd->max_depth);
    } else {
        st = cli_parse_choice(cmd, opt, v, shadow_hints, COUNT(shadow_hints),
                              &kd->shadow_caster_hint);
    }
    if (!x->kd_opt) x->kd_opt = opt;
    return st;
}

int cli_accel_args_parse(cli_args *a, cli_accel_args *x, int *taken)
{
    static const char *const rtree_opts[] = {"--build", "--layout", "--strategy", "--m", "--M",
                                             "--reinsert", "--reinsert-fraction", "--reinsert-mode",
                                             "--split", "--split-budget"};
    static const char *const kd_opts[] = {"--kd-build", "--dmin", "--ct", "--ci",
                                          "--empty-bonus", "--max-depth", "--shadow-hint"};
    *taken = 1;
    if (cli_is(a, "--accel")) {
        x->accel = cli_value(a, "--accel");
        return x->accel ? CLI_OK : CLI_USAGE;
    }
    if (cli_is(a, "--traversal")) {
        x->traversal = cli_value(a, "--traversal");
        return x->traversal ? CLI_OK : CLI_USAGE;
    }
    if (cli_is(a, "--embree-quality")) {
        const char *v = cli_value(a, "--embree-quality");
        if (!v) return CLI_USAGE;
        int k;
        int st = cli_parse_choice(a->cmd, "--embree-quality", v, embree_qualities,
                                  COUNT(embree_qualities), &k);
        x->build.embree.quality = (tt_embree_quality)k;
        x->embree_opt = "--embree-quality";
        return st;
    }
    if (cli_is(a, "--isa")) {
        const char *v = cli_value(a, "--isa");
        if (!v) return CLI_USAGE;
        if (!tt_isa_from_name(v, &x->build.isa))
            return cli_usage_error(a->cmd,
                                   "option --isa: unknown value '%s' (auto, scalar, sse4.2, avx2, "
                                   "avx512)", v);
        return CLI_OK;
    }
    for (int k = 0; k < COUNT(rtree_opts); k++) {
        if (cli_is(a, rtree_opts[k])) {
            const char *v = cli_value(a, rtree_opts[k]);
            return v ? parse_rtree(a, x, rtree_opts[k], v) : CLI_USAGE;
        }
    }
    for (int k = 0; k < COUNT(kd_opts); k++) {
        if (cli_is(a, kd_opts[k])) {
            const char *v = cli_value(a, kd_opts[k]);
            return v ? parse_kdtree(a, x, kd_opts[k], v) : CLI_USAGE;
        }
    }
    *taken = 0;
    return CLI_OK;
}

int cli_accel_args_finish(const char *cmd, cli_accel_args *x)
{
    if (!x->accel) x->accel = is_registered("rtree") ? "rtree" : "bruteforce";
    /* "embree" goes through to the library, whose message says how to get it. */
    if (!is_registered(x->accel) && strcmp(x->accel, "embree") != 0) {
        char list[256] = "";
        for (const char *const *n = tt_accel_names(); *n; n++) {
            if (list[0]) strncat(list, ", ", sizeof list - strlen(list) - 1);
            strncat(list, *n, sizeof list - strlen(list) - 1);
        }
        return cli_usage_error(cmd, "option --accel: unknown structure '%s' (this build has: %s)",
                               x->accel, list);
    }
    x->build.accel = x->accel;
    int rtree = strcmp(x->accel, "rtree") == 0, kdtree = strcmp(x->accel, "kdtree") == 0;
    const int wbvh = strcmp(x->accel, "wbvh") == 0; /* takes --M (its width) */
    if (wbvh ? x->rtree_opt_not_M != NULL : x->rtree_opt && !rtree)
        return cli_usage_error(cmd, "option %s applies to --accel rtree, not %s",
                               wbvh ? x->rtree_opt_not_M : x->rtree_opt, x->accel);
    if (x->embree_opt && strcmp(x->accel, "embree") != 0)
        return cli_usage_error(cmd, "option %s applies to --accel embree, not %s", x->embree_opt,
                               x->accel);
    if (x->kd_opt && !kdtree)
        return cli_usage_error(cmd, "option %s applies to --accel kdtree, not %s", x->kd_opt,
                               x->accel);
    if (x->traversal) {
        int k;
        if (rtree) {
            if (cli_parse_choice(cmd, "--traversal", x->traversal, rtree_traversals,
                                 COUNT(rtree_traversals), &k) != CLI_OK)
                return CLI_USAGE;
            x->build.rtree.traversal = (tt_rtree_traversal)k;
        } else if (kdtree) {
            if (cli_parse_choice(cmd, "--traversal", x->traversal, kd_traversals,
                                 COUNT(kd_traversals), &k) != CLI_OK)
                return CLI_USAGE;
            x->build.kdtree.traversal = (tt_kd_traversal)k;
        } else {
            return cli_usage_error(cmd, "option --traversal applies to rtree and kdtree, not %s",
                                   x->accel);
        }
    }
    if (kdtree && x->build.kdtree.shadow_caster_hint && x->build.kdtree.traversal == TT_KD_HTR)
        return cli_usage_error(cmd,
                               "option --shadow-hint caster needs --traversal btr, sltr or seq "
                               "(htr starts every ray at the root)");
    const tt_rtree_options *r = &x->build.rtree;
    const int M = tt_rtree_max_entries(r);
    if (rtree && 2 * r->m > M)
        return cli_usage_error(cmd, "options --m %d and --M %d: the R-tree needs 2 <= m <= M/2",
                               r->m, M);
    if (rtree && r->build != TT_RTREE_BUILD_INSERT && x->insert_opt)
        return cli_usage_error(cmd, "option %s applies to --build insert, not %s", x->insert_opt,
                               rtree_builds[r->build]);
    if (rtree && r->reinsert_fraction * (float)(M + 1) < 1.0f)
        return cli_usage_error(cmd,
                               "option --reinsert-fraction %g: with --M %d it reinserts less than "
                               "one entry (needs fraction * (M + 1) >= 1)",
                               r->reinsert_fraction, M);
    return CLI_OK;
}

void cli_accel_args_emit(cli_emit *e, const tt_build_options *b)
{
    emit_str(e, "isa_requested", tt_isa_name(b->isa));
    if (strcmp(b->accel, "rtree") == 0) {
        const tt_rtree_options *r = &b->rtree;
        emit_str(e, "build", rtree_builds[r->build]);
        emit_str(e, "layout", rtree_layouts[r->layout]);
        emit_int(e, "m", r->m);
        emit_int(e, "M", tt_rtree_max_entries(r));
        if (r->build == TT_RTREE_BUILD_INSERT) { /* the others do not use these */
            emit_str(e, "strategy", strategies[r->strategy]);
            emit_str(e, "reinsert", on_off[r->reinsert != 0]);
            emit_num(e, "reinsert_fraction", r->reinsert_fraction);
            emit_str(e, "reinsert_mode", reinsert_modes[r->reinsert_far != 0]);
            emit_str(e, "split", splits[r->split]);
        }
        emit_str(e, "traversal", rtree_traversals[r->traversal]);
    } else if (strcmp(b->accel, "kdtree") == 0) {
        const tt_kdtree_options *kd = &b->kdtree;
        emit_str(e, "kd_build", kd_builders[kd->builder]);
        const int dmin = tt_kdtree_dmin(kd);
        if (dmin < 0) emit_str(e, "dmin", "none");
        else emit_int(e, "dmin", dmin);
        emit_num(e, "ct", kd->cost_traversal);
        emit_num(e, "ci", kd->cost_intersect);
        emit_num(e, "empty_bonus", kd->empty_bonus);
        emit_int(e, "max_depth", kd->max_depth);
        emit_str(e, "traversal", kd_traversals[kd->traversal]);
        emit_str(e, "shadow_hint", shadow_hints[kd->shadow_caster_hint != 0]);
    } else if (strcmp(b->accel, "embree") == 0) {
        emit_str(e, "embree_quality", embree_qualities[b->embree.quality]);
    } else if (strcmp(b->accel, "wbvh") == 0) {
        emit_int(e, "M", b->rtree.M ? b->rtree.M : 16);
    }
}

void cli_accel_args_help(FILE *out)
{
    fprintf(out,
            "structure:\n"
            "  --accel NAME             bruteforce, rtree, kdtree, wbvh, embree (default: rtree if\n"
            "                           built; wbvh: the wide BVH, takes --M)\n"
            "  --isa NAME               SIMD kernels: auto|scalar|sse4.2|avx2|avx512 (default\n"
            "                           auto: the best this CPU runs; output key isa)\n"
            "  --traversal NAME         rtree: auto|stackless|ordered|stack (default auto);\n"
            "                           kdtree: htr|btr|sltr|seq (default htr)\n"
            "Embree (--accel embree):\n"
            "  --embree-quality high|medium|low  BVH build quality (default high, as the\n"
            "                           papers' tables compare; medium is Embree's usual)\n"
            "R-tree (--accel rtree):\n"
            "  --build NAME             insert|str|hilbert|sah (default sah): insertion\n"
            "                           (Feldmann 2015) or a bulk loader for static scenes:\n"
            "                           STR tiles, Hilbert-curve order, or top-down by the\n"
            "                           surface area heuristic; the options below down to\n"
            "                           --split apply to insert only\n"
            "  --layout complete|compact  complete: the paper's level-order array of the\n"
            "                           complete M-ary tree (empty slots included); compact:\n"
            "                           real nodes only, child boxes tested by SIMD (--isa),\n"
            "                           triangles in 8-wide blocks; its traversals: stack\n"
            "                           (= auto = ordered: near-to-far) or stackless (the\n"
            "                           GPU's) (default compact)\n"
            "  --strategy NAME          min-volume|min-surface|min-overlap|rstar|rstar-surface|\n"
            "                           rrstar (the RR*-tree's choice, Beckmann & Seeger 2009)\n"
            "                           (default rstar-surface)\n"
            "  --m N, --M N             minimum and maximum entries a node, 2 <= m <= M/2,\n"
            "                           M <= 16 (default m 2; M 16 in the compact layout,\n"
            "                           4 in the complete one, Feldmann's)\n"
            "  --reinsert on|off        R* forced reinsertion (default on)\n"
            "  --reinsert-fraction F    fraction of M+1 entries reinserted, in (0, 1) (default 0.3)\n"
            "  --reinsert-mode far|close  reinsert the farthest or closest first (default far)\n"
            "  --split rstar|quadratic  node split algorithm (default rstar)\n"
            "  --split-budget F         sah + compact: early split clipping, cutting long\n"
            "                           thin triangles into pieces with tighter boxes, up\n"
            "                           to F x the triangles extra references, in [0, 4];\n"
            "                           such a tree is rebuilt on updates (default 0: off)\n"
            "kd-tree (--accel kdtree):\n"
            "  --kd-build nlogn|nlog2n|binned  SAH builder: exact (O(N log N) or O(N log^2 N),\n"
            "                           the same tree) or binned (approximate, faster); all\n"
            "                           build in parallel with the threads (default nlogn)\n"
            "  --dmin N|none|auto       sparse boxes every N levels, or none (default auto:\n"
            "                           none for htr, which reads no boxes, else 4)\n"
            "  --ct F, --ci F           SAH traversal and intersection costs (default 1, 0.2)\n"
            "  --empty-bonus F          SAH bonus for cutting off empty space, in [0, 1):\n"
            "                           such a split costs (1 - F) x (default 0.2)\n"
            "  --max-depth N            maximum depth, 0 = automatic 8 + 1.3 log2 N (default 0)\n"
            "  --shadow-hint primary|caster  shadow rays start at the primary ray's end node;\n"
            "                           caster: each first searches the box of the tile's\n"
            "                           last shadow caster (default primary; caster needs\n"
            "                           --traversal btr, sltr or seq)\n");
}
