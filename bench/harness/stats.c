/* The optimizer benchmark harness (bench.h): statistics. Time to an accuracy (the first
 * iterate meeting it), error at a budget, median and spread; a configuration's status
 * on a scene; the Pareto summary of the own-stopping-rule runs; the performance and data
 * profiles' numbers. No I/O. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_impl.h"

/* A step function: the time of the first iterate that meets the threshold. No time
 * between two iterates is ever reported: an iterate exists only once the iteration that
 * produced it has ended (its line search included), so a threshold met by the first
 * iterate after x0 costs the whole first iteration. */
double eo_bench_time_to(int n, const double *t, const double *err, double thr)
{
    for (int k = 0; k < n; k++)
        if (err[k] <= thr) return t[k];
    return INFINITY;
}

double eo_bench_error_at(int n, const double *t, const double *err, double budget)
{
    if (n <= 0) return NAN;
    double e = err[0];
    for (int k = 0; k < n && t[k] <= budget; k++) e = err[k];
    return e;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double eo_bench_median(int n, const double *v, double *vmin, double *vmax)
{
    double w[64];
    int m = 0;
    for (int i = 0; i < n && m < 64; i++)
        if (!isnan(v[i])) w[m++] = v[i];
    if (vmin) *vmin = NAN;
    if (vmax) *vmax = NAN;
    if (!m) return NAN;
    qsort(w, (size_t)m, sizeof w[0], cmp_double);
    if (vmin) *vmin = w[0];
    if (vmax) *vmax = w[m - 1];
    if (m % 2) return w[m / 2];
    double a = w[m / 2 - 1], b = w[m / 2];
    if (isinf(a) || isinf(b)) return b;
    return 0.5 * (a + b);
}

/* A trajectory that satisfies its own stopping rule on every step but ends farther than
 * this fraction of the reference motion (RMS displacement over the measured steps) from
 * the reference has found another stationary point: status "elsewhere". */
#define ELSEWHERE 1e-2

void bench_aggregate(const eo_bench_suite *s, int repeats, bench_pair *p, int is_traj, double ref_disp,
                      const int *meas)
{
    for (int j = 0; j < s->nthr; j++) {
        double tot[BENCH_MAX_REPEATS];
        for (int q = 0; q < repeats; q++) {
            tot[q] = 0;
            for (int k = 0; k < p->nsteps; k++) tot[q] += p->st[k].ttt[j][q];
        }
        p->ttt_med[j] = eo_bench_median(repeats, tot, &p->ttt_min[j], &p->ttt_max[j]);
    }
    for (int j = 0; j < s->nbud; j++) {
        double worst[BENCH_MAX_REPEATS];
        for (int q = 0; q < repeats; q++) {
            worst[q] = -INFINITY;
            for (int k = 0; k < p->nsteps; k++) worst[q] = fmax(worst[q], p->st[k].eab[j][q]);
        }
        p->eab_med[j] = eo_bench_median(repeats, worst, NULL, NULL);
    }
    p->steps_reached = 0;
    for (int k = 0; k < p->nsteps; k++) {
        p->steps_reached += p->st[k].reached;
        p->nonfinite |= p->st[k].nonfinite;
        p->nan |= p->st[k].nan;
    }
    p->first_bad_step = -1;
    p->traj_converged = 0;
    p->traj_time = 0;
    p->traj_max_dist = 0;
    p->traj_final_dist = NAN;
    if (is_traj) {
        for (int k = 0; k < p->traj_done; k++) {
            const bench_traj_res *t = p->tr + k;
            p->nonfinite |= t->nonfinite;
            p->nan |= t->nan;
            if (t->reason > 0) p->traj_converged++;
            else if (p->first_bad_step < 0) {
                p->first_bad_step = k;
                p->first_bad_reason = t->reason;
            }
            p->traj_time += t->time;
            p->traj_max_dist = fmax(p->traj_max_dist, t->dist);
            p->traj_final_dist = t->dist;
        }
        if (p->traj_done < p->ntraj && p->first_bad_step < 0) {
            p->first_bad_step = p->traj_done;
            p->first_bad_reason = EO_DIVERGED_NONFINITE;
        }
    } else {
        for (int k = 0; k < p->nsteps; k++)
            if (!p->st[k].reached && p->first_bad_step < 0) {
                p->first_bad_step = k;
                p->first_bad_reason = p->st[k].reason;
            }
    }
    /* the failing step counted from the scene's start */
    const int bad = p->first_bad_step >= 0 ? p->first_bad_step : 0;
    const int scene_step = is_traj ? p->traj_first + bad : meas[bad < p->nsteps ? bad : 0];
    if (p->nonfinite) {
        snprintf(p->status, sizeof p->status, "non-finite");
        snprintf(p->reason, sizeof p->reason, "%s (step %d: %s)",
                 p->nan ? "NaN or non-finite positions returned"
                        : "non-finite g or gradient met, run stopped; returned positions finite",
                 scene_step + 1,
                 p->first_bad_step >= 0 ? eo_reason_name(p->first_bad_reason) : "curve run");
    } else if (p->first_bad_step < 0 && is_traj && p->traj_max_dist > ELSEWHERE * fmax(ref_disp, 1e-12)) {
        snprintf(p->status, sizeof p->status, "elsewhere");
        snprintf(p->reason, sizeof p->reason,
                 "own rule satisfied on every step, but up to %.2g m (%.0f%% of the reference motion) away from the "
                 "reference trajectory: another stationary point",
                 p->traj_max_dist, 100 * p->traj_max_dist / fmax(ref_disp, 1e-12));
    } else if (p->first_bad_step < 0) {
        snprintf(p->status, sizeof p->status, "converged");
        snprintf(p->reason, sizeof p->reason, "%s", is_traj ? "converged on every step" : "reached target on every step");
    } else {
        snprintf(p->status, sizeof p->status, "stopped");
        snprintf(p->reason, sizeof p->reason, "step %d: %s", scene_step + 1, eo_reason_name(p->first_bad_reason));
    }
}

/* Fastest and second fastest configuration of a scene at threshold j (-1 if none). */
void bench_fastest(const bench_out *b, int si, int j, int *first, int *second)
{
    *first = *second = -1;
    const bench_scene_res *sr = b->res + si;
    for (int c = 0; c < b->s->ncf; c++) {
        double t = sr->pair[c].ttt_med[j];
        if (!isfinite(t)) continue;
        if (*first < 0 || t < sr->pair[*first].ttt_med[j]) {
            *second = *first;
            *first = c;
        } else if (*second < 0 || t < sr->pair[*second].ttt_med[j]) {
            *second = c;
        }
    }
}


/* Two ratios within 2 % of each other are a tie for the Pareto front: closer than the
 * table's digits and the timing noise (converged configurations share the reference's
 * distance to a few digits; without it a 1.3x slower one is "on the front" by 1e-3). */
static int pareto_tie(double a, double b) { return fabs(log(a / b)) < log(1.02); }

int bench_pareto_compute(eo_ctx *ctx, const bench_out *b, pareto_pts *pp)
{
    const eo_bench_suite *s = b->s;
    pp->x = eo_malloc(ctx, 2 * (size_t)s->ncf * sizeof(double));
    pp->n = eo_calloc(ctx, 3 * (size_t)s->ncf, sizeof(int));
    if (!pp->x || !pp->n) {
        eo_free(ctx, pp->x);
        eo_free(ctx, pp->n);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    }
    pp->y = pp->x + s->ncf;
    pp->conv = pp->n + s->ncf;
    pp->front = pp->conv + s->ncf;
    for (int c = 0; c < s->ncf; c++) {
        double lx = 0, ly = 0;
        int n = 0, conv = 1;
        for (int si = 0; si < s->nsc; si++) {
            const bench_pair *p = b->res[si].pair + c, *base = b->res[si].pair + s->baseline;
            conv &= strcmp(p->status, "converged") == 0;
            if (!(p->traj_time > 0) || !(base->traj_time > 0) || !isfinite(p->traj_max_dist) || p->traj_done < 1 ||
                base->traj_done < 1)
                continue;
            double d = p->traj_max_dist / fmax(b->res[si].ref_disp, 1e-12);
            lx += log((p->traj_time / p->traj_done) / (base->traj_time / base->traj_done));
            ly += log(fmax(d, 1e-16));
            n++;
        }
        pp->x[c] = n ? exp(lx / n) : NAN;
        pp->y[c] = n ? exp(ly / n) : NAN;
        pp->n[c] = n;
        pp->conv[c] = conv && n > 0;
    }
    for (int c = 0; c < s->ncf; c++) {
        if (!pp->conv[c]) continue;
        int dominated = 0;
        for (int d = 0; d < s->ncf; d++) {
            if (d == c || !pp->conv[d]) continue;
            const int nx = pareto_tie(pp->x[d], pp->x[c]), ny = pareto_tie(pp->y[d], pp->y[c]);
            if ((nx || pp->x[d] < pp->x[c]) && (ny || pp->y[d] < pp->y[c]) &&
                ((!nx && pp->x[d] < pp->x[c]) || (!ny && pp->y[d] < pp->y[c])))
                dominated = 1;
        }
        pp->front[c] = !dominated;
    }
    return EO_OK;
}

void bench_pareto_free(eo_ctx *ctx, pareto_pts *pp)
{
    eo_free(ctx, pp->x);
    eo_free(ctx, pp->n);
}

/* The fastest configuration that converged everywhere (-1 if none) and the closest;
 * among ties (pareto_tie) with the fastest, the closer; with the closest, the faster. */
void bench_pareto_winners(const eo_bench_suite *s, const pareto_pts *pp, int *fast, int *close)
{
    *fast = *close = -1;
    for (int c = 0; c < s->ncf; c++) {
        if (!pp->conv[c]) continue;
        if (*fast < 0 || pp->x[c] < pp->x[*fast]) *fast = c;
        if (*close < 0 || pp->y[c] < pp->y[*close]) *close = c;
    }
    if (*fast < 0) return;
    const double x0 = pp->x[*fast], y0 = pp->y[*close];
    for (int c = 0; c < s->ncf; c++) {
        if (!pp->conv[c]) continue;
        if (pareto_tie(pp->x[c], x0) && pp->y[c] < pp->y[*fast]) *fast = c;
        if (pareto_tie(pp->y[c], y0) && pp->x[c] < pp->x[*close]) *close = c;
    }
}

/* Performance and data profiles.
 *
 * Instances: every measured step of every scene (in a stratum: of the scenes whose
 * "stratum" is that name; "all" holds every scene). Cost of configuration c on instance p
 * at accuracy level j: the median over the timed repeats of the time to the first iterate
 * with relative energy error (g - g*)/|g0 - g*| <= thr[j] (the suite's one convergence
 * criterion, the same for every method), INFINITY if no repeat reached it.
 *   performance profile (Dolan & More 2002): rho_c(tau) = share of the instances with
 *     t_pc <= tau * min_c' t_pc' (an instance nobody solved counts as unsolved by all);
 *   data profile (More & Wild 2009): d_c(kappa) = share of the instances with
 *     t_pc / t_grad(p) <= kappa, t_grad(p) = the time of one gradient evaluation of the
 *     step's objective at its starting guess (median of 5, same clock): the cost in
 *     gradient-equivalents, comparable across scenes of any size. */


double bench_prof_tau(int i) { return pow(2.0, i / 10.0); }
double bench_prof_kappa(int i) { return pow(10.0, i / 10.0); }

/* Strata: 0 = every scene, then each distinct non-empty scene "stratum" in order. */
int bench_prof_strata(const eo_bench_suite *s, const char **names, int cap)
{
    int n = 0;
    names[n++] = "all";
    for (int si = 0; si < s->nsc; si++) {
        const char *st = s->sc[si].o.stratum;
        if (!st[0]) continue;
        int k = 1;
        while (k < n && strcmp(names[k], st)) k++;
        if (k == n && n < cap) names[n++] = st;
    }
    return n;
}

static int prof_in(const eo_bench_suite *s, int si, int stratum, const char *const *names)
{
    return stratum == 0 || !strcmp(s->sc[si].o.stratum, names[stratum]);
}

/* Cost of every configuration on every instance of a stratum at level j: t[p*ncf + c]
 * (INFINITY unsolved) and the gradient time tg[p]; returns the instance count. */
int bench_prof_costs(const bench_out *b, int stratum, const char *const *names, int j, double *t, double *tg)
{
    const eo_bench_suite *s = b->s;
    int np = 0;
    for (int si = 0; si < s->nsc; si++) {
        if (!prof_in(s, si, stratum, names)) continue;
        const bench_scene_res *sr = b->res + si;
        for (int k = 0; k < s->sc[si].steps; k++, np++) {
            tg[np] = sr->ref[k].tgrad;
            for (int c = 0; c < s->ncf; c++) {
                const bench_step_res *st = sr->pair[c].st + k;
                double v = eo_bench_median(st->nrep, st->ttt[j], NULL, NULL);
                t[(size_t)np * s->ncf + c] = isfinite(v) ? v : INFINITY;
            }
        }
    }
    return np;
}

/* rho_c(tau) of configuration c over np instances */
double bench_prof_rho(const double *t, int np, int ncf, int c, double tau)
{
    if (!np) return NAN;
    int k = 0;
    for (int p = 0; p < np; p++) {
        double best = INFINITY;
        for (int d = 0; d < ncf; d++) best = fmin(best, t[(size_t)p * ncf + d]);
        const double v = t[(size_t)p * ncf + c];
        if (isfinite(v) && v <= tau * best * (1 + 1e-12)) k++;
    }
    return (double)k / np;
}

double bench_prof_data(const double *t, const double *tg, int np, int ncf, int c, double kappa)
{
    if (!np) return NAN;
    int k = 0;
    for (int p = 0; p < np; p++) {
        const double v = t[(size_t)p * ncf + c];
        if (isfinite(v) && tg[p] > 0 && v / tg[p] <= kappa) k++;
    }
    return (double)k / np;
}

int bench_prof_ninstances(const eo_bench_suite *s)
{
    int n = 0;
    for (int si = 0; si < s->nsc; si++) n += s->sc[si].steps;
    return n;
}
