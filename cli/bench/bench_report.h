/* Shared by the report's writers (bench_report*.c): where the report goes
 * and how a result is looked up and printed in a table cell. */
#ifndef TT_CLI_BENCH_REPORT_H
#define TT_CLI_BENCH_REPORT_H

#include "bench/bench.h"

typedef struct bench_report {
    FILE *f;
    tt_context *ctx;
    const char *out_dir;
    const bench_options *o;
    const bench_scene_list *s;
    const bench_matrix *m;
    const bench_results *r;
    FILE *err;
} bench_report;

/* The result of the run with these fields on the CPU; NULL if the matrix
 * has none. */
const bench_result *bench_report_find(const bench_report *rp, size_t scene, size_t view,
                                      bench_size size, tt_build_options build, bench_rays rays);
/* The same on `device`. */
const bench_result *bench_report_find_on(const bench_report *rp, size_t scene, size_t view,
                                         bench_size size, tt_build_options build, bench_rays rays,
                                         tt_device device);
/* "0.412 s", or why there is no number: "n/a" (structure not in this
 * build), "error", "-" (not run). */
void bench_cell_time(FILE *f, const bench_result *r);
/* "0.0123 s", "1.57 s": three significant digits below a second. */
void bench_format_seconds(char *buf, size_t size, double s);
/* The build time of the run's structure, same conventions. */
void bench_cell_build(FILE *f, const bench_result *r);
/* Our median time over Embree's in the same run ("3.1x"), or "-". */
void bench_cell_vs_embree(FILE *f, const bench_result *r);
/* a / b as "1.23" when both results have times, else "-". */
void bench_cell_ratio(FILE *f, const bench_result *a, const bench_result *b);
/* v printed with fmt, "-" when v is NaN (no number). */
void bench_cell_num(FILE *f, double v, const char *fmt);
/* A paper's value ("1.95 s"), "-" when the paper has none. */
void bench_cell_paper(FILE *f, double v);
int bench_result_ok(const bench_result *r);

void bench_report_feldmann(const bench_report *rp);
void bench_report_havran(const bench_report *rp);
/* The engine table (BENCH_E1). */
void bench_report_engine(const bench_report *rp);
/* The GPU section (--device gpu); nothing without GPU runs. */
void bench_report_gpu(const bench_report *rp);

#endif
