/* `treetrace bench`: options -> scenes -> matrix -> runs -> results.csv,
 * report.md and the figures (python3 -m treetrace.plots). */
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench/bench.h"
#include "bench/bench_yard.h"
#include "mpi/mpi.h"

static int run_bench(const bench_options *o, FILE *err)
{
    char found[4096];
    const char *dir = o->scenes_dir;
    if (!dir) {
        dir = bench_default_scenes_dir(found, sizeof found);
        if (!dir) {
            fprintf(err, "treetrace bench: no scenes folder found next to the executable or the "
                         "source (../shared/scenes); give --scenes DIR\n");
            return 1;
        }
    } else {
        char tsv[4200];
        snprintf(tsv, sizeof tsv, "%s/scenes.tsv", dir);
        if (access(tsv, R_OK) != 0) {
            fprintf(err, "treetrace bench: --scenes %s: no readable scenes.tsv there\n", dir);
            return 2;
        }
    }
    char out_buf[256];
    const char *out = o->out_dir;
    if (!out) {
        time_t now = time(NULL);
        struct tm tm;
        localtime_r(&now, &tm);
        strftime(out_buf, sizeof out_buf, "bench/results-%Y-%m-%d", &tm);
        out = out_buf;
    }

    tt_context_options co;
    tt_context_options_default(&co);
    co.threads = o->threads;
    tt_context *ctx = NULL;
    if (tt_context_create(&co, &ctx) != TT_OK) {
        fprintf(err, "treetrace bench: cannot create a context\n");
        return 1;
    }
    int rc = 1;
    bench_scene_list scenes;
    /* before any work (even the output folder): a missing GPU is known at once */
    if (tt_device_check(ctx, o->device) != TT_OK) {
        fprintf(err, "treetrace bench: %s\n", tt_context_last_error(ctx));
        tt_context_destroy(ctx);
        return 1;
    }
    if (bench_mkdirs(out) != 0) {
        fprintf(err, "treetrace bench: cannot create the output folder %s\n", out);
        tt_context_destroy(ctx);
        return 1;
    }
    bench_matrix m = {0};
    bench_results res = {0};
    int sr = bench_scenes_read(ctx, dir, o, &scenes, err);
    if (sr != 0) {
        rc = sr == -2 ? 2 : 1;
        goto done_ctx;
    }
    if (o->tables & BENCH_D) { /* table D runs frame sequences of its own */
        rc = bench_dynamic_run(ctx, o, &scenes, out, err);
        if (rc != 0 || !(o->tables & ~(unsigned)BENCH_D)) goto done_scenes;
        rc = 1;
    }
    if (bench_matrix_make(o, &scenes, &m) != 0) {
        fprintf(err, "treetrace bench: out of memory\n");
        goto done_scenes;
    }
    bench_yard yard;
    memset(&yard, 0, sizeof yard);
    /* the papers' tables (renders); none with --only E */
    if (m.count && bench_run_all(ctx, o, &scenes, &m, out, &res, err) != 0) goto done_matrix;
    if (o->ranks > 1) { /* MPI: rank 0 gathers every rank's runs and writes */
        if (cli_mpi_bench_gather(&m, &res) != 0) goto done_results;
        if (o->rank != 0) {
            rc = 0;
            goto done_results;
        }
    }
    /* the engine table: batch calls against Embree's own loops, not renders
     * (under mpirun rank 0 runs it alone, after the others' scenes are in) */
    if ((o->tables & BENCH_E1) && bench_yard_run(ctx, o, &scenes, &yard, err) != 0)
        goto done_results;
    res.engine = (o->tables & BENCH_E1) ? &yard : NULL;
    if (!m.count) res.threads = yard.threads;
    res.total_s += yard.total_s;
    char path[4200];
    int bad = 0;
    if (m.count) {
        snprintf(path, sizeof path, "%s/results.csv", out);
        bad |= bench_write_csv(path, &scenes, &m, &res, err);
    }
    if (res.engine) {
        snprintf(path, sizeof path, "%s/engine.csv", out);
        bad |= bench_yard_write_csv(path, &scenes, &yard, err);
    }
    bad |= bench_write_report(ctx, out, o, &scenes, &m, &res, err);
    if (!bad) bad |= bench_figures_draw(out, err);
    if (!bad) {
        size_t failed = 0;
        for (size_t i = 0; i < res.count; i++)
            failed += !res.items[i].ok && strcmp(res.items[i].error, "not in this build") != 0;
        size_t engine_failed = 0;
        for (size_t i = 0; i < yard.count; i++) {
            size_t nc;
            bench_engine_configs(&nc);
            for (size_t c = 0; c < nc; c++) engine_failed += !yard.views[i].configs[c].ok;
        }
        fprintf(err, "treetrace bench: wrote %s/ (%s%sreport.md)", out,
                m.count ? "results.csv, " : "", res.engine ? "engine.csv, " : "");
        if (failed) fprintf(err, " (%zu runs failed; see the csv's error column)", failed);
        if (engine_failed)
            fprintf(err, " (%zu engine-table measurements failed; see engine.csv)", engine_failed);
        fputc('\n', err);
        rc = failed || engine_failed ? 1 : 0;
    }
done_results:
    bench_yard_free(&yard);
    bench_results_free(&res);
done_matrix:
    bench_matrix_free(&m);
done_scenes:
    bench_scenes_free(&scenes);
done_ctx:
    tt_context_destroy(ctx);
    return rc;
}

int tt_cli_bench(int argc, char **argv)
{
    bench_options o;
    int rc = bench_parse_options(argc, argv, &o, stderr);
    if (rc == 1) return 0; /* --help */
    if (rc != 0) return 2;
    if (cli_mpi_wanted(0)) { /* under mpirun: the matrix across ranks */
        if (cli_mpi_bench_begin(&o.rank, &o.ranks) != 0) {
            bench_options_free(&o);
            return 2;
        }
        rc = cli_mpi_bench_end(run_bench(&o, stderr));
        bench_options_free(&o);
        return rc;
    }
    rc = run_bench(&o, stderr);
    bench_options_free(&o);
    return rc;
}
