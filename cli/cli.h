/* The treetrace command-line tool: one file per command, dispatched from the
 * table in main.c. A command takes argv with argv[0] being its own name and
 * returns the process exit status. */
#ifndef TT_CLI_CLI_H
#define TT_CLI_CLI_H

#include <stdio.h>

/* Exit statuses. */
#define CLI_OK 0
#define CLI_RUNTIME 1 /* the work failed: unreadable scene, unwritable file ...  */
#define CLI_USAGE 2   /* the command line is wrong                              */

typedef struct cli_command {
    const char *name;
    const char *summary; /* one line for `treetrace --help`                     */
    int (*run)(int argc, char **argv);
    void (*help)(FILE *out); /* NULL: `help CMD` runs `CMD --help`            */
} cli_command;

/* The commands (cmd_*.c). To add one: write cli/cmd_<name>.c (or a folder
 * cli/<name>/) with its run function (and a help function, or NULL if it
 * handles --help itself), declare it here or include its header in main.c,
 * and add one line to the table in main.c, e.g. for the benchmark:
 *     {"bench", "reproduce the papers' tables", tt_cli_bench, NULL},        */
int cmd_render(int argc, char **argv);
void cmd_render_help(FILE *out);
int cmd_info(int argc, char **argv);
void cmd_info_help(FILE *out);
/* saved structures (cmd_build.c) */
int cmd_build(int argc, char **argv);
void cmd_build_help(FILE *out);

#endif
