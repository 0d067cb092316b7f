/* `treetrace bench` refuses bad options with exit status 2 and a message
 * naming the option, before running anything; --help exits 0. */
#include "bench_support.h"

static void expect_bad(const char *args, const char *mention, const char *log)
{
    int rc = run_bench(args, log);
    CHECK_MSG(rc == 2, "'%s' exited %d, expected 2", args, rc);
    char *out = read_text(log);
    CHECK_MSG(out && strstr(out, mention), "'%s': the message does not mention '%s': %s", args,
              mention, out ? out : "(no output)");
    free(out);
}

int main(void)
{
    const char *scenes = make_tiny_scenes();
    char log[600], args[2048];
    snprintf(log, sizeof log, "%s/log.txt", scenes);

    expect_bad("--bogus", "--bogus", log);
    expect_bad("--repeat 0", "--repeat", log);
    expect_bad("--repeat x", "--repeat", log);
    expect_bad("--threads -1", "--threads", log);
    expect_bad("--threads", "--threads needs a value", log);
    expect_bad("--only F9", "F9", log);
    expect_bad("--only=", "--only", log);
    expect_bad("--size 100", "--size", log);
    expect_bad("--size 0x10", "--size", log);
    expect_bad("--kd-size 10x", "--kd-size", log);
    expect_bad("--dmin 0", "--dmin", log);
    expect_bad("--dmin 5-2", "--dmin", log);
    expect_bad("--budget -1", "--budget", log);
    expect_bad("--builds 0", "--builds", log);
    expect_bad("--ao 0", "--ao", log);
    expect_bad("--ao x", "--ao", log);
    expect_bad("--quick=1", "--quick takes no value", log);
    expect_bad("--all-views --first-view", "contradict", log);
    expect_bad("--frames 0", "--frames", log); /* table D's sequences */
    expect_bad("--frames x", "--frames", log);
    expect_bad("--scenes /nonexistent/folder", "/nonexistent/folder", log);
    snprintf(args, sizeof args, "--scenes '%s' --scene nosuchscene --out '%s/out'", scenes, scenes);
    expect_bad(args, "nosuchscene", log);

    int rc = run_bench("--help", log);
    CHECK(rc == 0);
    char *out = read_text(log);
    CHECK(out && strstr(out, "usage: treetrace bench") && strstr(out, "--quick") &&
          strstr(out, "--only") && strstr(out, "--builds") && strstr(out, "--ao") &&
          strstr(out, "--frames"));
    free(out);

    /* table D runs on its own: two frames of each sequence on the tiny bunny,
     * a CSV row per engine and frame, treetrace's with update and SAH */
    snprintf(args, sizeof args, "--scenes '%s' --scene bunny_res4 --only D --frames 2 --out '%s/dyn'",
             scenes, scenes);
    rc = run_bench(args, log);
    CHECK_MSG(rc == 0, "table D exited %d", rc);
    char csv[700];
    snprintf(csv, sizeof csv, "%s/dyn/dynamic.csv", scenes);
    out = read_text(csv);
    CHECK(out && strstr(out, "scene,mode,engine,frame,triangles,update_ms") &&
          strstr(out, "bunny_res4,deform,treetrace,2,") && strstr(out, "bunny_res4,edits,treetrace,2,") &&
          strstr(out, "bunny_res4,growth,treetrace,2,") && strstr(out, ",inplace") &&
          strstr(out, ",compact"));
    free(out);

    remove_tree(scenes);
    return tt_test_finish();
}
