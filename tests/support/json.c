#include "json.h"

#include <stdlib.h>
#include <string.h>

typedef struct parser {
    const char *p;
    int depth;
    /* top-level member visitor */
    void (*member)(void *user, const char *key, const char *value, const char *end);
    void *user;
} parser;

static void ws(parser *s)
{
    while (*s->p == ' ' || *s->p == '\t' || *s->p == '\n' || *s->p == '\r') s->p++;
}

static int value(parser *s);

/* A string; copies its raw content (escapes kept) into out if given. */
static int string(parser *s, char *out, size_t size)
{
    if (*s->p != '"') return 0;
    s->p++;
    size_t n = 0;
    while (*s->p != '"') {
        if ((unsigned char)*s->p < 0x20) return 0;
        if (*s->p == '\\') {
            s->p++;
            if (*s->p == 'u') {
                for (int i = 1; i <= 4; i++)
                    if (!strchr("0123456789abcdefABCDEF", s->p[i]) || !s->p[i]) return 0;
                s->p += 4;
            } else if (!*s->p || !strchr("\"\\/bfnrt", *s->p)) {
                return 0;
            }
        }
        if (out && n + 1 < size) out[n++] = *s->p;
        s->p++;
    }
    if (out) out[n] = '\0';
    s->p++;
    return 1;
}

static int digits(parser *s)
{
    if (*s->p < '0' || *s->p > '9') return 0;
    while (*s->p >= '0' && *s->p <= '9') s->p++;
    return 1;
}

static int number(parser *s)
{
    if (*s->p == '-') s->p++;
    if (*s->p == '0') s->p++;
    else if (!digits(s)) return 0;
    if (*s->p == '.') {
        s->p++;
        if (!digits(s)) return 0;
    }
    if (*s->p == 'e' || *s->p == 'E') {
        s->p++;
        if (*s->p == '+' || *s->p == '-') s->p++;
        if (!digits(s)) return 0;
    }
    return 1;
}

static int literal(parser *s, const char *word)
{
    size_t n = strlen(word);
    if (strncmp(s->p, word, n) != 0) return 0;
    s->p += n;
    return 1;
}

static int object(parser *s)
{
    s->p++; /* '{' */
    s->depth++;
    ws(s);
    if (*s->p == '}') {
        s->p++;
        s->depth--;
        return 1;
    }
    for (;;) {
        char key[64];
        ws(s);
        if (!string(s, key, sizeof key)) return 0;
        ws(s);
        if (*s->p++ != ':') return 0;
        ws(s);
        const char *start = s->p;
        if (!value(s)) return 0;
        if (s->depth == 1 && s->member) s->member(s->user, key, start, s->p);
        ws(s);
        if (*s->p == ',') {
            s->p++;
            continue;
        }
        if (*s->p++ != '}') return 0;
        s->depth--;
        return 1;
    }
}

static int array(parser *s)
{
    s->p++; /* '[' */
    s->depth++;
    ws(s);
    if (*s->p == ']') {
        s->p++;
        s->depth--;
        return 1;
    }
    for (;;) {
        ws(s);
        if (!value(s)) return 0;
        ws(s);
        if (*s->p == ',') {
            s->p++;
            continue;
        }
        if (*s->p++ != ']') return 0;
        s->depth--;
        return 1;
    }
}

static int value(parser *s)
{
    if (s->depth > 64) return 0;
    switch (*s->p) {
    case '{': return object(s);
    case '[': return array(s);
    case '"': return string(s, NULL, 0);
    case 't': return literal(s, "true");
    case 'f': return literal(s, "false");
    case 'n': return literal(s, "null");
    default: return number(s);
    }
}

static int parse(const char *text, void (*member)(void *, const char *, const char *, const char *),
                 void *user)
{
    parser s = {text, 0, member, user};
    ws(&s);
    if (*s.p != '{' || !object(&s)) return 0;
    ws(&s);
    return *s.p == '\0';
}

typedef struct key_list {
    char (*keys)[64];
    int max, n;
} key_list;

static void collect(void *user, const char *key, const char *v, const char *end)
{
    key_list *k = user;
    (void)v;
    (void)end;
    if (k->n < k->max) {
        strncpy(k->keys[k->n], key, 63);
        k->keys[k->n][63] = '\0';
    }
    k->n++;
}

int tt_json_object_keys(const char *text, char (*keys)[64], int max)
{
    key_list k = {keys, max, 0};
    return parse(text, collect, &k) ? k.n : -1;
}

typedef struct finder {
    const char *key;
    const char *value, *end;
} finder;

static void find(void *user, const char *key, const char *v, const char *end)
{
    finder *f = user;
    if (strcmp(key, f->key) == 0) {
        f->value = v;
        f->end = end;
    }
}

int tt_json_get_number(const char *text, const char *key, double *out)
{
    finder f = {key, NULL, NULL};
    if (!parse(text, find, &f) || !f.value) return 0;
    if (*f.value != '-' && (*f.value < '0' || *f.value > '9')) return 0;
    *out = strtod(f.value, NULL);
    return 1;
}

int tt_json_get_string(const char *text, const char *key, char *out, size_t size)
{
    finder f = {key, NULL, NULL};
    if (!parse(text, find, &f) || !f.value || *f.value != '"') return 0;
    parser s = {f.value, 0, NULL, NULL};
    return string(&s, out, size);
}
