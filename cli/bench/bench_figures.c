/* The report's figures: drawn by the Python package's plotting module
 * (python3 -m treetrace.plots OUT, matplotlib; PDF + PNG) from the CSVs
 * the bench wrote. Python and matplotlib are optional: without them the
 * report says how to draw the figures later, and the run still succeeds.
 * The package is taken from the source tree next to the executable (or the
 * one this was compiled from), else from wherever python3 finds it; the
 * shared library next to the executable is handed to it, as the tests do. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench/bench.h"

static int is_file(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0 && S_ISREG(st.st_mode);
}

/* The executable's folder ("" when unknown). */
static void exe_dir(char *buf, size_t size)
{
    ssize_t n = readlink("/proc/self/exe", buf, size - 1);
    buf[n > 0 ? n : 0] = '\0';
    char *slash = strrchr(buf, '/');
    if (slash) *slash = '\0';
    else buf[0] = '\0';
}

/* The folder holding treetrace/plots/ in a source tree, or "" (installed). */
static void package_dir(char *buf, size_t size)
{
    char dir[PATH_MAX], probe[PATH_MAX + 64];
    exe_dir(dir, sizeof dir);
    const char *rel[] = {"/../python", "/../../python"};
    for (size_t i = 0; dir[0] && i < 2; i++) {
        snprintf(probe, sizeof probe, "%s%s/treetrace/plots/__init__.py", dir, rel[i]);
        if (is_file(probe)) {
            snprintf(buf, size, "%s%s", dir, rel[i]);
            return;
        }
    }
#ifdef TT_SOURCE_DIR
    snprintf(probe, sizeof probe, "%s/python/treetrace/plots/__init__.py", TT_SOURCE_DIR);
    if (is_file(probe)) {
        snprintf(buf, size, "%s/python", TT_SOURCE_DIR);
        return;
    }
#endif
    buf[0] = '\0';
}

/* Runs argv with the package's environment; quiet: output to /dev/null.
 * Returns the exit status (127: could not run). */
static int run(char *const argv[], int quiet)
{
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) return 127;
    if (pid == 0) {
        char pkg[PATH_MAX], dir[PATH_MAX], lib[PATH_MAX + 32];
        package_dir(pkg, sizeof pkg);
        if (pkg[0]) {
            const char *old = getenv("PYTHONPATH");
            char path[2 * PATH_MAX + 2];
            snprintf(path, sizeof path, "%s%s%s", pkg, old && *old ? ":" : "", old ? old : "");
            setenv("PYTHONPATH", path, 1);
        }
        exe_dir(dir, sizeof dir);
        snprintf(lib, sizeof lib, "%s/libtreetrace.so.0", dir);
        if (!getenv("TREETRACE_LIBRARY") && dir[0] && is_file(lib)) setenv("TREETRACE_LIBRARY", lib, 1);
        setenv("PYTHONDONTWRITEBYTECODE", "1", 0);
        setenv("MPLBACKEND", "Agg", 0);
        if (quiet) {
            FILE *null = freopen("/dev/null", "w", stdout);
            if (null) (void)dup2(fileno(stdout), 2);
        }
        execvp(argv[0], argv);
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return 127;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 127;
}

static const char *python; /* the interpreter that has matplotlib; NULL: none */
static int probed;

const char *bench_figures_python(void)
{
    if (probed) return python;
    probed = 1;
    /* `python3` on PATH first, then Debian's (PATH may lead to another Python) */
    static const char *const candidates[] = {"python3", "/usr/bin/python3"};
    for (size_t i = 0; i < 2; i++) {
        char *argv[] = {(char *)candidates[i], "-c", "import matplotlib, numpy, treetrace.plots",
                        NULL};
        if (run(argv, 1) == 0) return python = candidates[i];
    }
    return NULL;
}

void bench_figures_hint(FILE *f, const char *out_dir)
{
    fprintf(f, "no python3 with matplotlib and the treetrace package was found, so no "
               "figures were drawn: install python3-matplotlib (scripts/python-deps.sh), then "
               "run `PYTHONPATH=python python3 -m treetrace.plots %s`",
            out_dir);
}

int bench_figures_draw(const char *out_dir, FILE *err)
{
    const char *py = bench_figures_python();
    if (!py) {
        fprintf(err, "treetrace bench: ");
        bench_figures_hint(err, out_dir);
        fputc('\n', err);
        return 0; /* optional: the tables and CSVs are complete without them */
    }
    char *argv[] = {(char *)py, "-m", "treetrace.plots", (char *)out_dir, NULL};
    int rc = run(argv, 0);
    if (rc != 0) {
        fprintf(err, "treetrace bench: drawing the figures failed (%s -m treetrace.plots %s "
                     "exited with %d)\n", py, out_dir, rc);
        return -1;
    }
    return 0;
}
