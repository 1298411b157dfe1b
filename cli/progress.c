/* Progress display and closing line of `elastopt run` (progress.h). */
#define _POSIX_C_SOURCE 200809L
#include "progress.h"

#include <math.h>
#include <string.h>
#include <unistd.h>

#include "elastopt/ctx.h"
#include "elastopt/status.h"

enum { PLAIN_EVERY_S = 5 };

int eo_cli_reason_rank(int reason)
{
    if (reason > 0) return 0;
    if (reason == EO_DIVERGED_NONFINITE) return 3;
    if (reason == EO_DIVERGED_MAX_ITERS || reason == EO_DIVERGED_TIME_BUDGET || reason == EO_DIVERGED_STAGNATED)
        return 1;
    return 2;
}

static void fmt_dur(double s, char *buf, size_t n)
{
    if (!(s >= 0)) snprintf(buf, n, "?");
    else if (s < 10) snprintf(buf, n, "%.2g s", s);
    else if (s < 60) snprintf(buf, n, "%.0f s", s);
    else if (s < 3600) snprintf(buf, n, "%dm%02ds", (int)(s / 60), (int)s % 60);
    else snprintf(buf, n, "%dh%02dm", (int)(s / 3600), (int)(s / 60) % 60);
}

void eo_cli_progress_init(eo_cli_progress *p, eo_cli_verbosity v, int nsteps, int first)
{
    memset(p, 0, sizeof *p);
    p->verbosity = v;
    p->tty = isatty(2);
    p->nsteps = nsteps;
    p->first = first;
    p->t_start = p->last_print = eo_wtime();
    p->worst = 1;
    p->worst_step = 0;
}

void eo_cli_progress_step(eo_cli_progress *p, const eo_run_record *r)
{
    if (p->verbosity == EO_CLI_QUIET) return;
    if (eo_cli_reason_rank(r->reason) > eo_cli_reason_rank(p->worst) || (p->worst_step == 0 && r->reason <= 0)) {
        p->worst = r->reason;
        p->worst_step = r->step;
    }
    double now = eo_wtime();
    if (p->verbosity == EO_CLI_VERBOSE) {
        fprintf(stderr, "step %d/%d  t = %.6g s  %s  %d iterations  %.3g s  min J %.4g  inverted %d  elastic %.6g J",
                r->step, p->nsteps, r->t, eo_reason_name(r->reason), r->iterations, r->wall, r->stats.min_J,
                r->stats.inverted, r->stats.elastic);
        if (r->rejected || r->substeps > 1) /* adaptive stepping */
            fprintf(stderr, "  %d substeps (smallest %.4g s), %d rejected", r->substeps, r->min_substep, r->rejected);
        fputc('\n', stderr);
        fflush(stderr);
        return;
    }
    int last = r->step >= p->nsteps;
    if (p->tty ? (now - p->last_print < 0.1 && !last) : (now - p->last_print < PLAIN_EVERY_S)) return;
    p->last_print = now;
    int done = r->step - p->first;
    double per = done > 0 ? (now - p->t_start) / done : 0;
    char pers[32], eta[32], worst[96];
    fmt_dur(per, pers, sizeof pers);
    fmt_dur(per * (p->nsteps - r->step), eta, sizeof eta);
    if (p->worst > 0) snprintf(worst, sizeof worst, eo_reason_is_explicit(p->worst) ? "all explicit" : "all converged");
    else snprintf(worst, sizeof worst, "worst %s (step %d)", eo_reason_name(p->worst), p->worst_step);
    fprintf(stderr, "%sstep %d/%d  t = %.4g s  %s/step  ETA %s  last %d iterations  %s%s", p->tty ? "\r\033[K" : "",
            r->step, p->nsteps, r->t, pers, eta, r->iterations, worst, p->tty ? "" : "\n");
    p->line_open = p->tty;
    fflush(stderr);
}

void eo_cli_progress_done(eo_cli_progress *p)
{
    if (p->line_open) fputc('\n', stderr);
    p->line_open = 0;
    fflush(stderr);
}

void eo_cli_progress_closing(const eo_run_record *rec, int nrec, int nsteps, char *buf, size_t n)
{
    int nconv = 0, nexpl = 0;
    for (int k = 0; k < nrec; k++) {
        nexpl += eo_reason_is_explicit(rec[k].reason);
        nconv += eo_reason_is_converged(rec[k].reason) && !eo_reason_is_explicit(rec[k].reason);
    }
    size_t u;
    if (nexpl && !nconv) u = (size_t)snprintf(buf, n, "%d/%d explicit", nexpl, nsteps);
    else if (nexpl) u = (size_t)snprintf(buf, n, "%d/%d converged, %d explicit", nconv, nsteps, nexpl);
    else u = (size_t)snprintf(buf, n, "%d/%d converged", nconv, nsteps);
    /* failing steps grouped by reason, in order of first appearance */
    for (int k = 0; k < nrec && u < n; k++) {
        int reason = rec[k].reason;
        if (reason > 0) continue;
        int seen = 0;
        for (int j = 0; j < k && !seen; j++) seen = rec[j].reason == reason;
        if (seen) continue;
        int count = 0, imin = rec[k].iterations, imax = rec[k].iterations;
        for (int j = k; j < nrec; j++) {
            if (rec[j].reason != reason) continue;
            if (rec[j].iterations < imin) imin = rec[j].iterations;
            if (rec[j].iterations > imax) imax = rec[j].iterations;
            count++;
        }
        u += (size_t)snprintf(buf + u, n - u, "; step%s ", count > 1 ? "s" : "");
        int listed = 0;
        for (int j = k; j < nrec && u < n; j++) {
            if (rec[j].reason != reason) continue;
            if (listed == 8) {
                u += (size_t)snprintf(buf + u, n - u, " and %d more", count - listed);
                break;
            }
            u += (size_t)snprintf(buf + u, n - u, "%s%d", listed ? ", " : "", rec[j].step);
            listed++;
        }
        if (u >= n) break;
        if (imin == imax)
            u += (size_t)snprintf(buf + u, n - u, ": %s (%d iteration%s)", eo_reason_name(reason), imax,
                                  imax == 1 ? "" : "s");
        else u += (size_t)snprintf(buf + u, n - u, ": %s (%d-%d iterations)", eo_reason_name(reason), imin, imax);
    }
    long rejected = 0;
    double hmin = INFINITY;
    for (int k = 0; k < nrec; k++) {
        rejected += rec[k].rejected;
        if (rec[k].rejected && rec[k].min_substep < hmin) hmin = rec[k].min_substep;
    }
    if (u < n && rejected) /* adaptive stepping */
        u += (size_t)snprintf(buf + u, n - u, "; %ld attempt%s rejected and retried in substeps (smallest %.4g s)",
                              rejected, rejected == 1 ? "" : "s", hmin);
    if (u < n && nrec < nsteps) snprintf(buf + u, n - u, "; %d of %d steps run", nrec, nsteps);
}
