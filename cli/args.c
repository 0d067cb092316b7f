#include "args.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

int cli_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "treetrace %s: ", cmd);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, " (see treetrace help %s)\n", cmd);
    return CLI_USAGE;
}

int cli_is(const cli_args *a, const char *name)
{
    const char *arg = a->argv[a->i];
    size_t n = strlen(name);
    return strncmp(arg, name, n) == 0 && (arg[n] == '\0' || arg[n] == '=');
}

const char *cli_value(cli_args *a, const char *name)
{
    const char *arg = a->argv[a->i];
    const char *eq = strchr(arg, '=');
    if (eq) return eq + 1;
    if (a->i + 1 >= a->argc) {
        cli_usage_error(a->cmd, "option %s needs a value", name);
        return NULL;
    }
    return a->argv[++a->i];
}

int cli_parse_long(const char *cmd, const char *opt, const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (*s == '\0' || *end != '\0' || end == s)
        return cli_usage_error(cmd, "option %s: '%s' is not an integer", opt, s);
    if (errno == ERANGE || v < lo || v > hi)
        return cli_usage_error(cmd, "option %s: %s is out of range [%ld, %ld]", opt, s, lo, hi);
    *out = v;
    return CLI_OK;
}

int cli_parse_int(const char *cmd, const char *opt, const char *s, int lo, int hi, int *out)
{
    long v = 0;
    int st = cli_parse_long(cmd, opt, s, lo, hi, &v);
    if (st == CLI_OK) *out = (int)v;
    return st;
}

/* strtod on the whole string, refusing NaN and infinities (which strtod
 * accepts as "nan", "inf" ...) and values that overflow a float. */
static int parse_finite(const char *s, float *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (*s == '\0' || end == s || *end != '\0') return 0;
    if (!isfinite(v) || fabs(v) > 3.4e38) return 0;
    *out = (float)v;
    return 1;
}

int cli_parse_float(const char *cmd, const char *opt, const char *s, double lo, int lo_open,
                    double hi, int hi_open, float *out)
{
    float v;
    if (!parse_finite(s, &v))
        return cli_usage_error(cmd, "option %s: '%s' is not a finite number", opt, s);
    int below = lo_open ? !(v > lo) : !(v >= lo);
    int above = hi_open ? !(v < hi) : !(v <= hi);
    if (below || above)
        return cli_usage_error(cmd, "option %s: %s is out of range %c%g, %g%c", opt, s,
                               lo_open ? '(' : '[', lo, hi, hi_open ? ')' : ']');
    *out = v;
    return CLI_OK;
}

int cli_parse_vec3(const char *cmd, const char *opt, const char *s, float out[3])
{
    char buf[256];
    if (strlen(s) >= sizeof buf)
        return cli_usage_error(cmd, "option %s: '%.40s...' is too long for x,y,z", opt, s);
    strcpy(buf, s);
    char *parts[3];
    int n = 0;
    char *p = buf;
    for (;;) {
        if (n == 3) return cli_usage_error(cmd, "option %s: '%s' is not x,y,z", opt, s);
        parts[n++] = p;
        char *comma = strchr(p, ',');
        if (!comma) break;
        *comma = '\0';
        p = comma + 1;
    }
    if (n != 3) return cli_usage_error(cmd, "option %s: '%s' is not x,y,z", opt, s);
    for (int k = 0; k < 3; k++)
        if (!parse_finite(parts[k], &out[k]))
            return cli_usage_error(cmd, "option %s: '%s' is not x,y,z with finite numbers", opt,
                                   s);
    return CLI_OK;
}

int cli_parse_size(const char *cmd, const char *opt, const char *s, uint32_t max, uint32_t *w,
                   uint32_t *h)
{
    const char *x = strchr(s, 'x');
    if (!x) x = strchr(s, 'X');
    if (!x) return cli_usage_error(cmd, "option %s: '%s' is not WxH", opt, s);
    char wbuf[32];
    size_t wn = (size_t)(x - s);
    if (wn == 0 || wn >= sizeof wbuf) return cli_usage_error(cmd, "option %s: '%s' is not WxH", opt, s);
    memcpy(wbuf, s, wn);
    wbuf[wn] = '\0';
    for (const char *c = wbuf; *c; c++)
        if (*c < '0' || *c > '9') return cli_usage_error(cmd, "option %s: '%s' is not WxH", opt, s);
    for (const char *c = x + 1; *c; c++)
        if (*c < '0' || *c > '9') return cli_usage_error(cmd, "option %s: '%s' is not WxH", opt, s);
    if (x[1] == '\0') return cli_usage_error(cmd, "option %s: '%s' is not WxH", opt, s);
    errno = 0;
    unsigned long long wv = strtoull(wbuf, NULL, 10), hv = strtoull(x + 1, NULL, 10);
    if (errno == ERANGE || wv < 1 || hv < 1 || wv > max || hv > max)
        return cli_usage_error(cmd, "option %s: %s: width and height must be in [1, %u]", opt, s,
                               max);
    *w = (uint32_t)wv;
    *h = (uint32_t)hv;
    return CLI_OK;
}

int cli_parse_choice(const char *cmd, const char *opt, const char *s, const char *const *names,
                     int count, int *out)
{
    for (int k = 0; k < count; k++) {
        if (strcmp(s, names[k]) == 0) {
            *out = k;
            return CLI_OK;
        }
    }
    char list[512] = "";
    for (int k = 0; k < count; k++) {
        strncat(list, names[k], sizeof list - strlen(list) - 1);
        if (k + 1 < count) strncat(list, "|", sizeof list - strlen(list) - 1);
    }
    return cli_usage_error(cmd, "option %s: '%s' is not one of %s", opt, s, list);
}

int cli_scene_arg(const cli_args *a, const char **scene)
{
    const char *arg = a->argv[a->i];
    if (arg[0] == '-' && arg[1] != '\0') return cli_usage_error(a->cmd, "unknown option '%s'", arg);
    if (*scene)
        return cli_usage_error(a->cmd, "more than one scene: '%s' and '%s'", *scene, arg);
    *scene = arg;
    return CLI_OK;
}
