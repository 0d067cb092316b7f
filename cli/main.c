/* Entry point: global options (--help, --version), `help CMD`, and dispatch
 * to the command table. */
#include <string.h>

#include "bench/bench.h"
#include "cli.h"
#include "treetrace/treetrace.h"

static const cli_command commands[] = {
    {"render", "trace a scene: timings, statistics, PNG, hit buffer, heatmap", cmd_render,
     cmd_render_help},
    {"info", "load a scene, build a structure, print its statistics and check it", cmd_info,
     cmd_info_help},
    {"build", "build a structure and save it to a file (render --accel-file maps it)", cmd_build,
     cmd_build_help},
    {"bench", "reproduce the papers' tables against Embree: results.csv, report.md, figures",
     tt_cli_bench, bench_print_help},
};

#define COMMAND_COUNT (sizeof commands / sizeof commands[0])

static const cli_command *find_command(const char *name)
{
    for (size_t i = 0; i < COMMAND_COUNT; i++)
        if (strcmp(commands[i].name, name) == 0) return &commands[i];
    return NULL;
}

static void usage(FILE *out)
{
    fprintf(out,
            "usage: treetrace COMMAND [ARGS...]\n"
            "       treetrace help COMMAND | treetrace COMMAND --help\n"
            "       treetrace --version\n"
            "\n"
            "Ray traces triangle scenes (OBJ, PLY) through R-trees and kd-trees.\n"
            "\n"
            "commands:\n");
    for (size_t i = 0; i < COMMAND_COUNT; i++)
        fprintf(out, "  %-8s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\nstructures in this build:");
    for (const char *const *n = tt_accel_names(); *n; n++) fprintf(out, " %s", *n);
    fprintf(out, "\n");
}

static int unknown_command(const char *name)
{
    fprintf(stderr, "treetrace: unknown command '%s' (see treetrace --help)\n", name);
    return CLI_USAGE;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return CLI_USAGE;
    }
    const char *first = argv[1];
    if (strcmp(first, "--help") == 0 || strcmp(first, "-h") == 0) {
        usage(stdout);
        return CLI_OK;
    }
    if (strcmp(first, "--version") == 0 || strcmp(first, "-V") == 0) {
        printf("treetrace %s\n", tt_version());
        return CLI_OK;
    }
    if (strcmp(first, "help") == 0) {
        if (argc == 2) {
            usage(stdout);
            return CLI_OK;
        }
        if (argc > 3) {
            fprintf(stderr, "treetrace help: expected one command name, got %d arguments\n",
                    argc - 2);
            return CLI_USAGE;
        }
        const cli_command *c = find_command(argv[2]);
        if (!c) return unknown_command(argv[2]);
        if (c->help) {
            c->help(stdout);
            return CLI_OK;
        }
        /* a command without a help function answers `CMD --help` itself */
        static char help_option[] = "--help";
        char *help_argv[] = {argv[2], help_option, NULL};
        return c->run(2, help_argv);
    }
    if (first[0] == '-') {
        fprintf(stderr, "treetrace: unknown option '%s' (see treetrace --help)\n", first);
        return CLI_USAGE;
    }
    const cli_command *c = find_command(first);
    if (!c) return unknown_command(first);
    return c->run(argc - 1, argv + 1);
}
