/* The optimizer benchmark harness (bench.h): the CSV outputs and their number formats.
 *
 *   summary.csv      one row per (scene, configuration): status and reason, time to each
 *                    threshold (median, min, max of the repeats, summed over the measured
 *                    steps), ratio to the baseline, error at each time budget (worst
 *                    step), trajectory results, fixed budgets, the repeats, clock, cap and
 *                    budget behind the row
 *   reference.csv    every reference step (and the Ipopt check, the gradient time)
 *   perf_profile.csv, data_profile.csv   the profiles (stats.c) at every tau / kappa
 * curves.csv, trajectory.csv and fixed.csv are written while the runs go (run.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_impl.h"
#include "elastopt/io.h"

/* One CSV number with its leading comma; a non-finite value (not reached, not
 * available, infinite) is an empty field: no output file holds a non-finite number. */
void eo_bench_csv_num(FILE *f, double v)
{
    if (!isfinite(v)) fputs(",", f);
    else fprintf(f, ",%.6e", v);
}

int eo_bench_keep_row(int k, int n, int full_rows)
{
    if (full_rows <= 0 || k <= full_rows || k == n - 1) return 1;
    return floor(50 * log10((double)k)) != floor(50 * log10((double)(k - 1)));
}

void eo_bench_file_name(const char *name, char *buf, size_t n)
{
    size_t k = 0;
    for (; *name && k + 1 < n; name++) {
        char c = *name;
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
                 c == '.';
        buf[k++] = ok ? c : '_';
    }
    buf[k] = 0;
}

/* Index of the headline threshold: 1e-6 if listed, else the tightest. */
int bench_headline_thr(const eo_bench_suite *s)
{
    for (int j = 0; j < s->nthr; j++)
        if (fabs(s->thr[j] - 1e-6) < 1e-12) return j;
    int best = 0;
    for (int j = 1; j < s->nthr; j++)
        if (s->thr[j] < s->thr[best]) best = j;
    return best;
}

void bench_fmt_thr(double t, char *buf, size_t n) { snprintf(buf, n, "%.0e", t); }

void bench_fmt_ms(double t, char *buf, size_t n)
{
    if (!isfinite(t)) snprintf(buf, n, "—");
    else if (t < 0.01) snprintf(buf, n, "%.3f", 1e3 * t);
    else snprintf(buf, n, "%.4g", 1e3 * t);
}

void bench_fmt_sci(double v, char *buf, size_t n)
{
    if (isnan(v)) snprintf(buf, n, "—");
    else snprintf(buf, n, "%.1e", v);
}


int bench_pair_iters(const bench_pair *p)
{
    int n = 0;
    for (int k = 0; k < p->nsteps; k++) n += p->st[k].iters;
    return n;
}

