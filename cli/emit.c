#include "emit.h"

#include <math.h>
#include <string.h>

void emit_begin(cli_emit *e, FILE *out, int json)
{
    memset(e, 0, sizeof *e);
    e->out = out;
    e->json = json;
    e->first[0] = 1;
    if (json) fputc('{', out);
}

void emit_end(cli_emit *e)
{
    if (e->json) fputs("\n}\n", e->out);
    fflush(e->out);
}

static void json_string(FILE *out, const char *s)
{
    fputc('"', out);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\') fprintf(out, "\\%c", *p);
        else if (*p == '\n') fputs("\\n", out);
        else if (*p == '\t') fputs("\\t", out);
        else if (*p < 0x20) fprintf(out, "\\u%04x", *p);
        else fputc(*p, out);
    }
    fputc('"', out);
}

/* Writes the key and its separator; the caller writes the value. */
static void key(cli_emit *e, const char *k)
{
    if (e->json) {
        if (!e->first[e->depth]) fputc(',', e->out);
        e->first[e->depth] = 0;
        fprintf(e->out, "\n%*s", 2 * (e->depth + 1), "");
        json_string(e->out, k);
        fputs(": ", e->out);
    } else {
        fprintf(e->out, "%s%s: ", e->prefix, k);
    }
}

static void end_value(cli_emit *e)
{
    if (!e->json) fputc('\n', e->out);
}

void emit_str(cli_emit *e, const char *k, const char *value)
{
    key(e, k);
    if (e->json) json_string(e->out, value);
    else fputs(value, e->out);
    end_value(e);
}

void emit_u64(cli_emit *e, const char *k, uint64_t value)
{
    key(e, k);
    fprintf(e->out, "%llu", (unsigned long long)value);
    end_value(e);
}

void emit_int(cli_emit *e, const char *k, long value)
{
    key(e, k);
    fprintf(e->out, "%ld", value);
    end_value(e);
}

static void number(cli_emit *e, double v)
{
    if (isfinite(v)) fprintf(e->out, "%.9g", v);
    else if (e->json) fputs("null", e->out);
    else fputs(isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf"), e->out);
}

void emit_num(cli_emit *e, const char *k, double value)
{
    key(e, k);
    number(e, value);
    end_value(e);
}

void emit_bool(cli_emit *e, const char *k, int value)
{
    key(e, k);
    if (e->json) fputs(value ? "true" : "false", e->out);
    else fputs(value ? "yes" : "no", e->out);
    end_value(e);
}

void emit_vec3(cli_emit *e, const char *k, const float v[3])
{
    key(e, k);
    if (e->json) fputc('[', e->out);
    for (int i = 0; i < 3; i++) {
        if (i) fputs(e->json ? ", " : ",", e->out);
        number(e, v[i]);
    }
    if (e->json) fputc(']', e->out);
    end_value(e);
}

void emit_group_begin(cli_emit *e, const char *k)
{
    if (e->json) {
        key(e, k);
        fputc('{', e->out);
    } else {
        size_t n = strlen(e->prefix);
        snprintf(e->prefix + n, sizeof e->prefix - n, "%s.", k);
    }
    if (e->depth + 1 < (int)(sizeof e->first / sizeof e->first[0])) e->depth++;
    e->first[e->depth] = 1;
}

void emit_group_end(cli_emit *e)
{
    if (e->json) {
        fprintf(e->out, "\n%*s}", 2 * e->depth, "");
    } else {
        /* drop the last "group." */
        size_t n = strlen(e->prefix);
        if (n) n--;
        while (n > 0 && e->prefix[n - 1] != '.') n--;
        e->prefix[n] = '\0';
    }
    if (e->depth > 0) e->depth--;
}
