/* Placeholder until this command is built; replaced by its real implementation. */
#include "commands.h"

#include <stdio.h>

int kg_cmd_bench(int argc, char** argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "kgyro bench: not built yet\n");
    return 1;
}
