/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_cli.c
 * @brief `sfit`: the host command-line tool; dispatches to sub-commands.
 *
 * Exit status: 0 ok, 1 the computation failed, 2 usage error, 3 file error.
 */
#include <string.h>

#include "cli.h"

typedef struct cli_command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *help;
} cli_command_t;

#define CLI_COMMAND_ROW(name, entry, help) {name, entry, help},
static const cli_command_t commands[] = {CLI_COMMANDS(CLI_COMMAND_ROW)};
#undef CLI_COMMAND_ROW

/* The build system passes the project version (CMakeLists.txt project()). */
#ifndef SFIT_CLI_VERSION
#error "SFIT_CLI_VERSION must be defined by the build (tools/CMakeLists.txt)"
#endif

static void usage(FILE *f)
{
    size_t i;
    fprintf(f, "sfit %s: sphere and circle fitting (GDKE / UGDK)\n"
               "usage: sfit COMMAND [options] FILE...\n"
               "       sfit help [COMMAND]   (or sfit COMMAND --help: every option)\n"
               "       sfit --version\n",
            SFIT_CLI_VERSION);
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        fprintf(f, "  %-9s %s\n", commands[i].name, commands[i].help);
    }
}

int main(int argc, char **argv)
{
    size_t i;
    if (argc < 2) {
        usage(stderr);
        return CLI_USAGE;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(stdout);
        return CLI_OK;
    }
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "-V") == 0) {
        printf("sfit %s\n", SFIT_CLI_VERSION);
        return CLI_OK;
    }
    if (strcmp(argv[1], "help") == 0) {
        if (argc < 3) {
            usage(stdout);
            return CLI_OK;
        }
        for (i = 0; i < sizeof commands / sizeof commands[0]; i++) {
            if (strcmp(argv[2], commands[i].name) == 0) {
                static char help_opt[] = "--help";
                char *av[3] = {argv[2], help_opt, NULL};
                return commands[i].run(2, av);
            }
        }
        fprintf(stderr, "sfit: no command '%s' (sfit help lists them)\n", argv[2]);
        return CLI_USAGE;
    }
    for (i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(argv[1], commands[i].name) == 0) {
            return commands[i].run(argc - 1, argv + 1);
        }
    }
    fprintf(stderr, "sfit: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return CLI_USAGE;
}
