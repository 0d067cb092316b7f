#include "cli_run.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static char tmp_dir[64];

static void remove_tmp(void)
{
    char cmd[128];
    if (!tmp_dir[0]) return;
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp_dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmp_dir);
}

static void make_tmp_dir(void)
{
    if (!tmp_dir[0]) {
        snprintf(tmp_dir, sizeof tmp_dir, "/tmp/tt_cli_XXXXXX");
        if (!mkdtemp(tmp_dir)) {
            perror("mkdtemp");
            exit(1);
        }
        atexit(remove_tmp);
    }
}

const char *tt_cli_tmp(const char *name)
{
    static char paths[8][512];
    static int slot;
    make_tmp_dir();
    char *p = paths[slot++ & 7];
    snprintf(p, sizeof paths[0], "%s/%s", tmp_dir, name);
    return p;
}

unsigned char *tt_test_read_file(const char *path, long *size)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *buf = malloc((size_t)n + 1);
    if (n < 0 || !buf || fread(buf, 1, (size_t)n, fp) != (size_t)n) {
        free(buf);
        fclose(fp);
        return NULL;
    }
    fclose(fp);
    buf[n] = '\0';
    if (size) *size = n;
    return buf;
}

int tt_cli_run(tt_cli_result *r, const char *fmt, ...)
{
    char args[4096], cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    /* not from tt_cli_tmp's ring of paths, which the caller's may be in */
    char out[512], err[512];
    make_tmp_dir();
    snprintf(out, sizeof out, "%s/stdout.txt", tmp_dir);
    snprintf(err, sizeof err, "%s/stderr.txt", tmp_dir);
    snprintf(cmd, sizeof cmd, "'%s' %s >'%s' 2>'%s' </dev/null", TT_CLI_PATH, args, out, err);
    int st = system(cmd);
    if (st == -1) r->status = -1;
    else if (WIFEXITED(st)) r->status = WEXITSTATUS(st);
    else r->status = 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
    r->out = (char *)tt_test_read_file(out, NULL);
    r->err = (char *)tt_test_read_file(err, NULL);
    if (!r->out) r->out = calloc(1, 1);
    if (!r->err) r->err = calloc(1, 1);
    return r->status;
}

void tt_cli_result_free(tt_cli_result *r)
{
    free(r->out);
    free(r->err);
    r->out = r->err = NULL;
}
