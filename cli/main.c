/* Placeholder entry point until the CLI lands; dispatches `bench`. */
#include <stdio.h>
#include <string.h>

#include "bench/bench.h"
#include "treetrace/treetrace.h"

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "bench") == 0) return tt_cli_bench(argc - 1, argv + 1);
    printf("treetrace %s\n", tt_version());
    return 0;
}
