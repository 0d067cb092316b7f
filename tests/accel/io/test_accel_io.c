/* Saved structures (tt_accel_save / tt_accel_load): every structure and
 * layout round-trips and the loaded one traces bit for bit like the one
 * saved (a rendered view's hit buffer and counts, and random rays' t, u,
 * v, prim); embree is refused by name; and every kind of bad file
 * (truncated, bit-flipped, wrong version, wrong scene, other byte order,
 * another SIMD layout, hostile sizes and indices) gets an error naming the
 * file and what is wrong, never a crash. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "accel/accel.h"
#include "accel/accel_io.h"
#include "check.h"
#include "io/accel_file.h"

static char dir[256];

typedef struct config {
    const char *label, *accel;
    void (*set)(tt_build_options *o);
} config;

static void set_none(tt_build_options *o) { (void)o; }
static void set_complete(tt_build_options *o)
{
    o->rtree.build = TT_RTREE_BUILD_INSERT;
    o->rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
}
static void set_complete_str(tt_build_options *o)
{
    o->rtree.build = TT_RTREE_BUILD_STR;
    o->rtree.layout = TT_RTREE_LAYOUT_COMPLETE;
    o->rtree.M = 8;
}
static void set_compact_m8(tt_build_options *o)
{
    o->rtree.build = TT_RTREE_BUILD_HILBERT;
    o->rtree.M = 8;
    o->rtree.traversal = TT_RTREE_STACKLESS;
}
static void set_kd_sltr(tt_build_options *o)
{
    o->kdtree.traversal = TT_KD_SLTR;
    o->kdtree.shadow_caster_hint = 1;
}
static void set_kd_binned_btr(tt_build_options *o)
{
    o->kdtree.builder = TT_KD_BINNED;
    o->kdtree.traversal = TT_KD_BTR;
    o->kdtree.dmin = 2;
}

static const config configs[] = {
    {"bruteforce", "bruteforce", set_none},
    {"rtree compact (default)", "rtree", set_none},
    {"rtree compact hilbert M=8 stackless", "rtree", set_compact_m8},
    {"rtree complete insert", "rtree", set_complete},
    {"rtree complete str M=8", "rtree", set_complete_str},
    {"kdtree htr", "kdtree", set_none},
    {"kdtree sltr caster hint", "kdtree", set_kd_sltr},
    {"kdtree binned btr dmin 2", "kdtree", set_kd_binned_btr},
};

static tt_render_result *render(tt_context *ctx, const tt_scene *s, const tt_accel *a)
{
    /* bruteforce tests every triangle a ray: a smaller image covers it */
    const uint32_t side = strcmp(tt_accel_name(a), "bruteforce") == 0 ? 24 : 96;
    tt_camera cam;
    tt_camera_frame_scene(s, &cam);
    tt_render_options ro;
    tt_render_options_default(&ro);
    ro.width = ro.height = side;
    ro.keep_hits = ro.stats = 1;
    tt_render_result *r = NULL;
    REQUIRE_OK(ctx, tt_render(ctx, s, a, &cam, &ro, &r));
    return r;
}

/* Random rays from inside and outside the scene box: same bits. */
static void same_rays(const tt_scene *s, const tt_accel *a, const tt_accel *b, const char *label,
                      int n)
{
    float lo[3], hi[3];
    tt_scene_bounds(s, lo, hi);
    uint32_t seed = 12345, bad = 0;
    for (int i = 0; i < n; i++) {
        tt_ray r;
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            float u = (float)(seed >> 8) / 16777216.0f;
            r.org[k] = lo[k] + (hi[k] - lo[k]) * (1.5f * u - 0.25f);
            seed = seed * 1664525u + 1013904223u;
            r.dir[k] = (float)(seed >> 8) / 8388608.0f - 1.0f;
        }
        r.tmin = 0.0f;
        r.tmax = TT_INF;
        if (r.dir[0] == 0 && r.dir[1] == 0 && r.dir[2] == 0) continue;
        tt_hit h1, h2;
        int o1, o2;
        tt_intersect1(a, &r, &h1);
        tt_intersect1(b, &r, &h2);
        tt_occluded1(a, &r, &o1);
        tt_occluded1(b, &r, &o2);
        if (memcmp(&h1, &h2, sizeof h1) != 0 || o1 != o2) bad++;
    }
    CHECK_MSG(bad == 0, "%s: %u random rays differ after loading", label, bad);
}

