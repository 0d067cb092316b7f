/* Results on stdout, either as `key: value` lines or as one JSON object with
 * the same keys, so scripts can use either. Nested groups become
 * "group.key: value" lines or nested JSON objects. */
#ifndef TT_CLI_EMIT_H
#define TT_CLI_EMIT_H

#include <stdint.h>
#include <stdio.h>

typedef struct cli_emit {
    FILE *out;
    int json;
    int depth;
    int first[4];      /* per nesting level: nothing written at it yet         */
    char prefix[128]; /* text mode: "group." inside a group                   */
} cli_emit;

void emit_begin(cli_emit *e, FILE *out, int json);
void emit_end(cli_emit *e);
void emit_str(cli_emit *e, const char *key, const char *value);
void emit_u64(cli_emit *e, const char *key, uint64_t value);
void emit_int(cli_emit *e, const char *key, long value);
/* Finite numbers with 9 significant digits; non-finite as null (JSON has no
 * infinity) or inf/nan in text. */
void emit_num(cli_emit *e, const char *key, double value);
void emit_bool(cli_emit *e, const char *key, int value);
void emit_vec3(cli_emit *e, const char *key, const float v[3]);
void emit_group_begin(cli_emit *e, const char *key);
void emit_group_end(cli_emit *e);

#endif
