/* Asking for the GPU where it cannot run fails cleanly, through the API and
 * the CLI, on every machine:
 *  - a build without CUDA: TT_ERR_UNSUPPORTED, "this build has no CUDA (...)";
 *  - a build with CUDA but no usable GPU (no driver, no device):
 *    TT_ERR_NO_DEVICE, "no usable CUDA device: <CUDA's reason>";
 *  - what the GPU does not trace (rtree stack, kdtree btr/seq or the caster
 *    hint, bruteforce): TT_ERR_UNSUPPORTED naming what it does, on any
 *    machine; an unknown device value: TT_ERR_INVALID_ARGUMENT.
 * The CLI exits 1 with the message on stderr and nothing on stdout, before
 * loading the scene. Where a usable GPU is present, the no-GPU checks are
 * replaced by checks that the GPU path succeeds (the results themselves are
 * compared in test_gpu_vs_cpu). */
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "cli_run.h"
#include "known_scene.h"

static int starts_with(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

static tt_scene *known_scene(tt_context *ctx)
{
    tt_scene *scene = NULL;
    REQUIRE_OK(ctx, tt_scene_create(ctx, tt_known_vertices, TT_KNOWN_VERTICES, tt_known_indices,
                                    TT_KNOWN_TRIANGLES, &scene));
    return scene;
}

static tt_status render_on(tt_context *ctx, const tt_scene *scene, const tt_build_options *bo,
                           tt_device device, tt_render_result **out)
{
    tt_accel *accel = NULL;
    REQUIRE_OK(ctx, tt_accel_build(ctx, scene, bo, &accel));
    tt_camera cam = tt_known_camera();
    tt_render_options o;
    tt_render_options_default(&o);
    o.width = TT_KNOWN_W;
    o.height = TT_KNOWN_H;
    o.keep_hits = 1;
    o.device = device;
    static char sentinel;
    *out = (tt_render_result *)&sentinel; /* must be reset to NULL on failure */
    tt_status st = tt_render(ctx, scene, accel, &cam, &o, out);
    tt_accel_destroy(accel);
    return st;
}

/* What the device check says here: 1 if a GPU is usable, else 0 after
 * checking the status and message. */
static int check_no_gpu_status(tt_context *ctx, tt_status st, const char *where)
{
    const char *msg = tt_context_last_error(ctx);
#ifdef TT_HAVE_CUDA
    if (st == TT_OK) return 1;
    CHECK_MSG(st == TT_ERR_NO_DEVICE, "%s: status %s", where, tt_strerror(st));
    CHECK_MSG(strstr(msg, "no usable CUDA device: no device here (") != NULL ||
                  strstr(msg, "no usable CUDA device: a device is present but failing") != NULL,
              "%s: message '%s'", where, msg);
    /* with no NVIDIA device node or kernel driver, CUDA's failure means "no
     * device"; "present but failing" is kept for a machine that has one */
    if (access("/dev/nvidia0", F_OK) != 0 && access("/proc/driver/nvidia/version", F_OK) != 0)
        CHECK_MSG(strstr(msg, "no usable CUDA device: no device here (") != NULL,
                  "%s: no NVIDIA device node here, yet: '%s'", where, msg);
    /* a present but failing device is a failure where one is required */
    CHECK_MSG(!tt_test_gpu_required(), "%s: a GPU is required here but: %s", where, msg);
#else
    CHECK_MSG(st == TT_ERR_UNSUPPORTED, "%s: status %s", where, tt_strerror(st));
    CHECK_MSG(strstr(msg, "this build has no CUDA (") != NULL, "%s: message '%s'", where, msg);
#endif
    return 0;
}

static int test_api_device(tt_context *ctx, const tt_scene *scene)
{
    CHECK(tt_device_check(ctx, TT_DEVICE_CPU) == TT_OK);
    CHECK(tt_device_check(ctx, (tt_device)7) == TT_ERR_INVALID_ARGUMENT);
    tt_status st = tt_device_check(ctx, TT_DEVICE_GPU);
    int gpu = check_no_gpu_status(ctx, st, "tt_device_check");

    tt_build_options bo;
    tt_build_options_default(&bo);
    bo.accel = "rtree";
    tt_render_result *res;
    st = render_on(ctx, scene, &bo, TT_DEVICE_GPU, &res);
    if (check_no_gpu_status(ctx, st, "tt_render") != gpu)
        CHECK_MSG(0, "tt_render and tt_device_check disagree about the GPU");
    if (st != TT_OK) CHECK_MSG(res == NULL, "a failed tt_render left a result");
    else tt_render_result_destroy(res);

    st = render_on(ctx, scene, &bo, (tt_device)7, &res);
    CHECK(st == TT_ERR_INVALID_ARGUMENT && res == NULL);
    CHECK(strstr(tt_context_last_error(ctx), "unknown device 7") != NULL);
    /* the CPU is unaffected */
    st = render_on(ctx, scene, &bo, TT_DEVICE_CPU, &res);
    CHECK_OK(ctx, st);
    if (st == TT_OK) {
        CHECK(tt_render_get_summary(res)->device == TT_DEVICE_CPU);
        CHECK(tt_render_get_summary(res)->device_name[0] == '\0');
        tt_render_result_destroy(res);
    }
    return gpu;
}

/* Choices the GPU does not trace are refused on every machine, before the
 * device is looked at, with a message naming what it traces. */
static void test_api_unsupported(tt_context *ctx, const tt_scene *scene)
{
    static const char *const supported = "the GPU traces rtree with the auto, stackless or "
                                         "ordered traversal (in the compact layout: auto or "
                                         "stackless) and kdtree with sltr or htr";
    struct {
        const char *accel;
        int rtree_traversal, kd_traversal, caster, compact;
        const char *names;
    } cases[] = {
        {"rtree", TT_RTREE_STACK, 0, 0, 0, "not rtree with the stack traversal"},
        {"rtree", TT_RTREE_ORDERED, 0, 0, 1,
         "not rtree in the compact layout with the ordered traversal"},
        {"bruteforce", 0, 0, 0, 0, "not bruteforce"},
        {"kdtree", 0, TT_KD_BTR, 0, 0, "not kdtree with the btr traversal"},
        {"kdtree", 0, TT_KD_SEQ, 0, 0, "not kdtree with the seq traversal"},
        {"kdtree", 0, TT_KD_SLTR, 1, 0, "not the kd-tree's shadow-caster hint"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tt_build_options bo;
        tt_build_options_default(&bo);
        bo.accel = cases[i].accel;
        bo.rtree.traversal = (tt_rtree_traversal)cases[i].rtree_traversal;
        bo.kdtree.traversal = (tt_kd_traversal)cases[i].kd_traversal;
        bo.kdtree.shadow_caster_hint = cases[i].caster;
        if (cases[i].compact) bo.rtree.layout = TT_RTREE_LAYOUT_COMPACT;
        int present = 0;
        for (const char *const *n = tt_accel_names(); *n; n++) present |= strcmp(*n, bo.accel) == 0;
        if (!present) continue;
        tt_render_result *res;
        tt_status st = render_on(ctx, scene, &bo, TT_DEVICE_GPU, &res);
        const char *msg = tt_context_last_error(ctx);
        CHECK_MSG(st == TT_ERR_UNSUPPORTED && res == NULL, "case %zu: status %s", i,
                  tt_strerror(st));
        CHECK_MSG(strstr(msg, supported) && strstr(msg, cases[i].names), "case %zu: message '%s'",
                  i, msg);
    }
}

static void test_cli(const char *scene, int gpu)
{
    tt_cli_result r;
    tt_cli_run(&r, "render '%s' %s --size 16x12 --device gpu", scene, TT_KNOWN_CLI_CAMERA);
    if (gpu) {
        CHECK_MSG(r.status == 0, "exit %d: %s", r.status, r.err);
        CHECK(strstr(r.out, "device: gpu") != NULL);
    } else {
        CHECK_MSG(r.status == 1, "--device gpu without a GPU: exit %d", r.status);
        CHECK_MSG(r.out[0] == '\0', "--device gpu without a GPU printed results:\n%s", r.out);
#ifdef TT_HAVE_CUDA
        const char *want = "treetrace render: no usable CUDA device: ";
#else
        const char *want = "treetrace render: this build has no CUDA (";
#endif
        CHECK_MSG(starts_with(r.err, want), "stderr '%s', expected it to start with '%s'", r.err,
                  want);
        CHECK_MSG(strchr(r.err, '\n') == r.err + strlen(r.err) - 1, "not one line: '%s'", r.err);
    }
    tt_cli_result_free(&r);
    /* the device is checked before the scene is read */
    if (!gpu) {
        tt_cli_run(&r, "render /nonexistent/scene.ply --device gpu");
        CHECK_MSG(r.status == 1 && !strstr(r.err, "nonexistent"),
                  "exit %d, stderr '%s': the device should be refused first", r.status, r.err);
        tt_cli_result_free(&r);
    }
    tt_cli_run(&r, "render '%s' --device tpu", scene);
    CHECK_MSG(r.status == 2 && strstr(r.err, "option --device: 'tpu' is not one of cpu|gpu"),
              "exit %d, stderr '%s'", r.status, r.err);
    tt_cli_result_free(&r);
    tt_cli_run(&r, "render '%s' %s --size 16x12 --device cpu", scene, TT_KNOWN_CLI_CAMERA);
    CHECK_MSG(r.status == 0 && strstr(r.out, "device: cpu"), "exit %d: %s", r.status, r.err);
    tt_cli_result_free(&r);
}

int main(void)
{
    tt_context *ctx = tt_test_context();
    tt_scene *scene = known_scene(ctx);
    int gpu = test_api_device(ctx, scene);
    if (gpu) printf("a usable GPU is present: checked that the GPU path runs instead\n");
    test_api_unsupported(ctx, scene);
    const char *path = tt_cli_tmp("known.ply");
    REQUIRE_OK(ctx, tt_known_write_ply(path) == 0 ? TT_OK : TT_ERR_IO);
    test_cli(path, gpu);
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
