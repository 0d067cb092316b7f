#include "check.h"

#include <stdarg.h>
#include <string.h>
#include <unistd.h>

int tt_test_passed, tt_test_failed;

static unsigned isa_ran, isa_skipped; /* bit per tt_isa value */

static int isa_compiled(tt_isa isa)
{
    if (isa == TT_ISA_SCALAR) return 1;
#if defined(TT_HAVE_X86_KERNELS) && (defined(__x86_64__) || defined(__i386__))
    return isa > TT_ISA_SCALAR && isa <= TT_ISA_AVX512;
#else
    return 0;
#endif
}

static int isa_hidden(tt_isa isa)
{
    const char *h = getenv("TT_TEST_HIDE_ISAS");
    const char *name = tt_isa_name(isa);
    size_t len = strlen(name);
    for (const char *p = h; p && *p;) {
        size_t n = strcspn(p, ", ");
        if (n == len && strncmp(p, name, n) == 0) return 1;
        p += n;
        p += strspn(p, ", ");
    }
    return 0;
}

int tt_test_isa_runs(tt_isa isa)
{
    if (isa < TT_ISA_SCALAR || isa > TT_ISA_AVX512) return 0;
    unsigned bit = 1u << isa;
    if (tt_isa_supported(isa) && !isa_hidden(isa)) {
        isa_ran |= bit;
        return 1;
    }
    if (isa_compiled(isa) && !(isa_skipped & bit)) {
        isa_skipped |= bit;
        printf("SKIPPED: the %s kernels are compiled into this binary, but this CPU cannot run "
               "them: not compared\n",
               tt_isa_name(isa));
    }
    return 0;
}

int tt_test_finish(void)
{
    if (isa_ran) {
        printf("ISAs compared:");
        for (int i = TT_ISA_SCALAR; i <= TT_ISA_AVX512; i++)
            if (isa_ran & (1u << i)) printf(" %s", tt_isa_name((tt_isa)i));
        printf("\n");
    }
    printf("%d passed, %d failed\n", tt_test_passed, tt_test_failed);
    if (tt_test_failed) return 1;
    if (isa_skipped) {
        printf("skipped: kernels compiled in but not runnable here were not compared:");
        for (int i = TT_ISA_SCALAR; i <= TT_ISA_AVX512; i++)
            if (isa_skipped & (1u << i)) printf(" %s", tt_isa_name((tt_isa)i));
        printf("\n");
        return 77;
    }
    return 0;
}

void tt_test_skip(const char *fmt, ...)
{
    /* A skip must not swallow the failures of the checks that ran before
     * it: those make the program fail, and the skip is only reported. */
    va_list ap;
    va_start(ap, fmt);
    printf(tt_test_failed ? "not skipped, failed: " : "skipped: ");
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
    if (tt_test_failed) {
        printf("%d passed, %d failed before the skip\n", tt_test_passed, tt_test_failed);
        fflush(stdout);
        exit(1);
    }
    fflush(stdout);
    exit(77);
}

int tt_test_gpu_required(void)
{
    const char *e = getenv("TT_REQUIRE_GPU");
    return (e && strcmp(e, "1") == 0) || access("/dev/nvidia0", F_OK) == 0;
}

void tt_test_no_gpu(tt_status st, const char *why)
{
    /* A build without CUDA (TT_ERR_UNSUPPORTED) cannot use a GPU that is
     * there: it skips unless TT_REQUIRE_GPU=1 asks for one explicitly. */
    const char *e = getenv("TT_REQUIRE_GPU");
    int required = st == TT_ERR_UNSUPPORTED ? e && strcmp(e, "1") == 0 : tt_test_gpu_required();
    if (required) {
        fprintf(stderr,
                "FAILED: a GPU is required here (/dev/nvidia0 exists or TT_REQUIRE_GPU=1) but "
                "cannot be used: %s\n",
                why);
        printf("%d passed, %d failed\n", tt_test_passed, tt_test_failed + 1);
        exit(1);
    }
    tt_test_skip("%s", why);
}

tt_context *tt_test_context(void)
{
    tt_context *ctx = NULL;
    if (tt_context_create(NULL, &ctx) != TT_OK) {
        fprintf(stderr, "cannot create a context\n");
        exit(1);
    }
    return ctx;
}

const char *tt_test_scene_path(const char *file)
{
    static char path[4][4096];
    static int slot;
    char *p = path[slot++ & 3];
    /* the environment's TT_SCENES_DIR first (as for the Python tests),
     * else the folder the build was configured with */
    const char *dir = getenv("TT_SCENES_DIR");
    snprintf(p, sizeof path[0], "%s/%s", dir && *dir ? dir : TT_SCENES_DIR, file);
    if (access(p, R_OK) != 0) tt_test_skip("shared scene %s is not present (set TT_SCENES_DIR)", p);
    return p;
}

tt_scene *tt_test_load_scene(tt_context *ctx, const char *file)
{
    tt_scene *scene = NULL;
    REQUIRE_OK(ctx, tt_scene_load(ctx, tt_test_scene_path(file), &scene));
    return scene;
}

void tt_test_view(tt_context *ctx, const char *name, tt_camera *out)
{
    REQUIRE_OK(ctx, tt_view_find(ctx, tt_test_scene_path("views.tsv"), name, out));
}

int tt_test_has_accel(const char *name)
{
    for (const char *const *n = tt_accel_names(); *n; n++)
        if (strcmp(*n, name) == 0) return 1;
    return 0;
}

tt_accel *tt_test_build_isa(tt_context *ctx, const tt_scene *scene, const char *name, tt_isa isa)
{
    tt_build_options opt;
    tt_build_options_default(&opt);
    opt.accel = name;
    opt.isa = isa;
    tt_accel *a = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, &opt, &a));
    return a;
}

tt_accel *tt_test_build_default(tt_context *ctx, const tt_scene *scene, const char *name)
{
    return tt_test_build_isa(ctx, scene, name, TT_ISA_AUTO);
}

typedef struct stat_lookup {
    const char *name;
    double value;
} stat_lookup;

static void take_stat(void *user, const char *key, double value)
{
    stat_lookup *l = user;
    if (strcmp(key, l->name) == 0) l->value = value;
}

double tt_test_stat(const tt_accel *accel, const char *name)
{
    stat_lookup l = {name, -1.0};
    tt_accel_statistics(accel, take_stat, &l);
    return l.value;
}
