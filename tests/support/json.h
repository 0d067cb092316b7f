/* A small strict JSON reader for tests of the CLI's --json output: checks
 * that a text is exactly one JSON object and reads its top-level members. */
#ifndef TT_TEST_JSON_H
#define TT_TEST_JSON_H

#include <stddef.h>

/* The number of top-level members of the object `text`, with their keys
 * copied into keys[0 .. max-1]; -1 if text is not one valid JSON object
 * (trailing whitespace allowed). */
int tt_json_object_keys(const char *text, char (*keys)[64], int max);

/* Top-level member `key` of the object: 1 and its value if it is a number
 * (or a string, for tt_json_get_string), else 0. */
int tt_json_get_number(const char *text, const char *key, double *out);
int tt_json_get_string(const char *text, const char *key, char *out, size_t size);

#endif
