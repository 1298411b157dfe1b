/* Shared pieces of the elastopt command: the subcommand table and helpers.
 * Exit status: 0 success, 1 ran but did not converge somewhere, 2 bad input or usage. */
#ifndef ELASTOPT_CLI_H
#define ELASTOPT_CLI_H

#include <stdio.h>

#include "elastopt/config.h"
#include "elastopt/ctx.h"

enum { EO_EXIT_OK = 0, EO_EXIT_NOT_CONVERGED = 1, EO_EXIT_BAD_INPUT = 2 };

typedef struct eo_cli_command {
    const char *name;
    const char *summary;  /* one line for `elastopt --help` */
    const char *usage;    /* full usage text for `elastopt CMD --help` */
    int (*run)(eo_ctx *ctx, int argc, char **argv);  /* argv[0] is the command name */
} eo_cli_command;

/* NULL-terminated, in main.c */
extern const eo_cli_command *const eo_cli_commands[];

/* Print "elastopt: error: <message>" for a failed library call and return 2. */
int eo_cli_fail(eo_ctx *ctx, int rc);
/* Print a usage error and return 2. */
int eo_cli_usage_error(const eo_cli_command *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Print "unknown <what> '<arg>'" with a "did you mean" among the options ("-x", "--xyz")
   of the command's usage text when arg starts with '-', then the usage; return 2. */
int eo_cli_unknown_arg(const eo_cli_command *cmd, const char *what, const char *arg);
/* 1 if argv has -h or --help. */
int eo_cli_wants_help(int argc, char **argv);

#endif
