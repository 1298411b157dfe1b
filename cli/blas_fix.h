/* Run on the CPU's own BLAS kernels: re-execute once with OPENBLAS_CORETYPE when the
 * loaded OpenBLAS runs a generic fallback core (cli/blas_fix.c). Used by the CLI and the
 * benchmark programs; the library only reports (machine.h), it never executes. */
#ifndef ELASTOPT_CLI_BLAS_FIX_H
#define ELASTOPT_CLI_BLAS_FIX_H

/* Call first in main, with main's argv (argv[argc] == NULL). Returns when nothing was
 * done: no fallback, opted out (no_fix, ELASTOPT_NO_BLAS_FIX=1), OPENBLAS_CORETYPE set
 * by the user (unless ELASTOPT_BLAS_FIX=force), already re-executed
 * (ELASTOPT_BLAS_FIXED_FROM), under valgrind, or the exec failed (a warning on stderr);
 * otherwise execv("/proc/self/exe", argv) does not return. */
void eo_cli_blas_fix(char **argv, int no_fix);

#endif
