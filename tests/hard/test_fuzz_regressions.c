/* Replays what the fuzzers found and what they start from, under the same
 * checks as the fuzzers themselves (tests/fuzz/fuzz_common.h): every input
 * is either loaded into a sane scene (or view) or refused with a parse error
 * naming it, within the allocation bound, leaking nothing, also when an
 * allocation fails midway.
 *
 * tests/fuzz/regressions/<target>-<what>.<ext>: inputs that once crashed or
 * broke a rule; <target> (obj, ply, views) picks the parser, as in the
 * fuzzer of that name. tests/fuzz/corpus/<target>/: the seeds, which are
 * valid files and must load. */
#include <dirent.h>
#include <string.h>

#include "check.h"

/* A broken rule is one failed check; the rest of that input is skipped. */
#define FUZZ_FAILED()                                                                      \
    do {                                                                                   \
        tt_test_failed++;                                                                  \
        return;                                                                            \
    } while (0)
#define FUZZ_PASSED() (tt_test_passed++)
#include "../fuzz/fuzz_common.h"

typedef struct file_data {
    unsigned char *bytes;
    size_t size;
} file_data;

static int read_all(const char *path, file_data *out)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    size_t cap = 4096, n = 0;
    unsigned char *b = malloc(cap);
    for (;;) {
        if (!b) break;
        if (n == cap) {
            unsigned char *p = realloc(b, cap *= 2);
            if (!p) {
                free(b);
                b = NULL;
                break;
            }
            b = p;
        }
        size_t got = fread(b + n, 1, cap - n, f);
        n += got;
        if (got == 0) break;
    }
    int ok = b && !ferror(f);
    fclose(f);
    if (!ok) {
        free(b);
        return 0;
    }
    out->bytes = b;
    out->size = n;
    return 1;
}

/* Runs the fuzzer of `target` on one input; returns the load's status. */
static tt_status replay(const char *target, const file_data *d)
{
    if (strcmp(target, "obj") == 0) {
        fuzz_load("obj", d->bytes, d->size);
    } else if (strcmp(target, "ply") == 0) {
        fuzz_load(fuzz_ply_format(d->bytes, d->size), d->bytes, d->size);
    } else {
        char name[256];
        fuzz_second_line_name(d->bytes, d->size, name, sizeof name);
        tt_status named = TT_ERR_PARSE;
        if (name[0]) {
            fuzz_find_view(d->bytes, d->size, name);
            named = fuzz_last_status;
        }
        fuzz_find_view(d->bytes, d->size, "no such scene:no such view");
        CHECK(fuzz_last_status != TT_OK);
        return named;
    }
    return fuzz_last_status;
}

/* Every regular file in dir; `target` NULL: the part of the name before the
 * first '-'. must_load: the input is valid and must be accepted. */
static int replay_dir(const char *dir, const char *target, int must_load)
{
    DIR *dp = opendir(dir);
    if (!dp) {
        fprintf(stderr, "cannot open %s\n", dir);
        tt_test_failed++;
        return 0;
    }
    int files = 0;
    for (struct dirent *e; (e = readdir(dp));) {
        if (e->d_name[0] == '.') continue;
        char path[4096], t[16];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (target) {
            snprintf(t, sizeof t, "%s", target);
        } else {
            size_t n = strcspn(e->d_name, "-");
            snprintf(t, sizeof t, "%.*s", (int)(n < sizeof t ? n : sizeof t - 1), e->d_name);
        }
        if (strcmp(t, "obj") && strcmp(t, "ply") && strcmp(t, "views")) {
            fprintf(stderr, "%s: the name does not start with obj-, ply- or views-\n", path);
            tt_test_failed++;
            continue;
        }
        file_data d;
        if (!read_all(path, &d)) {
            fprintf(stderr, "cannot read %s\n", path);
            tt_test_failed++;
            continue;
        }
        int failed_before = tt_test_failed;
        tt_status st = replay(t, &d);
        if (must_load) CHECK_MSG(st == TT_OK, "%s: the seed is refused: %s", path, tt_strerror(st));
        if (tt_test_failed != failed_before) fprintf(stderr, "  ^ with input %s\n", path);
        files++;
        free(d.bytes);
    }
    closedir(dp);
    return files;
}

int main(void)
{
    int n = replay_dir(TT_TESTS_DIR "/fuzz/regressions", NULL, 0);
    CHECK(n > 0);
    printf("%d regression inputs\n", n);
    static const char *const targets[] = {"obj", "ply", "views"};
    for (int i = 0; i < 3; i++) {
        char dir[4096];
        snprintf(dir, sizeof dir, "%s/fuzz/corpus/%s", TT_TESTS_DIR, targets[i]);
        int seeds = replay_dir(dir, targets[i], 1);
        CHECK(seeds > 0);
        printf("%d %s seeds\n", seeds, targets[i]);
    }
    return tt_test_finish();
}