int eo_bench_write_summary(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    char path[1200], lab[32];
    snprintf(path, sizeof path, "%s/summary.csv", b->dir);
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "scene,config,baseline,tets,steps,status,reason,steps_reached,iterations");
    for (int j = 0; j < s->nthr; j++) {
        bench_fmt_thr(s->thr[j], lab, sizeof lab);
        fprintf(f, ",t_%s_median,t_%s_min,t_%s_max,ratio_%s", lab, lab, lab, lab);
    }
    for (int j = 0; j < s->nbud; j++) fprintf(f, ",err_at_%gs", s->bud[j]);
    fprintf(f, ",final_rel_err,traj_converged,traj_time,traj_max_dist,traj_final_dist,traj_rel_dist");
    for (int j = 0; j < s->nibud; j++)
        fprintf(f, ",fixed_%d_time_per_frame,fixed_%d_time_min,fixed_%d_time_max,fixed_%d_iters_per_frame,"
                   "fixed_%d_max_dist,fixed_%d_rel_dist",
                s->ibud[j], s->ibud[j], s->ibud[j], s->ibud[j], s->ibud[j], s->ibud[j]);
    fprintf(f, ",repeats,clock,max_iters,time_budget\n");
    for (int si = 0; si < s->nsc; si++) {
        const bench_scene_res *sr = b->res + si;
        const bench_pair *base = sr->pair + s->baseline;
        for (int c = 0; c < s->ncf; c++) {
            const bench_pair *p = sr->pair + c;
            int iters = 0;
            double fe = -INFINITY;
            for (int k = 0; k < p->nsteps; k++) {
                iters += p->st[k].iters;
                fe = fmax(fe, p->st[k].final_err);
            }
            fprintf(f, "%s,%s,%d,%d,%d,%s,\"%s\",%d,%d", s->sc[si].name, s->cf[c].name, c == s->baseline,
                    s->sc[si].nt, p->nsteps, p->status, p->reason, p->steps_reached, iters);
            for (int j = 0; j < s->nthr; j++) {
                eo_bench_csv_num(f, p->ttt_med[j]);
                eo_bench_csv_num(f, p->ttt_min[j]);
                eo_bench_csv_num(f, p->ttt_max[j]);
                double ratio = isfinite(p->ttt_med[j]) && isfinite(base->ttt_med[j]) && base->ttt_med[j] > 0
                                   ? p->ttt_med[j] / base->ttt_med[j]
                                   : NAN;
                eo_bench_csv_num(f, ratio);
            }
            for (int j = 0; j < s->nbud; j++) eo_bench_csv_num(f, p->eab_med[j]);
            eo_bench_csv_num(f, fe);
            fprintf(f, ",%d", p->traj_converged);
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_time : NAN);
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_max_dist : NAN);
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_final_dist : NAN);
            eo_bench_csv_num(f, s->o.trajectory ? p->traj_max_dist / fmax(sr->ref_disp, 1e-300) : NAN);
            for (int j = 0; j < s->nibud; j++) {
                const bench_fixed_res *z = p->fixed + j;
                if (!z->frames) { /* not run on this scene */
                    fputs(",,,,,,", f);
                    continue;
                }
                eo_bench_csv_num(f, z->ms_med);
                eo_bench_csv_num(f, z->ms_min);
                eo_bench_csv_num(f, z->ms_max);
                eo_bench_csv_num(f, z->frames ? (double)z->iters / z->frames : NAN);
                eo_bench_csv_num(f, z->nan ? NAN : z->max_dist);
                eo_bench_csv_num(f, z->nan ? NAN : z->max_dist / fmax(sr->win_disp, 1e-300));
            }
            /* the repeats behind every time of the row, its clock, and the cap and budget
             * that both the curve (speed) and the trajectory (status) runs had */
            fprintf(f, ",%d,%s,%d", sr->repeats, b->wall ? "wall" : "cpu", p->max_iters);
            eo_bench_csv_num(f, p->budget);
            fputc('\n', f);
        }
    }
    /* reference.csv next to it */
    rc = eo_afile_commit(ctx, &af);
    if (rc < 0) return rc;
    snprintf(path, sizeof path, "%s/reference.csv", b->dir);
    rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    f = eo_afile_fp(af);
    fprintf(f, "scene,step,scene_step,measured,t,n,iterations,reason,converged,rounding_floor,solve_time,g0,gstar,"
               "decrement,rel_err_floor,motion,correction,"
               "ipopt_reason,ipopt_iterations,ipopt_time,ipopt_rel_energy_diff,ipopt_rel_pos_diff,grad_time\n");
    for (int si = 0; si < s->nsc; si++)
        for (int k = 0, m = 0; k < b->res[si].nref; k++) {
            /* every reference step; `step` numbers the measured ones (1..steps) */
            const bench_scene_res *sr = b->res + si;
            const int meas = m < s->sc[si].steps && sr->meas[m] == k;
            const bench_ref *q = meas ? sr->ref + m : sr->allref + k;
            fprintf(f, "%s,", s->sc[si].name);
            if (meas) fprintf(f, "%d", m + 1);
            fprintf(f, ",%d,%d,%.6g,%d,%d,%s,%d,%d", k + 1, meas, q->t, q->n, q->iters, eo_reason_name(q->reason),
                    q->converged, q->rounding);
            m += meas;
            eo_bench_csv_num(f, q->time);
            char gb[2][32];
            fprintf(f, ",%s,%s", eo_fmt_double(gb[0], q->g0), eo_fmt_double(gb[1], q->gstar));
            eo_bench_csv_num(f, q->dec);
            eo_bench_csv_num(f, q->floor);
            eo_bench_csv_num(f, sr->motion[k]);
            eo_bench_csv_num(f, sr->correction[k]);
            if (q->ip_reason == -1000) fputs(",,,,,", f);
            else {
                fprintf(f, ",%s,%d", eo_reason_name(q->ip_reason), q->ip_iters);
                eo_bench_csv_num(f, q->ip_time);
                eo_bench_csv_num(f, q->ip_de);
                eo_bench_csv_num(f, q->ip_pe);
            }
            eo_bench_csv_num(f, meas ? q->tgrad : NAN); /* the data profiles' gradient-equivalent */
            fputc('\n', f);
        }
    return eo_afile_commit(ctx, &af);
}

