/* Placeholder entry point until the CLI lands. */
#include <stdio.h>

#include "treetrace/treetrace.h"

int main(void)
{
    printf("treetrace %s\n", tt_version());
    return 0;
}