static void round_trip(tt_context *ctx, const tt_scene *s, const config *c)
{
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = c->accel;
    c->set(&o);
    tt_accel *built = NULL, *loaded = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, s, &o, &built));
    char path[512];
    snprintf(path, sizeof path, "%s/rt.tta", dir);
    CHECK_OK(ctx, tt_accel_save(built, path, "bunny.ply"));
    CHECK_OK(ctx, tt_accel_load(ctx, s, path, TT_ISA_AUTO, &loaded));
    if (!loaded) {
        tt_accel_destroy(built);
        return;
    }
    CHECK(tt_accel_loaded(loaded) && !tt_accel_loaded(built));
    CHECK_MSG(strcmp(tt_accel_name(loaded), c->accel) == 0, "%s", c->label);
    tt_build_options lo, bo;
    tt_accel_options(loaded, &lo);
    tt_accel_options(built, &bo);
    CHECK_MSG(memcmp(&lo.rtree, &bo.rtree, sizeof lo.rtree) == 0 &&
                  memcmp(&lo.kdtree, &bo.kdtree, sizeof lo.kdtree) == 0,
              "%s: options differ after loading", c->label);
    CHECK_MSG(tt_accel_check(loaded) == TT_OK, "%s: check of the loaded structure: %s", c->label,
              tt_context_last_error(ctx));
    tt_render_result *r1 = render(ctx, s, built), *r2 = render(ctx, s, loaded);
    size_t n1, n2;
    const uint8_t *h1 = tt_render_hits(r1, &n1), *h2 = tt_render_hits(r2, &n2);
    CHECK_MSG(n1 == n2 && memcmp(h1, h2, n1) == 0, "%s: hit buffers differ", c->label);
    const tt_render_summary *s1 = tt_render_get_summary(r1), *s2 = tt_render_get_summary(r2);
    CHECK_MSG(memcmp(&s1->primary_stats, &s2->primary_stats, sizeof s1->primary_stats) == 0 &&
                  memcmp(&s1->shadow_stats, &s2->shadow_stats, sizeof s1->shadow_stats) == 0,
              "%s: traversal counts differ", c->label);
    /* bruteforce tests every triangle: fewer rays suffice to cover it */
    const int n = strcmp(c->accel, "bruteforce") == 0 ? 100 : 2000;
    same_rays(s, built, loaded, c->label, n);
    /* every ISA this CPU has loads the same file and traces the same */
    for (int isa = TT_ISA_SCALAR; isa <= TT_ISA_AVX512; isa++) {
        if (!tt_isa_supported((tt_isa)isa)) continue;
        tt_accel *other = NULL;
        CHECK_OK(ctx, tt_accel_load(ctx, s, path, (tt_isa)isa, &other));
        if (other) same_rays(s, built, other, c->label, n / 4);
        tt_accel_destroy(other);
    }
    tt_render_result_destroy(r1);
    tt_render_result_destroy(r2);
    tt_accel_destroy(loaded);
    tt_accel_destroy(built);
}

/* ---------------------------------------------------------- bad files */

static uint8_t *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *b = malloc(*size ? *size : 1);
    if (fread(b, 1, *size, f) != *size) *size = 0;
    fclose(f);
    return b;
}

static void spit(const char *path, const uint8_t *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    fwrite(b, 1, n, f);
    fclose(f);
}

/* Recomputes both checksums (a crafted file, not a damaged one). */
static void reseal(uint8_t *b, size_t n)
{
    tt_af_header h;
    memcpy(&h, b, sizeof h);
    h.payload_checksum = XXH3_64bits(b + TT_AF_HEADER_BYTES, n - TT_AF_HEADER_BYTES);
    h.header_checksum = XXH3_64bits(&h, offsetof(tt_af_header, header_checksum));
    memcpy(b, &h, sizeof h);
}

/* Loads the bytes as a file; expects failure with `status` (0: any) and a
 * message naming the file and containing `what`. */
static void expect_refused(tt_context *ctx, const tt_scene *s, const uint8_t *b, size_t n,
                           tt_status status, const char *what, const char *label)
{
    char path[512];
    snprintf(path, sizeof path, "%s/bad.tta", dir);
    spit(path, b, n);
    tt_accel *a = NULL;
    tt_status st = tt_accel_load(ctx, s, path, TT_ISA_AUTO, &a);
    const char *msg = tt_context_last_error(ctx);
    CHECK_MSG(st != TT_OK && a == NULL, "%s: accepted", label);
    if (st == TT_OK) {
        tt_accel_destroy(a);
        return;
    }
    CHECK_MSG(status == TT_OK || st == status, "%s: status %s (%s)", label, tt_strerror(st), msg);
    CHECK_MSG(strstr(msg, path) != NULL, "%s: the message does not name the file: %s", label, msg);
    CHECK_MSG(strstr(msg, what) != NULL, "%s: expected '%s' in: %s", label, what, msg);
}

