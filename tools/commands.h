/* The kgyro command line: one function per sub-command, each in tools/cmd_NAME.c.
 * Each returns the process exit code: 0 success, 1 failure, 2 bad input or usage. */
#ifndef KG_TOOLS_COMMANDS_H
#define KG_TOOLS_COMMANDS_H

int kg_cmd_run(int argc, char** argv);
int kg_cmd_bench(int argc, char** argv);
int kg_cmd_render(int argc, char** argv);
int kg_cmd_view(int argc, char** argv);
int kg_cmd_info(int argc, char** argv);

#endif
