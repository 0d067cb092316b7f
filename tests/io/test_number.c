/* The hand-written number parser: grammar (signs, leading '+', ".5", "5.",
 * exponents), refusals (garbage, nan/inf, overflow) and correct rounding,
 * checked against glibc's strtof (correctly rounded) on hand-picked,
 * random and rounding-midpoint inputs. */
#include <float.h>
#include <math.h>
#include <stdint.h>

#include "io/number.h"
#include "io_util.h"

static tt_num_result pf(const char *s, float *f) { return tt_parse_float(s, strlen(s), f); }

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* The parser agrees bit for bit with strtof on s. */
static int agrees(const char *s)
{
    float f = -12345.0f;
    if (pf(s, &f) != TT_NUM_OK) return 0;
    return same_bits(f, strtof(s, NULL));
}

static uint64_t rng = 88172645463325252ull;
static uint64_t next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

static void check_grammar(void)
{
    static const struct {
        const char *s;
        float v;
    } ok[] = {
        {"0", 0.0f}, {"1", 1.0f}, {"-1", -1.0f}, {"+1", 1.0f}, {".5", 0.5f}, {"5.", 5.0f},
        {"-.5", -0.5f}, {"+.5e1", 5.0f}, {"1e3", 1000.0f}, {"1E3", 1000.0f}, {"1e+3", 1000.0f},
        {"1e-3", 0.001f}, {"2.5e-3", 0.0025f}, {"00012.500", 12.5f}, {"0.000", 0.0f},
        {"1e-06", 1e-6f}, {"-0.011057", -0.011057f}, {"123456789", 123456792.0f},
        {"3.4028234663852886e38", FLT_MAX}, {"1e-50", 0.0f}, {"0e999999999999", 0.0f},
        {"1.401298464324817e-45", 1.401298464324817e-45f},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        float f = -7.0f;
        tt_num_result r = pf(ok[i].s, &f);
        CHECK_MSG(r == TT_NUM_OK && same_bits(f, ok[i].v), "\"%s\" -> %d %.9g", ok[i].s, r, f);
        CHECK_MSG(tt_is_float_token(ok[i].s, strlen(ok[i].s)), "\"%s\" is a float token", ok[i].s);
    }
    float f;
    CHECK(pf("-0", &f) == TT_NUM_OK && f == 0.0f && signbit(f));
    CHECK(pf("-0.0e5", &f) == TT_NUM_OK && f == 0.0f && signbit(f));

    static const char *const malformed[] = {
        "", "+", "-", ".", "+.", "e5", ".e5", "1e", "1e+", "1e-", "1.5x", "1.5.2", "--1", "+-1",
        "1,5", "0x10", "1 2", "1e5.5", "1f", "12a", "a12", "1..", "nanx", "infinit", "1e+-2",
    };
    for (size_t i = 0; i < sizeof malformed / sizeof malformed[0]; i++) {
        CHECK_MSG(pf(malformed[i], &f) == TT_NUM_MALFORMED, "\"%s\" is malformed", malformed[i]);
        CHECK_MSG(!tt_is_float_token(malformed[i], strlen(malformed[i])), "\"%s\" no float token",
                  malformed[i]);
    }
    static const char *const nonfinite[] = {"nan", "NaN", "-nan", "inf", "-inf", "+Inf", "INFINITY", "-infinity"};
    for (size_t i = 0; i < sizeof nonfinite / sizeof nonfinite[0]; i++) {
        CHECK_MSG(pf(nonfinite[i], &f) == TT_NUM_NOT_FINITE, "\"%s\" is not finite", nonfinite[i]);
        CHECK(tt_is_float_token(nonfinite[i], strlen(nonfinite[i])));
    }
    static const char *const range[] = {"1e39", "-1e39", "3.4028236e38", "1e999999999999999999",
                                         "340282356779733661637539395458142568448"};
    for (size_t i = 0; i < sizeof range / sizeof range[0]; i++)
        CHECK_MSG(pf(range[i], &f) == TT_NUM_RANGE, "\"%s\" is out of range", range[i]);
    /* just below the overflow threshold (FLT_MAX + half an ulp) rounds to FLT_MAX */
    CHECK(pf("3.40282356e38", &f) == TT_NUM_OK && f == FLT_MAX);

    /* the token is bounded by its length, not by a NUL */
    CHECK(tt_parse_float("2.5junk", 3, &f) == TT_NUM_OK && f == 2.5f);
}

