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

/* The BLAS thread policy of the CLI: when none of OPENBLAS_NUM_THREADS,
 * GOTO_NUM_THREADS, OMP_NUM_THREADS, BLIS_NUM_THREADS, MKL_NUM_THREADS is set, the BLAS
 * runs 1 thread unless the machine is idle (1-minute load average + 1 <= cores online),
 * when it keeps its default (one per core; OpenBLAS itself runs small calls on one
 * thread). Measured (bench/results/blas-threads-amd-epyc-2cpu.txt): on the shared
 * 2-core machine (load 5-12), a second thread changed the median wall time of a 50k- or
 * 108k-tet factorization by -2% to +29% and cost 7-41% more CPU time, in each of 9
 * measurements. Returns the thread count set, 0 when it left the BLAS alone. */
int eo_cli_blas_threads(void);
/* Why the BLAS has the threads it has, after eo_cli_blas_threads: "OPENBLAS_NUM_THREADS=2
 * (user)", "1 (busy machine: load 7.26 on 2 cores)", "default (idle machine: load ...)";
 * "" before. Static. */
const char *eo_cli_blas_threads_note(void);

#endif
