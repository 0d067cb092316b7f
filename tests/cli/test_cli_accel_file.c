/* `treetrace build` and `--accel-file`: a saved structure renders the same
 * hit buffer as the structure built in the process (default R-tree, the
 * complete layout, the kd-tree), `info` checks a loaded one, structure
 * options beside the file are usage errors, and a file for another scene
 * or a damaged file exits 1 with a message naming the file. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "cli_run.h"

static int same_file(const char *a, const char *b)
{
    long na = -1, nb = -2;
    unsigned char *x = tt_test_read_file(a, &na), *y = tt_test_read_file(b, &nb);
    int same = x && y && na == nb && memcmp(x, y, (size_t)na) == 0;
    free(x);
    free(y);
    return same;
}

int main(void)
{
    const char *bunny = TT_DATA_DIR "/bunny.ply";
    static const char *const configs[] = {"", "--layout complete --build str",
                                          "--accel kdtree --traversal sltr"};
    char file[1024], built[1024];
    snprintf(file, sizeof file, "%s", tt_cli_tmp("s.tta"));
    snprintf(built, sizeof built, "%s", tt_cli_tmp("built.hits"));
    tt_cli_result r;
    for (size_t i = 0; i < sizeof configs / sizeof configs[0]; i++) {
        CHECK_MSG(tt_cli_run(&r, "build %s -o %s %s", bunny, file, configs[i]) == 0, "%s", r.err);
        CHECK(strstr(r.out, "file_bytes: ") != NULL);
        tt_cli_result_free(&r);
        CHECK(tt_cli_run(&r, "render %s --size 64x48 --hits %s %s", bunny, built, configs[i]) == 0);
        tt_cli_result_free(&r);
        CHECK_MSG(tt_cli_run(&r, "render %s --size 64x48 --hits %s --accel-file %s", bunny,
                             tt_cli_tmp("loaded.hits"), file) == 0, "%s", r.err);
        CHECK(strstr(r.out, "accel_file: ") && strstr(r.out, "accel_load_s: "));
        tt_cli_result_free(&r);
        CHECK_MSG(same_file(built, tt_cli_tmp("loaded.hits")), "%s: hits differ", configs[i]);
        CHECK_MSG(tt_cli_run(&r, "info %s --accel-file %s", bunny, file) == 0, "%s", r.err);
        CHECK(strstr(r.out, "check: ok") != NULL);
        tt_cli_result_free(&r);
    }
    /* structure options beside the file */
    CHECK(tt_cli_run(&r, "render %s --accel-file %s --accel rtree", bunny, file) == 2);
    CHECK(strstr(r.err, "cannot be combined with --accel-file") != NULL);
    tt_cli_result_free(&r);
    CHECK(tt_cli_run(&r, "render %s --accel-file %s --M 8", bunny, file) == 2);
    tt_cli_result_free(&r);
    CHECK(tt_cli_run(&r, "build %s", bunny) == 2);
    tt_cli_result_free(&r);
    /* another scene's file */
    const char *res4 = tt_test_scene_path("bun_zipper_res4.ply");
    CHECK(tt_cli_run(&r, "render %s --size 8x8 --accel-file %s", res4, file) == 1);
    CHECK_MSG(strstr(r.err, file) && strstr(r.err, "saved for another scene") &&
                  strstr(r.err, "bunny.ply"), "%s", r.err);
    tt_cli_result_free(&r);
    /* a damaged file */
    long n = 0;
    unsigned char *b = tt_test_read_file(file, &n);
    b[n / 2] ^= 1;
    FILE *f = fopen(file, "wb");
    fwrite(b, 1, (size_t)n, f);
    fclose(f);
    free(b);
    CHECK(tt_cli_run(&r, "render %s --size 8x8 --accel-file %s", bunny, file) == 1);
    CHECK_MSG(strstr(r.err, file) && strstr(r.err, "checksum"), "%s", r.err);
    tt_cli_result_free(&r);
    /* embree: refused, saying why */
    if (tt_test_has_accel("embree")) {
        CHECK(tt_cli_run(&r, "build %s -o %s --accel embree", bunny, tt_cli_tmp("e.tta")) == 1);
        CHECK_MSG(strstr(r.err, "cannot be saved"), "%s", r.err);
        tt_cli_result_free(&r);
    }
    return tt_test_finish();
}
