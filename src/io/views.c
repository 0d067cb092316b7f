/* views.tsv (../shared/scenes/views.tsv): a header line
 * "scene view eye look up fov_deg light", then one view a line with
 * comma-separated triples; light may be empty or absent (no light). The
 * whole file is validated, not just the line asked for, so a broken file is
 * reported whichever view is wanted. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "geometry/vec3.h"
#include "io/file.h"
#include "io/number.h"
#include "io/parsers.h"

#define FIELDS 7

typedef struct field {
    const char *s;
    size_t len;
} field;

static const char *const column[FIELDS] = {"scene", "view", "eye", "look", "up", "fov_deg", "light"};

/* Splits a line at tabs; returns the number of fields (up to max + 1). */
static size_t split_tabs(const char *p, const char *end, field *f, size_t max)
{
    size_t n = 0;
    for (;;) {
        const char *tab = memchr(p, '\t', (size_t)(end - p));
        const char *fe = tab ? tab : end;
        if (n <= max) {
            f[n].s = p;
            f[n].len = (size_t)(fe - p);
        }
        n++;
        if (!tab || n > max) return n;
        p = tab + 1;
    }
}

static int field_is(field f, const char *s) { return f.len == strlen(s) && !memcmp(f.s, s, f.len); }

static tt_status parse_float_field(tt_context *ctx, const char *file, size_t line, const char *col,
                                   const char *s, size_t len, float *out)
{
    char q[64];
    tt_num_result r = tt_parse_float(s, len, out);
    if (r != TT_NUM_OK)
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: %s: %s %s", file, line, col, tt_num_result_text(r),
                        tt_quote_token(q, sizeof q, s, len));
    return TT_OK;
}

static tt_status parse_triple(tt_context *ctx, const char *file, size_t line, const char *col,
                              field f, float out[3])
{
    const char *p = f.s, *end = f.s + f.len;
    char q[64];
    for (int k = 0; k < 3; k++) {
        const char *comma = k < 2 ? memchr(p, ',', (size_t)(end - p)) : NULL;
        if (k < 2 && !comma)
            return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: %s: expected three comma-separated numbers, got %s",
                            file, line, col, tt_quote_token(q, sizeof q, f.s, f.len));
        const char *e = comma ? comma : end;
        /* tolerate spaces around the numbers */
        const char *a = p, *b = e;
        while (a < b && tt_is_space(*a)) a++;
        while (b > a && tt_is_space(b[-1])) b--;
        tt_status st = parse_float_field(ctx, file, line, col, a, (size_t)(b - a), &out[k]);
        if (st) return st;
        p = e + 1;
    }
    return TT_OK;
}

static float dist2(const float a[3], const float b[3])
{
    float d = 0;
    for (int k = 0; k < 3; k++) d += (a[k] - b[k]) * (a[k] - b[k]);
    return d;
}

/* Whether a squared length can be normalised in float: finite, and normal
 * so that 1 / sqrtf(len2) is finite too. */
static int normalisable(float len2) { return isfinite(len2) && len2 >= FLT_MIN; }

/* The camera builds its basis in float (render/camera.c, per the
 * conventions): forward = normalize(look - eye), right = normalize(cross(
 * forward, up)). Both must be normalisable there, or every primary ray comes
 * out zero or NaN; finite inputs are not enough (a difference of 1e38 and
 * -1e38 overflows, a squared length of 1e-30 underflows). So the same float
 * steps are replayed here and a view that fails them is refused. */
static tt_status check_basis(tt_context *ctx, const char *file, size_t line, const tt_camera *cam)
{
    tt_vec3 d = tt_v3_sub(tt_v3_load(cam->look), tt_v3_load(cam->eye));
    float d2 = tt_v3_dot(d, d);
    if (!normalisable(d2))
        return tt_error(ctx, TT_ERR_PARSE,
                        "%s:%zu: look - eye (%g, %g, %g) is too %s for a float view direction", file,
                        line, d.x, d.y, d.z, d2 > 1.0f ? "long" : "short");
    tt_vec3 r = tt_v3_cross(tt_v3_normalize(d), tt_v3_load(cam->up));
    float r2 = tt_v3_dot(r, r);
    if (!isfinite(r2))
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: the up vector is too long for float arithmetic",
                        file, line);
    if (!normalisable(r2)) /* up parallel to the view leaves no image plane */
        return tt_error(ctx, TT_ERR_PARSE,
                        "%s:%zu: the up vector is parallel to the view direction (or too short)",
                        file, line);
    return TT_OK;
}

/* One view line into *cam, checking that it describes a usable camera. */
static tt_status parse_view(tt_context *ctx, const char *file, size_t line, const field *f,
                            size_t n, tt_camera *cam)
{
    tt_status st;
    memset(cam, 0, sizeof *cam);
    if ((st = parse_triple(ctx, file, line, "eye", f[2], cam->eye))) return st;
    if ((st = parse_triple(ctx, file, line, "look", f[3], cam->look))) return st;
    if ((st = parse_triple(ctx, file, line, "up", f[4], cam->up))) return st;
    const char *a = f[5].s, *b = f[5].s + f[5].len;
    while (a < b && tt_is_space(*a)) a++;
    while (b > a && tt_is_space(b[-1])) b--;
    if ((st = parse_float_field(ctx, file, line, "fov_deg", a, (size_t)(b - a), &cam->fov_deg)))
        return st;
    if (!(cam->fov_deg > 0.0f && cam->fov_deg < 180.0f))
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: fov_deg %g is not in (0, 180)", file, line,
                        cam->fov_deg);
    int has_light = 0;
    if (n == FIELDS) {
        for (size_t i = 0; i < f[6].len; i++)
            if (!tt_is_space(f[6].s[i])) has_light = 1;
    }
    if (has_light) {
        if ((st = parse_triple(ctx, file, line, "light", f[6], cam->light))) return st;
        cam->has_light = 1;
    }
    static const float zero[3] = {0, 0, 0};
    if (dist2(cam->up, zero) == 0.0f)
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: the up vector is zero", file, line);
    if (dist2(cam->eye, cam->look) == 0.0f)
        return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: eye and look are the same point", file, line);
    return check_basis(ctx, file, line, cam);
}

