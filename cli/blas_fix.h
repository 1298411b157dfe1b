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

/* The BLAS thread policy of the CLI: 1 thread, unless OPENBLAS_NUM_THREADS,
 * GOTO_NUM_THREADS, OMP_NUM_THREADS, BLIS_NUM_THREADS or MKL_NUM_THREADS is set (then the
 * BLAS keeps what they say). Why (bench/results/blas-threads-amd-epyc-2cpu.txt): on the
 * shared 2-core machine (load 5-12), a second thread changed the median wall time of a
 * 50k- or 108k-tet factorization by -2% to +29% and cost 7-41% more CPU time, in each of
 * 9 measurements; and the count is not chosen from the load average, because OpenBLAS's
 * dpotrf blocks differently with 1 and 2 threads (results differ in the last bits), so a
 * load-dependent count would make a run, and a restart's "bit for bit", depend on what
 * else the machine runs. Returns 1 when it set 1 thread, 0 when it left the BLAS alone. */
int eo_cli_blas_threads(void);
/* Why the BLAS has the threads it has, after eo_cli_blas_threads: "OPENBLAS_NUM_THREADS=2
 * (user)", "1 (elastopt's default; ...)"; "" before. Static. */
const char *eo_cli_blas_threads_note(void);

#endif
