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
#include "elastopt/suggest.h"
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

/* The options a usage text names: every "-x" / "--xyz" word (letters, digits, '-', '_'). */
static void usage_options(const char *usage, char *buf, size_t n)
{
    size_t k = 0;
    buf[0] = 0;
    for (const char *p = usage; *p && k + 1 < n; p++) {
        if (*p != '-' || (p > usage && p[-1] != ' ' && p[-1] != '[' && p[-1] != '|' && p[-1] != '(' &&
                          p[-1] != '\n'))
            continue;
        const char *q = p;
        while (*q == '-') q++;
        if (q - p > 2 || !((*q >= 'a' && *q <= 'z') || (*q >= 'A' && *q <= 'Z'))) continue;
        while ((*q >= 'a' && *q <= 'z') || (*q >= 'A' && *q <= 'Z') || (*q >= '0' && *q <= '9') || *q == '-' ||
               *q == '_')
            q++;
        k += (size_t)snprintf(buf + k, n - k, "%s%.*s", k ? " " : "", (int)(q - p), p);
        p = q - 1;
    }
}

int eo_cli_unknown_arg(const eo_cli_command *cmd, const char *what, const char *arg)
{
    char opts[2048], hint[160] = "";
    if (arg[0] == '-') {
        usage_options(cmd->usage, opts, sizeof opts);
        /* "--model=x": suggest for the part before '=' */
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)strcspn(arg, "="), arg);
        eo_suggest_hint(name, opts, NULL, hint, sizeof hint);
    }
    return eo_cli_usage_error(cmd, "unknown %s '%s'%s", what, arg, hint);
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
    char names[512], hint[128];
    size_t k = 0;
    names[0] = 0;
    for (const eo_cli_command *const *c = eo_cli_commands; *c && k < sizeof names; c++)
        k += (size_t)snprintf(names + k, sizeof names - k, " %s", (*c)->name);
    eo_suggest_hint(argv[1], names, NULL, hint, sizeof hint);
    fprintf(stderr, "elastopt: unknown command '%s'%s; valid:%s\n", argv[1], hint, names);
    return EO_EXIT_BAD_INPUT;
}
