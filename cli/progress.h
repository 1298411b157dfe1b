/* What `elastopt run` prints while it runs (progress.c).
 *   quiet     nothing (errors only, printed elsewhere)
 *   normal    on a terminal (isatty(stderr)): one progress line redrawn with \r: step
 *             k/N, simulated time, wall time per step, ETA, iterations of the last
 *             step, worst reason so far; not a terminal: that line as a line of its own
 *             at most every 5 s
 *   verbose   one line per step
 * All of it on stderr. The closing line (eo_cli_progress_closing) goes to stdout. */
#ifndef ELASTOPT_CLI_PROGRESS_H
#define ELASTOPT_CLI_PROGRESS_H
#include <stdio.h>

#include "run_output.h"

typedef enum eo_cli_verbosity { EO_CLI_QUIET = 0, EO_CLI_NORMAL = 1, EO_CLI_VERBOSE = 2 } eo_cli_verbosity;

typedef struct eo_cli_progress {
    eo_cli_verbosity verbosity;
    int tty;             /* stderr is a terminal */
    int nsteps;          /* target step count */
    int first;           /* steps already done when this process started (a restart) */
    double t_start;      /* wall clock at init */
    double last_print;   /* wall clock of the last line (not a terminal) or redraw */
    int worst, worst_step;  /* worst reason so far and its first step */
    int line_open;       /* a \r line is on the terminal */
} eo_cli_progress;

void eo_cli_progress_init(eo_cli_progress *p, eo_cli_verbosity v, int nsteps, int first);
/* After a completed step. */
void eo_cli_progress_step(eo_cli_progress *p, const eo_run_record *r);
/* Before any other output (an error, the closing line): end the \r line. */
void eo_cli_progress_done(eo_cli_progress *p);
/* "38/40 converged; steps 12, 31: diverged_max_iters (100 iterations); ..." for the
 * records rec[0..nrec-1] of a run of nsteps steps, into buf. */
void eo_cli_progress_closing(const eo_run_record *rec, int nrec, int nsteps, char *buf, size_t n);
/* Worst-first rank of a reason: 0 converged, 1 ran out (iterations, time, stagnated),
 * 2 failed (line search, direction, linear solve, ...), 3 non-finite. */
int eo_cli_reason_rank(int reason);
#endif