/* perf_profile.csv and data_profile.csv: every stratum (first "all"), accuracy level and
 * configuration at every tau = 2^(i/10) (1 .. 1024) and kappa = 10^(i/10) gradient-
 * equivalents (1 .. 1e7), with the instance count (stats.c computes the values). */
int eo_bench_write_profiles(eo_ctx *ctx, bench_out *b)
{
    const eo_bench_suite *s = b->s;
    const char *names[64];
    const int nst = bench_prof_strata(s, names, 64);
    const int npmax = bench_prof_ninstances(s);
    double *t = eo_malloc(ctx, ((size_t)npmax * s->ncf + npmax + 1) * sizeof(double));
    eo_afile *pf = NULL, *df = NULL;
    int rc = EO_OK;
    if (!t) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    double *tg = t + (size_t)npmax * s->ncf;
    char path[1400];
    snprintf(path, sizeof path, "%s/perf_profile.csv", b->dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &pf));
    snprintf(path, sizeof path, "%s/data_profile.csv", b->dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &df));
    FILE *P = eo_afile_fp(pf), *D = eo_afile_fp(df);
    fprintf(P, "stratum,threshold,config,instances,tau,fraction\n");
    fprintf(D, "stratum,threshold,config,instances,grad_equivalents,fraction\n");
    for (int q = 0; q < nst; q++)
        for (int j = 0; j < s->nthr; j++) {
            const int np = bench_prof_costs(b, q, names, j, t, tg);
            for (int c = 0; c < s->ncf; c++) {
                for (int i = 0; i < PROF_NTAU; i++)
                    fprintf(P, "%s,%.0e,%s,%d,%.6g,%.6g\n", names[q], s->thr[j], s->cf[c].name, np, bench_prof_tau(i),
                            bench_prof_rho(t, np, s->ncf, c, bench_prof_tau(i)));
                for (int i = 0; i < PROF_NKAPPA; i++)
                    fprintf(D, "%s,%.0e,%s,%d,%.6g,%.6g\n", names[q], s->thr[j], s->cf[c].name, np,
                            bench_prof_kappa(i), bench_prof_data(t, tg, np, s->ncf, c, bench_prof_kappa(i)));
            }
        }
    EO_TRY(rc = eo_afile_commit(ctx, &pf));
    EO_TRY(rc = eo_afile_commit(ctx, &df));
    rc = EO_OK;
fail:
    eo_afile_abort(ctx, &pf);
    eo_afile_abort(ctx, &df);
    eo_free(ctx, t);
    return rc;
}
