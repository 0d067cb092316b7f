/* Progress on stderr: a bar redrawn in place when stderr is a terminal,
 * one plain line per run otherwise (logs, CI). */
#include <time.h>
#include <unistd.h>

#include "bench/bench.h"

double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void bench_progress_start(bench_progress *p, FILE *f, size_t total)
{
    p->f = f;
    p->tty = isatty(fileno(f));
    p->total = total;
    p->done = 0;
    p->t0 = bench_now();
    fprintf(f, "treetrace bench: %zu runs\n", total);
}

void bench_progress_step(bench_progress *p, const char *what)
{
    p->done++;
    double el = bench_now() - p->t0;
    if (p->tty) {
        enum { W = 30 };
        int fill = p->total ? (int)((double)W * (double)p->done / (double)p->total) : W;
        char bar[W + 1];
        for (int i = 0; i < W; i++) bar[i] = i < fill ? '#' : '.';
        bar[W] = '\0';
        /* \033[K clears the rest of the line; the label is cut to fit 100 cols */
        fprintf(p->f, "\r\033[K[%s] %zu/%zu %5.0fs %.50s", bar, p->done, p->total, el, what);
        fflush(p->f);
    } else {
        fprintf(p->f, "[%zu/%zu %.0fs] %s\n", p->done, p->total, el, what);
    }
}

void bench_progress_end(bench_progress *p)
{
    if (p->tty) fputc('\n', p->f);
    fprintf(p->f, "treetrace bench: %zu runs in %.1f s\n", p->done, bench_now() - p->t0);
}