/* Appends "scene:view" to the list of available names (for the error when
 * the wanted one is missing), ending it with ", ..." instead once the next
 * name would not fit. A name is only added while room for that ellipsis
 * stays behind it, so the ellipsis always fits too. */
#define ELLIPSIS ", ..."
static void append_name(char *list, size_t cap, int *truncated, const field *f)
{
    if (*truncated) return;
    size_t n = strlen(list);
    char item[160];
    snprintf(item, sizeof item, "%s%.*s:%.*s", n ? ", " : "", (int)(f[0].len > 64 ? 64 : f[0].len),
             f[0].s, (int)(f[1].len > 64 ? 64 : f[1].len), f[1].s);
    if (n + strlen(item) + sizeof ELLIPSIS > cap) {
        memcpy(list + n, ELLIPSIS, sizeof ELLIPSIS);
        *truncated = 1;
        return;
    }
    memcpy(list + n, item, strlen(item) + 1);
}

tt_status tt_view_find_memory(tt_context *ctx, const char *views_name, const char *data,
                              size_t size, const char *name, tt_camera *out)
{
    if (!ctx || !out) return TT_ERR_INVALID_ARGUMENT;
    if (!views_name) views_name = "<memory>";
    if (!name) return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "%s: no view name given", views_name);
    if (!data && size)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "%s: NULL data with a nonzero size", views_name);
    const char *colon = strchr(name, ':');
    if (!colon || name[0] == ':' || name[strlen(name) - 1] == ':')
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT,
                        "%s: view name \"%.64s\" is not SCENE:VIEW (e.g. conference:main)",
                        views_name, name);
    size_t name_len = strlen(name);
    const char *p = data ? data : "", *end = p + size;
    size_t line = 0, found_line = 0;
    tt_camera found;
    char names[600] = "";
    int names_truncated = 0;
    memset(&found, 0, sizeof found);
    int header_seen = 0;
    while (p < end) {
        line++;
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end;
        if (le > p && le[-1] == '\r') le--;
        const char *next = nl ? nl + 1 : end;
        int blank = 1;
        for (const char *c = p; c < le; c++)
            if (!tt_is_space(*c)) blank = 0;
        if (blank) {
            p = next;
            continue;
        }
        field f[FIELDS + 1];
        size_t n = split_tabs(p, le, f, FIELDS);
        p = next;
        if (!header_seen) {
            header_seen = 1;
            int ok = n == FIELDS;
            for (size_t i = 0; ok && i < FIELDS; i++) ok = field_is(f[i], column[i]);
            if (!ok)
                return tt_error(ctx, TT_ERR_PARSE,
                                "%s:%zu: expected the header \"scene<TAB>view<TAB>eye<TAB>look<TAB>up<TAB>fov_deg<TAB>light\"",
                                views_name, line);
            continue;
        }
        if (n != FIELDS && n != FIELDS - 1)
            return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: %s%zu tab-separated fields, expected %d (or %d without a light)",
                            views_name, line, n > FIELDS ? "more than " : "", n > FIELDS ? (size_t)FIELDS : n,
                            FIELDS, FIELDS - 1);
        if (f[0].len == 0 || f[1].len == 0)
            return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: empty scene or view name", views_name, line);
        tt_camera cam;
        tt_status st = parse_view(ctx, views_name, line, f, n, &cam);
        if (st) return st;
        append_name(names, sizeof names, &names_truncated, f);
        /* "scene:view" compared whole, so a ':' inside either part is harmless */
        if (f[0].len + 1 + f[1].len == name_len && !memcmp(f[0].s, name, f[0].len) &&
            name[f[0].len] == ':' && !memcmp(f[1].s, name + f[0].len + 1, f[1].len)) {
            if (found_line)
                return tt_error(ctx, TT_ERR_PARSE, "%s:%zu: view %.64s is defined again (first on line %zu)",
                                views_name, line, name, found_line);
            found = cam;
            found_line = line;
        }
    }
    if (!header_seen)
        return tt_error(ctx, TT_ERR_PARSE, "%s: the file is empty (expected a header line)", views_name);
    if (!found_line)
        return tt_error(ctx, TT_ERR_PARSE, "%s: no view %.64s; available: %s", views_name, name,
                        names[0] ? names : "(none)");
    *out = found;
    return TT_OK;
}

tt_status tt_view_find(tt_context *ctx, const char *views_path, const char *name, tt_camera *out)
{
    if (!ctx || !out) return TT_ERR_INVALID_ARGUMENT;
    if (!views_path) return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "tt_view_find: NULL path");
    char *data;
    size_t size;
    tt_status st = tt_read_file(ctx, views_path, &data, &size);
    if (st) return st;
    st = tt_view_find_memory(ctx, views_path, data, size, name, out);
    tt_free(ctx, data);
    return st;
}
