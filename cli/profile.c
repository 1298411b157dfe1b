/* `--profile`: the solver's time per phase, per step and in total (PETSc's -log_view
 * idea for one optimizer): assembly (Hessian: element kernels + scatter), factorization
 * (symbolic = analyze, once per pattern; numeric), solves, line search (its objective
 * evaluations included), gradients outside the line search, other (the rest of the
 * minimization: stopping tests, Hessian-fix bookkeeping, vector updates, logging
 * callbacks), and the ratio of one Newton iteration to one numeric factorization,
 * (total / iterations) / (numeric / factorizations). CPU seconds of the solving thread
 * (eo_cputime, the c_* fields of eo_solver_get_profile, shown through eo_profile_cpu_view):
 * they do not grow while the thread waits for a core on a shared machine; this file only
 * prints. First line: the BLAS that
 * factorized (eo_blas_describe: name, version, core, threads, "(fixed from Prescott)"). */
#include "profile.h"

#include <math.h>
#include <string.h>

#include "blas_fix.h"
#include "elastopt/machine.h"

static const eo_profile *solver_profile(const eo_sim *sim)
{
    eo_solver *s = eo_sim_solver(sim);
    return s ? eo_solver_get_profile(s) : NULL;
}

void eo_cli_profile_begin(eo_cli_profile *p, int on, const eo_sim *sim)
{
    memset(p, 0, sizeof *p);
    p->on = on;
    p->out = stdout;
    const eo_profile *pr = solver_profile(sim);
    if (pr) p->last = *pr;
    if (on) eo_cli_profile_blas(p->out);
}

void eo_cli_profile_blas(FILE *out)
{
    char line[640];
    eo_blas_describe(line, sizeof line);
    const char *why = eo_cli_blas_threads_note();
    fprintf(out, "profile: %s%s%s\n", line, *why ? "; threads: " : "", why);
    fprintf(out, "profile: seconds are CPU seconds of the solving thread (CLOCK_THREAD_CPUTIME_ID)\n");
}

void eo_cli_profile_step(eo_cli_profile *p, const eo_sim *sim, int step)
{
    if (!p->on) return;
    const eo_profile *now = solver_profile(sim);
    if (!now) return;
    eo_profile dw, d;
    eo_profile_diff(now, &p->last, &dw);
    eo_profile_cpu_view(&dw, &d);
    p->last = *now;
    if (!d.minimizations) return; /* explicit step: no solver */
    double ratio = eo_profile_iteration_ratio(&d);
    fprintf(p->out,
            "profile step %d: %ld it %.4f s | assembly %.4f (%ld) | factor symbolic %.4f (%ld) numeric %.4f (%ld) | "
            "not PD %ld | solve %.4f (%ld) | line search %.4f (%ld evals) | gradient %.4f (%ld) | other %.4f | iteration/factor ",
            step, d.iterations, d.t_total, d.t_assembly, d.n_assembly, d.t_analyze, d.n_analyze, d.t_factor,
            d.n_factor, d.n_not_pd, d.t_solve, d.n_solve, d.t_linesearch, d.n_ls_evals, d.t_gradient, d.n_gradient,
            eo_profile_other(&d));
    if (isfinite(ratio)) fprintf(p->out, "%.3f\n", ratio);
    else fprintf(p->out, "-\n");
}

static void row(FILE *out, const char *name, double t, long n, double total)
{
    fprintf(out, "  %-22s %10.4f %6.1f%%", name, t, total > 0 ? 100 * t / total : 0.0);
    if (n >= 0) fprintf(out, " %8ld %12.6f\n", n, n > 0 ? t / (double)n : 0.0);
    else fprintf(out, " %8s %12s\n", "", "");
}

void eo_cli_profile_print(FILE *out, const char *title, const eo_profile *pr)
{
    const double T = pr->t_total;
    fprintf(out, "profile %s: %ld minimizations, %ld iterations, %.4f CPU s in the solver\n", title, pr->minimizations,
            pr->iterations, T);
    fprintf(out, "  %-22s %10s %7s %8s %12s\n", "phase", "seconds", "share", "calls", "s/call");
    row(out, "assembly (Hessian)", pr->t_assembly, pr->n_assembly, T);
    row(out, "factor: symbolic", pr->t_analyze, pr->n_analyze, T);
    row(out, "factor: numeric", pr->t_factor, pr->n_factor, T);
    fprintf(out, "  %-22s %10s %7s %8ld\n", "  not pos. definite", "", "", pr->n_not_pd);
    row(out, "solve", pr->t_solve, pr->n_solve, T);
    row(out, "line search", pr->t_linesearch, pr->n_ls_evals, T);
    row(out, "gradient", pr->t_gradient, pr->n_gradient, T);
    row(out, "other", eo_profile_other(pr), -1, T);
    double ratio = eo_profile_iteration_ratio(pr);
    if (isfinite(ratio))
        fprintf(out, "  iteration / numeric factorization: %.3f (%.4f s per iteration, %.4f s per factorization)\n",
                ratio, T / (double)pr->iterations, pr->t_factor / (double)pr->n_factor);
    else
        fprintf(out, "  iteration / numeric factorization: - (no factorization)\n");
}

void eo_cli_profile_total(eo_cli_profile *p, const eo_sim *sim, const char *title)
{
    if (!p->on) return;
    eo_solver *s = eo_sim_solver(sim);
    if (!s) return;
    eo_profile c;
    eo_profile_cpu_view(eo_solver_get_profile(s), &c);
    eo_cli_profile_print(p->out, title, &c);
    const eo_linsolve *ls = eo_solver_get_linsolve(s);
    if (ls && eo_linsolve_get_stats(ls)->n_analyze > 0) {
        /* the choice of solver.linear = auto; a reused factor makes most factor calls
         * no-ops, so the real numeric factorizations are counted apart */
        char d[256];
        const eo_linsolve_stats *st = eo_linsolve_get_stats(ls);
        fprintf(p->out, "  linear solver: %s", eo_linsolve_describe(ls, d, sizeof d));
        if (st->n_refactor > 0)
            fprintf(p->out, "; %ld numeric factorizations for %ld factor calls (the others reuse a factor as the CG "
                    "preconditioner)", st->n_refactor, st->n_factor);
        fputc('\n', p->out);
    }
}
