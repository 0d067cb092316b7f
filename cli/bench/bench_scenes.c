/* The scenes folder: scenes.tsv names each model file, views.tsv its camera
 * views (layout in ../shared/scenes/README.md). Cameras are parsed by the
 * library (tt_view_find), so the benchmark reads them exactly as render does. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench/bench.h"

int bench_scene_is_tiny(const char *name)
{
    return strcmp(name, "bunny_res4") == 0 || strcmp(name, "cornell") == 0;
}

static int has_scenes_tsv(const char *dir)
{
    char p[4200];
    snprintf(p, sizeof p, "%s/scenes.tsv", dir);
    return access(p, R_OK) == 0;
}

/* Drops the last `n` path components of `path` in place. */
static void strip_components(char *path, int n)
{
    while (n-- > 0) {
        char *slash = strrchr(path, '/');
        if (!slash) {
            path[0] = '\0';
            return;
        }
        *slash = '\0';
    }
}

const char *bench_default_scenes_dir(char *buf, size_t size)
{
    const char *env = getenv("TT_SCENES_DIR");
    if (env && *env && has_scenes_tsv(env)) {
        snprintf(buf, size, "%s", env);
        return buf;
    }
    char base[PATH_MAX];
    /* next to the executable: <repo>/build/treetrace -> <repo>/../shared */
    ssize_t n = readlink("/proc/self/exe", base, sizeof base - 1);
    if (n > 0) {
        base[n] = '\0';
        strip_components(base, 1);
        const char *rel[] = {"/../../shared/scenes", "/../shared/scenes",
                             "/../../../shared/scenes"};
        for (size_t i = 0; i < sizeof rel / sizeof rel[0]; i++) {
            snprintf(buf, size, "%s%s", base, rel[i]);
            if (has_scenes_tsv(buf)) return buf;
        }
    }
    /* next to the source this was compiled from: <repo>/cli/bench/this.c */
    snprintf(base, sizeof base, "%s", __FILE__);
    if (base[0] == '/') {
        strip_components(base, 3);
        snprintf(buf, size, "%s/../shared/scenes", base);
        if (has_scenes_tsv(buf)) return buf;
    }
    const char *cwd_rel[] = {"../shared/scenes", "shared/scenes"};
    for (size_t i = 0; i < 2; i++) {
        if (has_scenes_tsv(cwd_rel[i])) {
            snprintf(buf, size, "%s", cwd_rel[i]);
            return buf;
        }
    }
    return NULL;
}

/* Reads a whole text file into a NUL-terminated buffer (free it). */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap);
    while (buf) {
        size_t got = fread(buf + len, 1, cap - len - 1, f);
        len += got;
        if (len + 1 < cap) break;
        char *nb = realloc(buf, cap * 2);
        if (!nb) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = nb;
        cap *= 2;
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        free(buf);
        return NULL;
    }
    buf[len] = '\0';
    return buf;
}

/* Splits a line at tabs in place; returns the number of fields (<= max). */
static int split_tabs(char *line, char **fields, int max)
{
    int n = 0;
    char *p = line;
    while (n < max) {
        fields[n++] = p;
        char *t = strchr(p, '\t');
        if (!t) break;
        *t = '\0';
        p = t + 1;
    }
    return n;
}

/* Iterates the lines of buf (modified in place, \r stripped). */
static char *next_line(char **cursor)
{
    char *p = *cursor;
    if (!p || !*p) return NULL;
    char *nl = strchr(p, '\n');
    if (nl) {
        *nl = '\0';
        *cursor = nl + 1;
    } else {
        *cursor = p + strlen(p);
    }
    size_t len = strlen(p);
    if (len && p[len - 1] == '\r') p[len - 1] = '\0';
    return p;
}

static int selected(const bench_options *o, const char *name)
{
    if (!o->scene_names) return !bench_scene_is_tiny(name);
    for (size_t i = 0; i < o->scene_name_count; i++)
        if (strcmp(o->scene_names[i], name) == 0) return 1;
    return 0;
}

static int column(char **fields, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(fields[i], name) == 0) return i;
    return -1;
}