static const tt_af_entry *entry(const uint8_t *b, uint32_t id)
{
    const tt_af_header *h = (const tt_af_header *)b;
    const tt_af_entry *t = (const tt_af_entry *)(b + TT_AF_HEADER_BYTES);
    for (uint32_t i = 0; i < h->section_count; i++)
        if (t[i].id == id) return &t[i];
    return NULL;
}

static void bad_files(tt_context *ctx, const tt_scene *s, const tt_scene *other,
                      const char *accel, void (*set)(tt_build_options *))
{
    tt_build_options o;
    tt_build_options_default(&o);
    o.accel = accel;
    set(&o);
    tt_accel *a = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, s, &o, &a));
    char path[512];
    snprintf(path, sizeof path, "%s/good.tta", dir);
    REQUIRE_OK(ctx, tt_accel_save(a, path, "bunny.ply"));
    tt_accel_destroy(a);
    size_t n = 0;
    uint8_t *good = slurp(path, &n), *b = malloc(n);
    CHECK(n > TT_AF_HEADER_BYTES);

    /* truncated: at several lengths, the empty file included */
    const size_t cuts[] = {0, 7, 100, TT_AF_HEADER_BYTES, TT_AF_HEADER_BYTES + 10, n / 2, n - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof cuts[0]; i++)
        expect_refused(ctx, s, good, cuts[i], TT_ERR_PARSE, cuts[i] == 0 ? "empty" : "trunc",
                       "truncated");
    /* trailing bytes */
    uint8_t *longer = malloc(n + 8);
    memcpy(longer, good, n);
    memset(longer + n, 0, 8);
    expect_refused(ctx, s, longer, n + 8, TT_ERR_PARSE, "trailing", "trailing bytes");
    free(longer);
    /* a flipped bit anywhere: the header, the table, the arrays */
    uint32_t seed = 99;
    for (int i = 0; i < 64; i++) {
        memcpy(b, good, n);
        seed = seed * 1664525u + 1013904223u;
        size_t at = i < 8 ? (size_t)i * 31 : (size_t)(seed % n);
        b[at] ^= (uint8_t)(1u << (seed >> 29));
        expect_refused(ctx, s, b, n, TT_OK, ": ", "bit flip");
    }
    memcpy(b, good, n);
    b[n - 1] ^= 0x10;
    expect_refused(ctx, s, b, n, TT_ERR_PARSE, "checksum", "bit flip at the end");
    /* not our file */
    memcpy(b, good, n);
    memcpy(b, "GIF89a..", 8);
    expect_refused(ctx, s, b, n, TT_ERR_PARSE, "not a treetrace", "magic");
    /* wrong container version, correctly sealed */
    memcpy(b, good, n);
    ((tt_af_header *)b)->version = 99;
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_UNSUPPORTED, "version 99", "container version");
    /* wrong record version of the structure */
    memcpy(b, good, n);
    ((tt_af_header *)b)->layout_version = 77;
    reseal(b, n);
    if (strcmp(accel, "bruteforce") != 0)
        expect_refused(ctx, s, b, n, TT_ERR_UNSUPPORTED, "version 77", "layout version");
    /* other byte order */
    memcpy(b, good, n);
    ((tt_af_header *)b)->endian = 0x04030201u;
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_UNSUPPORTED, "byte order", "endianness");
    /* another SIMD block width */
    memcpy(b, good, n);
    ((tt_af_header *)b)->block_width = 16;
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_UNSUPPORTED, "16-lane", "SIMD layout");
    /* a structure this build does not know */
    memcpy(b, good, n);
    snprintf(((tt_af_header *)b)->structure, 16, "octree");
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_UNSUPPORTED, "octree", "unknown structure");
    /* hostile sizes: a section claiming more elements than the file holds,
     * a huge section count, an offset past the end */
    memcpy(b, good, n);
    tt_af_entry *e = (tt_af_entry *)(b + TT_AF_HEADER_BYTES);
    e[0].count = UINT64_MAX / 2;
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_PARSE, "past the end", "hostile count");
    memcpy(b, good, n);
    ((tt_af_header *)b)->section_count = 1000000;
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_PARSE, "sections", "hostile section count");
    memcpy(b, good, n);
    e[0].offset = (uint64_t)1 << 60;
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_PARSE, "offset", "hostile offset");
    memcpy(b, good, n);
    e[0].elem = 0;
    reseal(b, n);
    expect_refused(ctx, s, b, n, TT_ERR_PARSE, "element size", "hostile element size");
    /* hostile content, sealed: indices out of range in the arrays */
    const uint32_t ids[] = {TT_AF_SEC_RTC_NODES, TT_AF_SEC_RTP_PRIM, TT_AF_SEC_RTP_LEAF_START,
                            TT_AF_SEC_KD_NODES, TT_AF_SEC_KD_REFS, TT_AF_SEC_RTC_HEADER};
    for (size_t k = 0; k < sizeof ids / sizeof ids[0]; k++) {
        const tt_af_entry *se = entry(good, ids[k]);
        if (!se || se->count == 0) continue;
        for (int j = 0; j < 8; j++) {
            memcpy(b, good, n);
            uint32_t *w = (uint32_t *)(b + se->offset);
            const uint64_t words = se->count * se->elem / 4;
            seed = seed * 1664525u + 1013904223u;
            /* in the node arrays the index words; elsewhere any word */
            uint64_t at = seed % words;
            if (ids[k] == TT_AF_SEC_KD_NODES) at |= 1; /* the bits word */
            w[at] = 0x7ffffff0u ^ (seed & 0xf);
            reseal(b, n);
            tt_accel *x = NULL;
            snprintf(path, sizeof path, "%s/hostile.tta", dir);
            spit(path, b, n);
            tt_status st = tt_accel_load(ctx, s, path, TT_ISA_AUTO, &x);
            if (st == TT_OK) { /* a change that kept the structure valid: it must still trace */
                tt_render_result *r = render(ctx, s, x);
                tt_render_result_destroy(r);
                tt_accel_destroy(x);
            } else {
                CHECK_MSG(strstr(tt_context_last_error(ctx), path) != NULL, "hostile: %s",
                          tt_context_last_error(ctx));
            }
        }
    }
    /* the file of another scene: refused, naming the scene it was saved for */
    snprintf(path, sizeof path, "%s/good.tta", dir);
    tt_accel *x = NULL;
    tt_status st = tt_accel_load(ctx, other, path, TT_ISA_AUTO, &x);
    CHECK(st == TT_ERR_INVALID_ARGUMENT && x == NULL);
    CHECK_MSG(strstr(tt_context_last_error(ctx), "another scene") &&
                  strstr(tt_context_last_error(ctx), "bunny.ply") &&
                  strstr(tt_context_last_error(ctx), path),
              "wrong scene: %s", tt_context_last_error(ctx));
    free(good);
    free(b);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    snprintf(dir, sizeof dir, "/tmp/tt_accel_io_%d", (int)getpid());
    char cmd[300];
    snprintf(cmd, sizeof cmd, "mkdir -p %s", dir);
    if (system(cmd) != 0) return 1;
    tt_scene *s = NULL, *other = NULL;
    REQUIRE_OK(ctx, tt_scene_load(ctx, TT_DATA_DIR "/bunny.ply", &s));
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t idx[3] = {0, 1, 2};
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 3, idx, 1, &other));

    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; i++)
        round_trip(ctx, s, &configs[i]);
    bad_files(ctx, s, other, "rtree", set_none);
    bad_files(ctx, s, other, "rtree", set_complete_str);
    bad_files(ctx, s, other, "kdtree", set_kd_sltr);
    bad_files(ctx, s, other, "bruteforce", set_none);

    /* Embree: refused by name, saying why */
    if (tt_test_has_accel("embree")) {
        tt_build_options o;
        tt_build_options_default(&o);
        o.accel = "embree";
        tt_accel *e = NULL;
        REQUIRE_OK(ctx, tt_accel_build(ctx, s, &o, &e));
        char path[512];
        snprintf(path, sizeof path, "%s/embree.tta", dir);
        CHECK(tt_accel_save(e, path, NULL) == TT_ERR_UNSUPPORTED);
        CHECK_MSG(strstr(tt_context_last_error(ctx), "embree") &&
                      strstr(tt_context_last_error(ctx), "cannot be saved"),
                  "%s", tt_context_last_error(ctx));
        CHECK(access(path, F_OK) != 0);
        tt_accel_destroy(e);
    }
    /* a missing file and a folder */
    tt_accel *a = NULL;
    CHECK(tt_accel_load(ctx, s, "/nonexistent/x.tta", TT_ISA_AUTO, &a) == TT_ERR_IO);
    CHECK(strstr(tt_context_last_error(ctx), "/nonexistent/x.tta") != NULL);
    CHECK(tt_accel_load(ctx, s, dir, TT_ISA_AUTO, &a) == TT_ERR_IO);

    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
    tt_scene_destroy(s);
    tt_scene_destroy(other);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
