/* Running the built command-line tool (TT_CLI_PATH) from tests: exit status,
 * stdout and stderr captured, files in a private temporary folder. */
#ifndef TT_TEST_CLI_RUN_H
#define TT_TEST_CLI_RUN_H

typedef struct tt_cli_result {
    int status; /* the exit status; 128 + N when killed by signal N (a crash) */
    char *out;  /* stdout, NUL-terminated                                      */
    char *err;  /* stderr                                                      */
} tt_cli_result;

/* Runs `TT_CLI_PATH <args>` through the shell (args are printf-formatted and
 * must be quoted by the caller where needed). Returns r->status. */
int tt_cli_run(tt_cli_result *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void tt_cli_result_free(tt_cli_result *r);

/* A path inside this test's temporary folder (created on first use, removed
 * with everything in it at exit). The string lives until 8 more calls. */
const char *tt_cli_tmp(const char *name);

/* A whole file read into memory (NUL-terminated); NULL if unreadable. */
unsigned char *tt_test_read_file(const char *path, long *size);

#endif
