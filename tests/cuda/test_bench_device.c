/* `treetrace bench --device`: an unknown device is a usage error (exit 2);
 * without a usable GPU (or without CUDA in the build) --device gpu fails at
 * once with the reason on one line and creates nothing (exit 1). Where a
 * GPU is present, a tiny bench on it (bunny_res4 and cornell, Feldmann's
 * Tables 1 and 3 and Havran & Bittner's Table 1) writes GPU rows that all
 * succeeded, agree with Embree on every pixel where Embree is built in,
 * and a GPU section in the report. */
#include "../cli/bench_support.h"

static int line_count(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

static void with_gpu(const char *scenes, const char *out, const char *log)
{
    char args[2048];
    snprintf(args, sizeof args,
             "--scenes '%s' --out '%s' --only F1,F3,H1 --size 32x24 --repeat 1 --first-view "
             "--no-heatmaps --threads 2 --device gpu",
             scenes, out);
    int rc = run_bench(args, log);
    char *text = read_text(log);
    CHECK_MSG(rc == 0, "bench --device gpu: exit %d:\n%s", rc, text ? text : "");
    free(text);
    char path[1024];
    snprintf(path, sizeof path, "%s/results.csv", out);
    char *csv = read_text(path);
    CHECK(csv != NULL);
    if (csv) {
        int gpu = 0, gpu_ok = 0;
        for (char *line = strtok(csv, "\n"); line; line = strtok(NULL, "\n")) {
            char *dev = strstr(line, ",gpu,");
            if (!dev) continue;
            gpu++;
            gpu_ok += strstr(line, ",ok,") != NULL;
        }
        CHECK_MSG(gpu > 0 && gpu_ok == gpu, "%d GPU rows, %d ok", gpu, gpu_ok);
        free(csv);
    }
    snprintf(path, sizeof path, "%s/report.md", out);
    char *md = read_text(path);
    CHECK(md && strstr(md, "## GPU (CUDA)") && strstr(md, "### Every GPU run"));
    if (md) {
        /* every GPU row of the agreement table at 100% */
        for (char *line = strtok(md, "\n"); line; line = strtok(NULL, "\n"))
            if (strstr(line, " (GPU) |"))
                CHECK_MSG(strstr(line, "| 100.0000% |") != NULL, "agreement: %s", line);
        free(md);
    }
}

int main(void)
{
    const char *scenes = make_tiny_scenes();
    char out[512], log[512];
    snprintf(out, sizeof out, "%s/out", scenes);
    snprintf(log, sizeof log, "%s/log.txt", scenes);

    char args[2048];
    snprintf(args, sizeof args, "--scenes '%s' --out '%s' --device tpu", scenes, out);
    int rc = run_bench(args, log);
    char *text = read_text(log);
    CHECK_MSG(rc == 2 && text && strstr(text, "--device: expected cpu or gpu, got 'tpu'"),
              "exit %d: %s", rc, text ? text : "");
    free(text);

    tt_context *ctx = tt_test_context();
    tt_status dev = tt_device_check(ctx, TT_DEVICE_GPU);
    int gpu = dev == TT_OK;
    if (!gpu && (dev != TT_ERR_UNSUPPORTED || getenv("TT_REQUIRE_GPU")) && tt_test_gpu_required())
        CHECK_MSG(0, "a GPU is required here (/dev/nvidia0 or TT_REQUIRE_GPU=1) but: %s",
                  tt_context_last_error(ctx));
    if (gpu) {
        with_gpu(scenes, out, log);
    } else {
        snprintf(args, sizeof args, "--scenes '%s' --out '%s' --device gpu", scenes, out);
        rc = run_bench(args, log);
        text = read_text(log);
        char want[600];
        snprintf(want, sizeof want, "treetrace bench: %s\n", tt_context_last_error(ctx));
        CHECK_MSG(rc == 1 && text && strcmp(text, want) == 0 && line_count(text) == 1,
                  "exit %d, output '%s', expected '%s'", rc, text ? text : "", want);
        free(text);
        CHECK_MSG(access(out, F_OK) != 0, "bench --device gpu without a GPU created %s", out);
        printf("no usable GPU (%s): checked the refusal only\n", tt_context_last_error(ctx));
    }
    tt_context_destroy(ctx);
    remove_tree(scenes);
    return tt_test_finish();
}
