#include "io/number.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Enough significant digits that truncating there (plus a "sticky" nonzero
 * digit for whatever was dropped) can never move a value across a float
 * rounding midpoint: a float midpoint has at most ~105 significant decimal
 * digits (2^-150 times an odd 25-bit number). */
#define KEEP_DIGITS 120

typedef struct decimal {
    int neg;
    char digits[KEEP_DIGITS]; /* significant digits, no leading zeros       */
    int nd;
    int sticky;               /* a nonzero digit was dropped after digits   */
    int64_t exp10;            /* value = DIGITS * 10^exp10 (+ sticky)       */
} decimal;

static int is_digit(char c) { return c >= '0' && c <= '9'; }

static char lower(char c) { return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c; }

static int starts_with_ci(const char *s, size_t len, const char *word)
{
    size_t i = 0;
    for (; word[i]; i++)
        if (i >= len || lower(s[i]) != word[i]) return 0;
    return 1;
}

/* "nan", "inf" or "infinity" after an optional sign. */
static int is_nonfinite_word(const char *s, size_t len)
{
    size_t i = (len && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
    s += i;
    len -= i;
    return (len == 3 && (starts_with_ci(s, len, "nan") || starts_with_ci(s, len, "inf"))) ||
           (len == 8 && starts_with_ci(s, len, "infinity"));
}

static void add_digit(decimal *d, char c, int fraction)
{
    if (d->nd == 0 && c == '0') {
        if (fraction) d->exp10--; /* leading zero after the point: 0.05 */
        return;
    }
    if (d->nd < KEEP_DIGITS) {
        d->digits[d->nd++] = c;
        if (fraction) d->exp10--;
    } else {
        if (c != '0') d->sticky = 1;
        if (!fraction) d->exp10++;
    }
}

/* Splits a token into sign, significant digits and exponent; 0 if it is
 * not a decimal number. */
static int scan(const char *s, size_t len, decimal *d)
{
    size_t i = 0, ndigits = 0;
    d->neg = 0;
    d->nd = 0;
    d->sticky = 0;
    d->exp10 = 0;
    if (i < len && (s[i] == '+' || s[i] == '-')) d->neg = s[i++] == '-';
    for (; i < len && is_digit(s[i]); i++, ndigits++) add_digit(d, s[i], 0);
    if (i < len && s[i] == '.') {
        for (i++; i < len && is_digit(s[i]); i++, ndigits++) add_digit(d, s[i], 1);
    }
    if (ndigits == 0) return 0;
    if (i < len && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        int eneg = 0;
        if (i < len && (s[i] == '+' || s[i] == '-')) eneg = s[i++] == '-';
        if (i >= len || !is_digit(s[i])) return 0;
        int64_t e = 0;
        for (; i < len && is_digit(s[i]); i++)
            if (e < 1000000000) e = e * 10 + (s[i] - '0'); /* saturate: the value is 0 or inf anyway */
        d->exp10 += eneg ? -e : e;
    }
    return i == len;
}

int tt_is_float_token(const char *s, size_t len)
{
    decimal d;
    return scan(s, len, &d) || is_nonfinite_word(s, len);
}

tt_num_result tt_parse_float(const char *s, size_t len, float *out)
{
    static const float pow10f[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f,
                                   1e6f, 1e7f, 1e8f, 1e9f, 1e10f};
    decimal d;
    if (!scan(s, len, &d)) return is_nonfinite_word(s, len) ? TT_NUM_NOT_FINITE : TT_NUM_MALFORMED;
    float sign = d.neg ? -1.0f : 1.0f;
    if (d.nd == 0) { /* all zeros, whatever the exponent */
        *out = sign * 0.0f;
        return TT_NUM_OK;
    }
    if (!d.sticky)
        while (d.nd > 0 && d.digits[d.nd - 1] == '0') d.nd--, d.exp10++;
    /* The value lies in [10^(top-1), 10^top). */
    int64_t top = d.exp10 + d.nd;
    if (top > 39) return TT_NUM_RANGE; /* >= 1e38 * 10 > FLT_MAX */
    if (top < -46) {                   /* < 1e-46: below half the smallest denormal */
        *out = sign * 0.0f;
        return TT_NUM_OK;
    }
    /* Fast path: an integer mantissa and a power of ten both exact in a
     * float give a single correctly rounded multiply or divide. */
    if (FLT_EVAL_METHOD == 0 && !d.sticky && d.nd <= 8 && d.exp10 >= -10 && d.exp10 <= 10) {
        uint32_t m = 0;
        for (int i = 0; i < d.nd; i++) m = m * 10 + (uint32_t)(d.digits[i] - '0');
        if (m <= (1u << 24)) {
            float f = (float)m;
            f = d.exp10 >= 0 ? f * pow10f[d.exp10] : f / pow10f[-d.exp10];
            *out = sign * f;
            return TT_NUM_OK;
        }
    }
    /* Slow path: strtof on a canonical "[-]DIGITS[1]eEXP" (no decimal
     * point, so the locale cannot interfere). The sticky '1' stands for
     * the dropped nonzero digits. */
    char buf[KEEP_DIGITS + 32];
    size_t n = 0;
    if (d.neg) buf[n++] = '-';
    for (int i = 0; i < d.nd; i++) buf[n++] = d.digits[i];
    int64_t e = d.exp10;
    if (d.sticky) buf[n++] = '1', e--;
    snprintf(buf + n, sizeof buf - n, "e%lld", (long long)e);
    errno = 0;
    float f = strtof(buf, NULL);
    if (isinf(f)) return TT_NUM_RANGE;
    *out = f;
    return TT_NUM_OK;
}

tt_num_result tt_parse_int64(const char *s, size_t len, int64_t *out)
{
    size_t i = 0;
    int neg = 0;
    if (i < len && (s[i] == '+' || s[i] == '-')) neg = s[i++] == '-';
    if (i >= len) return TT_NUM_MALFORMED;
    /* Accumulate as a negative number so INT64_MIN fits. */
    int64_t v = 0;
    int range = 0;
    for (; i < len; i++) {
        if (!is_digit(s[i])) return TT_NUM_MALFORMED;
        int dgt = s[i] - '0';
        if (v < (INT64_MIN + dgt) / 10) range = 1;
        else v = v * 10 - dgt;
    }
    if (range || (!neg && v == INT64_MIN)) return TT_NUM_RANGE;
    *out = neg ? v : -v;
    return TT_NUM_OK;
}

const char *tt_num_result_text(tt_num_result r)
{
    switch (r) {
    case TT_NUM_OK: return "a number";
    case TT_NUM_MALFORMED: return "malformed number";
    case TT_NUM_NOT_FINITE: return "not a finite number";
    case TT_NUM_RANGE: return "number out of range";
    }
    return "bad number";
}
