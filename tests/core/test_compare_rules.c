/* The comparison rules every ray-by-ray test relies on (support/compare.h),
 * checked on crafted hits, so that loosening them fails here:
 *  - the same triangle agrees only with bit-identical t, u and v (one ulp
 *    off in any of them, or -0 for +0, is a disagreement);
 *  - different triangles agree with t within TT_TEST_EDGE_REL (1e-6), not
 *    the conventions' 1e-4; a miss agrees only with a miss;
 *  - Embree's rule (its own triangle test) keeps the 1e-4. */
#include <math.h>

#include "check.h"
#include "compare.h"

static tt_hit hit(uint32_t prim, float t, float u, float v)
{
    tt_hit h = {t, u, v, prim};
    return h;
}

int main(void)
{
    const float t = 1500.0f; /* conference's distances */
    tt_hit a = hit(7, t, 0.25f, 0.5f);
    tt_hit b = a;
    CHECK(tt_test_hits_agree(&a, &b));
    b.t = nextafterf(t, INFINITY);
    CHECK(!tt_test_hits_agree(&a, &b));
    CHECK(!tt_test_hits_agree_t(&a, &b));
    b = a, b.u = nextafterf(a.u, 1.0f);
    CHECK(!tt_test_hits_agree(&a, &b));
    CHECK(tt_test_hits_agree_t(&a, &b)); /* no u, v there */
    b = a, b.v = nextafterf(a.v, 0.0f);
    CHECK(!tt_test_hits_agree(&a, &b));
    tt_hit z = hit(7, t, 0.0f, 0.5f), nz = hit(7, t, -0.0f, 0.5f);
    CHECK(!tt_test_hits_agree(&z, &nz));

    /* another triangle: a shared edge's rounding agrees, 0.15 units does not */
    b = hit(8, t * (1.0f + 2e-7f), 0.9f, 0.1f);
    CHECK(tt_test_hits_agree(&a, &b) && tt_test_hits_agree(&b, &a));
    b = hit(8, t, 0.9f, 0.1f); /* a tie */
    CHECK(tt_test_hits_agree(&a, &b));
    b = hit(8, t + 0.15f, 0.9f, 0.1f);
    CHECK(!tt_test_hits_agree(&a, &b) && !tt_test_hits_agree(&b, &a));
    CHECK(!tt_test_hits_agree_t(&a, &b));
    b = hit(8, t * (1.0f + 5e-6f), 0.9f, 0.1f);
    CHECK(!tt_test_hits_agree(&a, &b));

    /* misses */
    tt_hit m = hit(TT_INVALID_ID, INFINITY, 0.0f, 0.0f), m2 = m;
    CHECK(tt_test_hits_agree(&m, &m2) && tt_test_hits_agree_foreign(&m, &m2));
    CHECK(!tt_test_hits_agree(&a, &m) && !tt_test_hits_agree(&m, &a));
    CHECK(!tt_test_hits_agree_foreign(&a, &m));

    /* Embree: the conventions' 1e-4, whichever triangle */
    b = hit(7, t * (1.0f + 5e-5f), 0.3f, 0.4f);
    CHECK(tt_test_hits_agree_foreign(&a, &b));
    b = hit(8, t * (1.0f + 5e-5f), 0.3f, 0.4f);
    CHECK(tt_test_hits_agree_foreign(&a, &b));
    b = hit(7, t * (1.0f + 3e-4f), 0.3f, 0.4f);
    CHECK(!tt_test_hits_agree_foreign(&a, &b));
    return tt_test_finish();
}
