/* kgyro: run, benchmark, render and view KineticGyro scenes. */
#include "commands.h"

#include <stdio.h>
#include <string.h>

typedef struct kg_command {
    const char* name;
    int (*fn)(int argc, char** argv);
    const char* summary;
} kg_command;

static const kg_command kCommands[] = {
    {"run", kg_cmd_run, "run a scene and write body states (and contacts) as CSV"},
    {"bench", kg_cmd_bench, "benchmark scenes in kgyro and the peer engines"},
    {"render", kg_cmd_render, "render a scene offscreen to GIF and PNG"},
    {"view", kg_cmd_view, "open a scene in an interactive window"},
    {"info", kg_cmd_info, "list the backends and OpenCL devices found"},
};

static void kg_usage(FILE* out)
{
    fprintf(out, "usage: kgyro COMMAND [OPTIONS]\n\ncommands:\n");
    for (size_t i = 0; i < sizeof kCommands / sizeof kCommands[0]; ++i) {
        fprintf(out, "  %-8s %s\n", kCommands[i].name, kCommands[i].summary);
    }
    fprintf(out, "\n'kgyro COMMAND --help' explains each command's options.\n");
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        kg_usage(stderr);
        return 2;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        kg_usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < sizeof kCommands / sizeof kCommands[0]; ++i) {
        if (strcmp(argv[1], kCommands[i].name) == 0) {
            return kCommands[i].fn(argc - 1, argv + 1);
        }
    }
    fprintf(stderr, "kgyro: unknown command '%s'\n", argv[1]);
    kg_usage(stderr);
    return 2;
}
