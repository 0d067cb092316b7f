/* Number tokens shared by the OBJ, PLY and views parsers. A token is a
 * pointer and a length (the input buffer is not NUL-terminated), and the whole
 * token must be a number: "1.5x" is malformed, not 1.5 followed by garbage. */
#ifndef TT_IO_NUMBER_H
#define TT_IO_NUMBER_H

#include <stddef.h>
#include <stdint.h>

typedef enum tt_num_result {
    TT_NUM_OK = 0,
    TT_NUM_MALFORMED,  /* not a decimal number                              */
    TT_NUM_NOT_FINITE, /* "nan", "inf", "infinity" (any case, signed)        */
    TT_NUM_RANGE       /* too large for the destination type                 */
} tt_num_result;

/* Decimal [+-](digits[.digits] | .digits)[(e|E)[+-]digits] to the nearest
 * float (correctly rounded, like strtof, but locale-independent). Values
 * below the smallest denormal become a signed zero. */
tt_num_result tt_parse_float(const char *s, size_t len, float *out);

/* [+-]digits. */
tt_num_result tt_parse_int64(const char *s, size_t len, int64_t *out);

/* Whether the token is a float by the grammar above, or nan/inf: for values
 * that are skipped, which only need to be well-formed. */
int tt_is_float_token(const char *s, size_t len);

/* A short phrase for an error message ("malformed number"). */
const char *tt_num_result_text(tt_num_result r);

/* Whitespace as the parsers see it (space, tab, CR, LF, VT, FF). */
static inline int tt_is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

#endif