static int read_scenes_tsv(const char *dir, const bench_options *o, bench_scene_list *out,
                           FILE *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/scenes.tsv", dir);
    char *text = slurp(path);
    if (!text) {
        fprintf(err, "treetrace bench: cannot read %s\n", path);
        return -1;
    }
    char *cur = text, *line, *f[16];
    int lineno = 1, rc = 0;
    line = next_line(&cur);
    int nf = line ? split_tabs(line, f, 16) : 0;
    int c_name = column(f, nf, "name"), c_file = column(f, nf, "file");
    int c_tris = column(f, nf, "triangles");
    if (c_name < 0 || c_file < 0) {
        fprintf(err, "treetrace bench: %s:1: the header has no 'name' and 'file' columns\n", path);
        free(text);
        return -1;
    }
    while ((line = next_line(&cur))) {
        lineno++;
        if (!*line || line[0] == '#') continue;
        int n = split_tabs(line, f, 16);
        if (n <= c_name || n <= c_file) {
            fprintf(err, "treetrace bench: %s:%d: expected at least %d tab-separated fields\n",
                    path, lineno, (c_name > c_file ? c_name : c_file) + 1);
            rc = -1;
            break;
        }
        long tris = c_tris >= 0 && c_tris < n ? strtol(f[c_tris], NULL, 10) : -1;
        if (!selected(o, f[c_name])) continue;
        /* --quick leaves out the big scenes (their kd-tree builds alone take
         * most of a minute) unless they are named */
        if (o->quick && !o->scene_names && tris > BENCH_QUICK_MAX_TRIANGLES) continue;
        bench_scene *grown = realloc(out->items, (out->count + 1) * sizeof *grown);
        if (!grown) {
            rc = -1;
            break;
        }
        out->items = grown;
        bench_scene *s = &out->items[out->count++];
        memset(s, 0, sizeof *s);
        snprintf(s->name, sizeof s->name, "%s", f[c_name]);
        snprintf(s->path, sizeof s->path, "%s/%s", dir, f[c_file]);
        s->triangles = tris;
    }
    free(text);
    return rc;
}

static int read_views_tsv(tt_context *ctx, const char *dir, const bench_options *o,
                          bench_scene_list *out, FILE *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/views.tsv", dir);
    char *text = slurp(path);
    if (!text) {
        fprintf(err, "treetrace bench: cannot read %s\n", path);
        return -1;
    }
    char *cur = text, *line, *f[16];
    int lineno = 1, rc = 0;
    next_line(&cur); /* the header */
    while (rc == 0 && (line = next_line(&cur))) {
        lineno++;
        if (!*line || line[0] == '#') continue;
        int n = split_tabs(line, f, 16);
        if (n < 2) {
            fprintf(err, "treetrace bench: %s:%d: expected scene<TAB>view<TAB>...\n", path, lineno);
            rc = -1;
            break;
        }
        for (size_t i = 0; i < out->count; i++) {
            bench_scene *s = &out->items[i];
            if (strcmp(s->name, f[0]) != 0) continue;
            if (s->view_count && !o->all_views) continue;
            bench_view *grown = realloc(s->views, (s->view_count + 1) * sizeof *grown);
            if (!grown) {
                rc = -1;
                break;
            }
            s->views = grown;
            bench_view *v = &s->views[s->view_count];
            memset(v, 0, sizeof *v);
            snprintf(v->name, sizeof v->name, "%s", f[1]);
            char full[160];
            snprintf(full, sizeof full, "%s:%s", f[0], f[1]);
            tt_status st = tt_view_find(ctx, path, full, &v->camera);
            if (st != TT_OK) {
                fprintf(err, "treetrace bench: view %s: %s\n", full, tt_context_last_error(ctx));
                rc = -1;
                break;
            }
            s->view_count++;
        }
    }
    free(text);
    return rc;
}

int bench_scenes_read(tt_context *ctx, const char *dir, const bench_options *o,
                      bench_scene_list *out, FILE *err)
{
    memset(out, 0, sizeof *out);
    snprintf(out->dir, sizeof out->dir, "%s", dir);
    if (read_scenes_tsv(dir, o, out, err) || read_views_tsv(ctx, dir, o, out, err)) {
        bench_scenes_free(out);
        return -1;
    }
    for (size_t i = 0; i < o->scene_name_count; i++) {
        size_t k = 0;
        while (k < out->count && strcmp(out->items[k].name, o->scene_names[i]) != 0) k++;
        if (k == out->count) {
            fprintf(err, "treetrace bench: --scene %s: no such scene in %s/scenes.tsv\n",
                    o->scene_names[i], dir);
            bench_scenes_free(out);
            return -2; /* a bad option, not a broken folder */
        }
    }
    /* a scene without views cannot be rendered: say so, keep the others */
    size_t kept = 0;
    for (size_t i = 0; i < out->count; i++) {
        if (out->items[i].view_count == 0) {
            fprintf(err, "treetrace bench: scene %s has no view in %s/views.tsv; left out\n",
                    out->items[i].name, dir);
            continue;
        }
        out->items[kept++] = out->items[i];
    }
    out->count = kept;
    if (out->count == 0) {
        fprintf(err, "treetrace bench: no scene to run in %s\n", dir);
        bench_scenes_free(out);
        return -1;
    }
    return 0;
}

void bench_scenes_free(bench_scene_list *l)
{
    for (size_t i = 0; i < l->count; i++) free(l->items[i].views);
    free(l->items);
    l->items = NULL;
    l->count = 0;
}