static void check_integers(void)
{
    int64_t v;
    CHECK(tt_parse_int64("42", 2, &v) == TT_NUM_OK && v == 42);
    CHECK(tt_parse_int64("+42", 3, &v) == TT_NUM_OK && v == 42);
    CHECK(tt_parse_int64("-42", 3, &v) == TT_NUM_OK && v == -42);
    CHECK(tt_parse_int64("9223372036854775807", 19, &v) == TT_NUM_OK && v == INT64_MAX);
    CHECK(tt_parse_int64("-9223372036854775808", 20, &v) == TT_NUM_OK && v == INT64_MIN);
    CHECK(tt_parse_int64("9223372036854775808", 19, &v) == TT_NUM_RANGE);
    CHECK(tt_parse_int64("-9223372036854775809", 20, &v) == TT_NUM_RANGE);
    CHECK(tt_parse_int64("99999999999999999999999", 23, &v) == TT_NUM_RANGE);
    CHECK(tt_parse_int64("", 0, &v) == TT_NUM_MALFORMED);
    CHECK(tt_parse_int64("-", 1, &v) == TT_NUM_MALFORMED);
    CHECK(tt_parse_int64("1.0", 3, &v) == TT_NUM_MALFORMED);
    CHECK(tt_parse_int64("12x", 3, &v) == TT_NUM_MALFORMED);
    CHECK(tt_parse_int64("1e3", 3, &v) == TT_NUM_MALFORMED);
}

/* Random decimals of every shape: short (the fast path), long mantissas,
 * wide exponents, denormals. */
static void check_random(void)
{
    size_t bad = 0;
    for (int i = 0; i < 200000; i++) {
        char s[300];
        size_t n = 0;
        uint64_t r = next();
        if (r & 1) s[n++] = '-';
        else if (r & 2) s[n++] = '+';
        int digits = (int)(next() % (i % 10 == 0 ? 150 : 12)) + 1;
        int point = (int)(next() % (uint64_t)(digits + 1));
        for (int k = 0; k < digits; k++) {
            if (k == point) s[n++] = '.';
            s[n++] = (char)('0' + next() % 10);
        }
        if (next() & 1) n += (size_t)snprintf(s + n, sizeof s - n, "e%d", (int)(next() % 100) - 55);
        s[n] = '\0';
        float want = strtof(s, NULL);
        float got;
        tt_num_result res = pf(s, &got);
        int ok = isinf(want) ? res == TT_NUM_RANGE : (res == TT_NUM_OK && same_bits(got, want));
        if (!ok && bad++ < 5) fprintf(stderr, "random \"%s\": %d %.9g, strtof %.9g\n", s, res, got, want);
    }
    CHECK_MSG(bad == 0, "%zu random numbers disagree with strtof", bad);
}

/* Exact midpoints between adjacent floats (ties go to even), and the same
 * digits truncated (just below the midpoint) or extended by a 1 (just above):
 * where double rounding through a double would go wrong. */
static void check_midpoints(void)
{
    size_t bad = 0, total = 0;
    for (int i = 0; i < 20000; i++) {
        uint32_t bits = (uint32_t)next() & 0x7f7fffffu; /* finite, below FLT_MAX */
        float a;
        memcpy(&a, &bits, sizeof a);
        float b = nextafterf(a, INFINITY);
        if (isinf(b)) continue;
        double mid = ((double)a + (double)b) / 2.0; /* exact in a double */
        char s[400];
        snprintf(s, sizeof s, "%.150e", mid); /* glibc prints the exact value */
        char *e = strchr(s, 'e');
        char exp_part[16];
        snprintf(exp_part, sizeof exp_part, "%s", e);
        /* strip trailing zeros of the mantissa */
        char *end = e;
        while (end[-1] == '0') end--;
        *end = '\0';
        char variant[3][448];
        snprintf(variant[0], sizeof variant[0], "%s%s", s, exp_part);          /* exact */
        snprintf(variant[1], sizeof variant[1], "%s0000000001%s", s, exp_part); /* above */
        size_t len = strlen(s);
        if (len > 12) s[len - 1] = '\0';                                        /* below */
        snprintf(variant[2], sizeof variant[2], "%s%s", s, exp_part);
        for (int v = 0; v < 3; v++, total++)
            if (!agrees(variant[v]) && bad++ < 5) {
                float got = 0;
                pf(variant[v], &got);
                fprintf(stderr, "midpoint \"%s\": %.9g, strtof %.9g\n", variant[v], got,
                        strtof(variant[v], NULL));
            }
    }
    CHECK_MSG(bad == 0, "%zu of %zu midpoint cases disagree with strtof", bad, total);
}

int main(void)
{
    check_grammar();
    check_integers();
    check_random();
    check_midpoints();
    return tt_test_finish();
}
