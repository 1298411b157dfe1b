/* elastopt: command-line front end. One file per subcommand (cmd_<name>.c), one line
 * per subcommand in the table below. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "blas_fix.h"
#include "cli.h"
#include "eo_build_config.h"
#include "elastopt/plugin.h"
#include "petsc_load.h"

extern const eo_cli_command eo_cmd_list, eo_cmd_help;
extern const eo_cli_command eo_cmd_material;
extern const eo_cli_command eo_cmd_mesh, eo_cmd_convert;
extern const eo_cli_command eo_cmd_run, eo_cmd_check;
extern const eo_cli_command eo_cmd_bench;
extern const eo_cli_command eo_cmd_poisson, eo_cmd_stability;

const eo_cli_command *const eo_cli_commands[] = {
    &eo_cmd_list,
    &eo_cmd_help,
    &eo_cmd_run, &eo_cmd_check,
    &eo_cmd_mesh, &eo_cmd_convert,
    &eo_cmd_material,
    &eo_cmd_bench,
    &eo_cmd_poisson, &eo_cmd_stability,
    NULL,
};

int eo_cli_fail(eo_ctx *ctx, int rc)
{
    const char *m = eo_ctx_message(ctx);
    fprintf(stderr, "elastopt: error: %s\n", m && *m ? m : eo_status_string(rc));
    return EO_EXIT_BAD_INPUT;
}

int eo_cli_usage_error(const eo_cli_command *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "elastopt %s: ", cmd->name);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\nusage: %s", cmd->usage);
    va_end(ap);
    return EO_EXIT_BAD_INPUT;
}

int eo_cli_wants_help(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) return 1;
    return 0;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: elastopt COMMAND [options]\n\n"
               "Deformable-body simulation where every implicit step is an optimization problem.\n\n"
               "commands:\n");
    for (const eo_cli_command *const *c = eo_cli_commands; *c; c++)
        fprintf(f, "  %-10s %s\n", (*c)->name, (*c)->summary);
    fprintf(f, "\nglobal option: --plugin FILE (repeatable; also ELASTOPT_PLUGINS=a.so:b.so) loads methods\n"
               "from a plug-in shared object (elastopt/plugin.h).\n"
               "global option: --no-blas-fix (also ELASTOPT_NO_BLAS_FIX=1) keeps OpenBLAS's own kernel choice;\n"
               "by default, when OpenBLAS runs a generic core (Prescott) on a CPU with AVX2 / AVX-512,\n"
               "elastopt executes itself again with OPENBLAS_CORETYPE set (elastopt(1), BLAS kernels).\n"
               "\n`elastopt COMMAND --help` documents each command.\n"
               "exit status: 0 success, 1 ran but did not converge, 2 bad input or usage.\n");
}

/* Load the plug-ins of ELASTOPT_PLUGINS (':'-separated) and of every `--plugin FILE`
 * (removed from argv, wherever it is). Returns 0, or 2 after printing the error. */
static int load_plugins(eo_ctx *ctx, int *argc, char **argv)
{
    const char *env = getenv("ELASTOPT_PLUGINS");
    if (env && *env) {
        char buf[4096];
        snprintf(buf, sizeof buf, "%s", env);
        for (char *save = NULL, *tok = strtok_r(buf, ":", &save); tok; tok = strtok_r(NULL, ":", &save))
            if (eo_plugin_load(ctx, tok) < 0) return eo_cli_fail(ctx, EO_ERR_IO);
    }
    int out = 1;
    for (int i = 1; i < *argc; i++) {
        if (strcmp(argv[i], "--plugin") == 0) {
            if (i + 1 >= *argc) {
                fprintf(stderr, "elastopt: error: --plugin needs a FILE\n");
                return EO_EXIT_BAD_INPUT;
            }
            if (eo_plugin_load(ctx, argv[++i]) < 0) return eo_cli_fail(ctx, EO_ERR_IO);
            continue;
        }
        argv[out++] = argv[i];
    }
    *argc = out;
    argv[out] = NULL;
    return 0;
}

/* Remove every `--no-blas-fix` from argv; returns 1 when there was one. */
static int take_no_blas_fix(int *argc, char **argv)
{
    int out = 1, found = 0;
    for (int i = 1; i < *argc; i++) {
        if (strcmp(argv[i], "--no-blas-fix") == 0) found = 1;
        else argv[out++] = argv[i];
    }
    *argc = out;
    argv[out] = NULL;
    return found;
}

int main(int argc, char **argv)
{
    /* First of all: OpenBLAS on a generic fallback core -> execute again with
     * OPENBLAS_CORETYPE (blas_fix.c). Same argv, so --no-blas-fix is still in it then. */
    int no_fix = 0;
    for (int i = 1; i < argc; i++) no_fix |= strcmp(argv[i], "--no-blas-fix") == 0;
    eo_cli_blas_fix(argv, no_fix);
    take_no_blas_fix(&argc, argv);
    eo_cli_blas_threads(); /* 1 BLAS thread unless the user chose (blas_fix.h) */

    eo_ctx *pctx = NULL; /* plug-ins register process-wide; this context only reports */
    if (eo_ctx_create(NULL, &pctx) < 0) {
        fprintf(stderr, "elastopt: out of memory\n");
        return EO_EXIT_BAD_INPUT;
    }
    int prc = load_plugins(pctx, &argc, argv);
    if (!prc) prc = eo_cli_petsc_load(pctx, &argc, argv); /* the PETSc / MPI backend, if built */
    eo_ctx_destroy(&pctx);
    if (prc) return prc;
    if (argc < 2) {
        usage(stderr);
        return EO_EXIT_BAD_INPUT;
    }
    if (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0) {
        usage(stdout);
        return EO_EXIT_OK;
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("elastopt %s (ABI %d)\n", EO_VERSION, eo_abi_version());
        return EO_EXIT_OK;
    }
    for (const eo_cli_command *const *c = eo_cli_commands; *c; c++) {
        if (strcmp((*c)->name, argv[1]) != 0) continue;
        if (eo_cli_wants_help(argc - 1, argv + 1)) {
            printf("usage: %s", (*c)->usage);
            return EO_EXIT_OK;
        }
        eo_ctx *ctx = NULL;
        if (eo_ctx_create(NULL, &ctx) < 0) {
            fprintf(stderr, "elastopt: out of memory\n");
            return EO_EXIT_BAD_INPUT;
        }
        eo_ctx_set_logger(ctx, eo_log_stderr, NULL, EO_LOG_WARN);
        eo_cli_petsc_attach(ctx); /* under mpirun: meshes read on rank 0, broadcast */
        int rc = (*c)->run(ctx, argc - 1, argv + 1);
        eo_ctx_destroy(&ctx);
        return rc;
    }
    fprintf(stderr, "elastopt: unknown command '%s'; valid:", argv[1]);
    for (const eo_cli_command *const *c = eo_cli_commands; *c; c++) fprintf(stderr, " %s", (*c)->name);
    fprintf(stderr, "\n");
    return EO_EXIT_BAD_INPUT;
}
