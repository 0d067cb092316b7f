/* The machine a benchmark ran on, for the report: CPU model (from
 * /proc/cpuinfo), online CPUs, the compiler this was built with, the date
 * and Embree's version when it is compiled in. */
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench/bench.h"

static void cpu_model(char *buf, size_t size)
{
    snprintf(buf, size, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        /* x86: "model name"; some ARM kernels: "Processor" or "Hardware" */
        if (strncmp(line, "model name", 10) == 0 || strncmp(line, "Processor", 9) == 0) {
            char *colon = strchr(line, ':');
            if (!colon) continue;
            colon++;
            while (*colon == ' ' || *colon == '\t') colon++;
            size_t n = strcspn(colon, "\n");
            snprintf(buf, size, "%.*s", (int)n, colon);
            break;
        }
    }
    fclose(f);
}

void bench_machine_read(bench_machine *m)
{
    memset(m, 0, sizeof *m);
    cpu_model(m->cpu, sizeof m->cpu);
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    m->cores = n > 0 ? (int)n : 0;
#if defined(__clang__)
    snprintf(m->compiler, sizeof m->compiler, "clang %s", __clang_version__);
#elif defined(__GNUC__)
    snprintf(m->compiler, sizeof m->compiler, "gcc %s", __VERSION__);
#else
    snprintf(m->compiler, sizeof m->compiler, "unknown C compiler");
#endif
    time_t now = time(NULL);
    struct tm tm;
    localtime_r(&now, &tm);
    strftime(m->date, sizeof m->date, "%Y-%m-%d %H:%M:%S %z", &tm);
#ifdef TT_HAVE_EMBREE
    snprintf(m->embree, sizeof m->embree, "Embree 3 (compiled in)");
#else
    snprintf(m->embree, sizeof m->embree, "not compiled in");
#endif
}
