/* The run-time ISA choice: names round-trip, auto resolves to the best
 * supported ISA, an unsupported or unknown request is a clear error, and a
 * structure reports the ISA it was built for. */
#include <string.h>

#include "check.h"

int main(void)
{
    tt_context *ctx = tt_test_context();
    for (int i = TT_ISA_AUTO; i <= TT_ISA_AVX512; i++) {
        tt_isa back;
        CHECK(tt_isa_from_name(tt_isa_name((tt_isa)i), &back) && back == (tt_isa)i);
    }
    tt_isa x;
    CHECK(!tt_isa_from_name("avx3", &x));
    CHECK(!tt_isa_from_name(NULL, &x));
    CHECK(strcmp(tt_isa_name((tt_isa)99), "") == 0);
    CHECK(tt_isa_supported(TT_ISA_SCALAR));
    CHECK(!tt_isa_supported(TT_ISA_AUTO));
    CHECK(tt_isa_supported(tt_isa_best()));
    for (int i = tt_isa_best() + 1; i <= TT_ISA_AVX512; i++) CHECK(!tt_isa_supported((tt_isa)i));

    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t idx[3] = {0, 1, 2};
    tt_scene *scene;
    REQUIRE_OK(ctx, tt_scene_create(ctx, v, 3, idx, 1, &scene));
    for (int i = TT_ISA_AUTO; i <= TT_ISA_AVX512 + 1; i++) {
        tt_build_options o;
        tt_build_options_default(&o);
        o.accel = "bruteforce";
        o.isa = (tt_isa)i;
        tt_accel *acc = NULL;
        tt_status st = tt_accel_build(ctx, scene, &o, &acc);
        if (i == TT_ISA_AUTO) {
            CHECK(st == TT_OK && tt_accel_isa(acc) == tt_isa_best());
        } else if (i > TT_ISA_AVX512) {
            CHECK(st == TT_ERR_INVALID_ARGUMENT && acc == NULL);
        } else if (tt_isa_supported((tt_isa)i)) {
            CHECK(st == TT_OK && tt_accel_isa(acc) == (tt_isa)i);
        } else {
            CHECK(st == TT_ERR_UNSUPPORTED && acc == NULL);
            CHECK(strstr(tt_context_last_error(ctx), tt_isa_name((tt_isa)i)) != NULL);
        }
        tt_accel_destroy(acc);
    }
    tt_scene_destroy(scene);
    tt_context_destroy(ctx);
    return tt_test_finish();
}
