/* The optimizer benchmark harness (bench.h): running a suite, the per-step protocol.
 *
 * For a scene with measured steps k = 0..S−1 (after `skip` reference-only steps):
 *
 *   reference   xₖ₊₁ = argmin gₖ by Newton + clamp + backtracking, stopped when the
 *               Newton decrement λ²/2 ≤ ref_tol·|gₖ(x₀)| (checked in the iteration
 *               callback, the solver's own tol set to 1e-300); the states (xₖ, vₖ, tₖ),
 *               x*ₖ, gₖ(x₀) and gₖ(x*ₖ) are stored.
 *   curves      for each configuration and step: the step object is set back to state
 *               k (eo_step_set_state), its objective and starting guess rebuilt, one
 *               warm-up run of at most `warmup_iters` iterations (it pays the first-call
 *               costs: symbolic analysis, workspaces), then `repeats` timed runs record
 *               time and g; the first also records the position error
 *               eₚ = ‖x − x*‖_M/‖x₀ − x*‖_M of every iterate (its own time excluded).
 *               Each run stops when eₑ = (g − g*)/|g₀ − g*| ≤ target.
 *   trajectory  each configuration with its own stopping rule from the scene's initial
 *               state over all skip + S steps (the whole benchmark scene), stopping at
 *               the first step its rule does not meet; distance per frame to the
 *               reference positions. A suite scene with time.adaptive = true (a scene
 *               key like any other, `set` in the suite) steps these runs adaptively
 *               (sim.h: a step that fails is retried in substeps, frames stay at n·dt);
 *               the reference and the fixed-budget runs always take nominal steps.
 *
 * Every step runs through eo_sim (sim.h), the library's one copy of the step protocol:
 * the reference and the trajectories with eo_sim_step (the sim's solver swapped with
 * eo_sim_set_solver), the measured steps with eo_sim_set_state + eo_sim_trial (the
 * next step's problem solved from one state, without advancing). A scene with an
 * explicit integrator has no step problem to minimize and is rejected at load.
 *
 * Distributed (the context carries distribution hooks: `elastopt bench` under mpirun): each
 * rank holds its part of every scene's mesh and runs the whole protocol on it; every
 * configuration must be a distributed one (solver.backend = petsc, or a petsc_, snes_ or
 * tao_ optimizer: checked before anything is written), the reference is newton on the backend with
 * the same settings, the Ipopt check is skipped, g(x₀) and every mass-weighted sum are
 * reduced over the parts (a shared vertex counted by its owner only, eo_bench_run_opts.owned),
 * and the times are this rank's.
 *
 * All recording buffers are sized before the runs; the callbacks do not allocate. One
 * curve solver per configuration exists at a time (created per scene; it re-sizes
 * itself when a release changes the number of free coordinates). */
#define _DEFAULT_SOURCE /* getloadavg */
#include <float.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "bench_impl.h"
#include "elastopt/io.h"
#include "elastopt/registry.h"
#include "elastopt/scene.h"
#include "elastopt/sim.h"
#include "elastopt/suggest.h"

/* Recording buffer of one minimization (sized before the run). */
typedef struct rec_buf {
    int cap, n;
    double *t, *g, *gn, *pe;  /* per record; pe NULL: no position error */
    double *t2;               /* per record: the other clock's time (t is the suite's clock) */
    int wall;                 /* t is wall time (else CPU time of the solving thread) */
    double *e;                /* relative energy error, filled after the run */
    const double *xstar, *wM;
    eo_ctx *ctx;              /* distributed: the position error's sums are reduced over the parts */
    double pe0;               /* ‖x₀ − x*‖_M */
    int nfree;
    double gstar, de, target, budget;
    double cb_wall, cb_cpu;   /* the callback's own time (position errors), excluded */
    int max_records;          /* > 0: stop after this many records (warm-up run) */
    double gbest;             /* lowest g so far */
    int since_best;           /* records since gbest last decreased */
    int reached, out_of_time, stagnated;
} rec_buf;

/* A curve run that has not lowered its best g for this many iterations is stopped as
 * stagnated (the step length has reached the rounding level of g: e.g. Armijo accepts
 * α‖p‖ too small to change g, and the run would otherwise go on to its cap). */
enum { STAGNATION_ITERS = 20 };

/* ‖a − b‖_w; distributed: summed over the parts (w is 0 on the vertices a part does not own) */
static double mnorm_diff(eo_ctx *ctx, int n, const double *w, const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < n; i++) {
        double d = a[i] - b[i];
        s += w[i] * d * d;
    }
    eo_ctx_reduce(ctx, &s, 1, EO_REDUCE_SUM);
    return sqrt(s);
}

static int curve_iter(const eo_iter_info *it, void *user)
{
    rec_buf *b = user;
    const double w_in = b->pe ? eo_wtime() : 0, c_in = b->pe ? eo_cputime() : 0;
    const double tw = it->time - b->cb_wall, tc = it->cpu_time - b->cb_cpu;
    const double t = b->wall ? tw : tc;
    if (b->n < b->cap) {
        int k = b->n++;
        b->t[k] = t;
        b->t2[k] = b->wall ? tc : tw;
        b->g[k] = it->g;
        b->gn[k] = it->grad_norm;
        if (b->pe) {
            double d = mnorm_diff(b->ctx, b->nfree, b->wM, it->x, b->xstar);
            b->pe[k] = b->pe0 > 0 ? d / b->pe0 : (d == 0 ? 0 : INFINITY);
        }
    }
    int stop = 0;
    if (it->g < b->gbest) {
        b->gbest = it->g;
        b->since_best = 0;
    } else {
        b->since_best++;
    }
    if (b->max_records > 0 && b->n >= b->max_records) stop = 1;
    if ((it->g - b->gstar) / b->de <= b->target) stop = b->reached = 1;
    else if (b->budget > 0 && t > b->budget) stop = b->out_of_time = 1;
    else if (b->since_best >= STAGNATION_ITERS) stop = b->stagnated = 1;
    if (b->pe) {
        b->cb_wall += eo_wtime() - w_in;
        b->cb_cpu += eo_cputime() - c_in;
    }
    return stop;
}

/* Reference stop: the Newton decrement below tol = ref_tol·|g(x₀)|, or the rounding
 * floor: the last step did not lower g although its decrement was already below
 * 1e-9·|g(x₀)| (then no tighter solution exists in floating point: the line search
 * only accepts steps that leave g unchanged), or the decrement at the level the rounding
 * of ∇g alone produces (the stopping rules' floor, EO_STOP_FLOOR·ε²·s[0] of the
 * objective's rounding scales). The scale of g is |g(x₀)|, at least the rounding of the
 * terms g sums (ε·s[2]): a start with g(x₀) ≈ 0 (x₀ = ỹ, no elastic energy, a potential
 * that vanishes at the body's centre) would otherwise make the tolerance 0 and run the
 * reference to its iteration cap. */
typedef struct ref_state {
    double tol, gscale, floor, dec, prev_g, prev_dec;
    int stopped, rounding;
} ref_state;

static int ref_iter(const eo_iter_info *it, void *user)
{
    ref_state *r = user;
    if (!isnan(it->decrement)) r->dec = it->decrement;
    if (!isnan(it->decrement) && it->decrement <= r->floor && !it->reason) return r->stopped = r->rounding = 1;
    if (it->iteration > 0 && !(it->g < r->prev_g) && r->prev_dec <= 1e-9 * r->gscale) {
        r->dec = r->prev_dec;
        return r->stopped = r->rounding = 1;
    }
    r->prev_g = it->g;
    r->prev_dec = isnan(it->decrement) ? INFINITY : it->decrement;
    if (!isnan(it->decrement) && it->decrement <= r->tol && !it->reason) return r->stopped = 1;
    return 0;
}

static int all_finite(int n, const double *x)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* Mass-weighted RMS distance of two full position vectors (distributed: over the parts;
 * m is 0 on the vertices a part does not own). */
static double rms_dist(eo_ctx *ctx, int nv, const double *m, const double *a, const double *b)
{
    double s = 0, mt = 0;
    for (int v = 0; v < nv; v++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            double d = a[3 * v + k] - b[3 * v + k];
            d2 += d * d;
        }
        s += m[v] * d2;
        mt += m[v];
    }
    double sm[2] = {s, mt};
    eo_ctx_reduce(ctx, sm, 2, EO_REDUCE_SUM);
    s = sm[0], mt = sm[1];
    return mt > 0 ? sqrt(s / mt) : NAN;
}

typedef struct run_ctx {
    eo_ctx *ctx;
    const eo_bench_suite *s;
    const eo_bench_run_opts *ro;
    bench_out *out;
    int repeats, si;
    int wall;             /* the run's clock is wall time (else thread CPU time) */
    double t0, units_total, units_done;
    FILE *curves, *traj, *fixed;
} run_ctx;

static void progress(run_ctx *r, int si, int ci, const char *phase)
{
    if (!r->ro->progress) return;
    eo_bench_progress p = {.scene = si, .nscenes = r->s->nsc, .config = ci, .nconfigs = r->s->ncf,
                           .scene_name = r->s->sc[si].name,
                           .config_name = ci >= 0 ? r->s->cf[ci].name : "",
                           .phase = phase};
    p.elapsed = eo_wtime() - r->t0;
    p.fraction = r->units_total > 0 ? r->units_done / r->units_total : 0;
    p.eta = p.fraction > 0.002 ? p.elapsed * (1 - p.fraction) / p.fraction : -1;
    r->ro->progress(&p, r->ro->user);
}

/* timed repeats: the run option (--repeats) if given, else `own` (the scene's or the
 * suite's), capped at BENCH_MAX_REPEATS */
static int run_repeats(const eo_bench_run_opts *ro, int own)
{
    int n = ro->repeats > 0 ? ro->repeats : own;
    return n < 1 ? 1 : n > BENCH_MAX_REPEATS ? BENCH_MAX_REPEATS : n;
}

/* Steps of a scene's trajectory runs before the measured steps are known: the window's
 * length if it is contiguous (select = first, or a window start), else up to the horizon. */
static int traj_steps_estimate(const bench_scene *b)
{
    if (b->traj_window) return b->select == BENCH_SELECT_FIRST ? b->steps : b->steps + 1;
    return b->skip + (b->select == BENCH_SELECT_FIRST ? b->steps : b->horizon);
}

/* Work units of a scene (tets x step solves) for the progress fraction: reference,
 * curves (warm-up + repeats), trajectories, fixed budgets (a fraction of a solve each). */
static double scene_units(const eo_bench_suite *s, const bench_scene *b, int repeats, int traj_steps)
{
    double u = (double)b->nt * (b->skip + b->horizon) +
               (double)b->nt * b->steps * s->ncf * (repeats + 1) +
               (double)b->nt * b->steps * s->ncf * 0.3 * b->nibud_on;
    if (s->o.trajectory) u += (double)b->nt * traj_steps * s->ncf;
    return u;
}

static const char *curve_reason_name(const bench_step_res *r)
{
    return r->reached ? "reached_target" : r->stagnated ? "stagnated" : eo_reason_name(r->reason);
}

/* Write the curve rows of one (scene, config, step) and the plot data block. */
static void write_curve(run_ctx *r, FILE *dat, const bench_scene *b, const bench_config *c, int step,
                        const rec_buf *rep, int nrep, const bench_step_res *res, double *tmp)
{
    int nmax = 0;
    for (int q = 0; q < nrep; q++)
        if (rep[q].n > nmax) nmax = rep[q].n;
    fprintf(dat, "# %s step %d\n", c->name, step + 1);
    for (int k = 0; k < nmax; k++) {
        int m = 0, src = -1;
        for (int q = 0; q < nrep; q++)
            if (rep[q].n > k) {
                tmp[m++] = rep[q].t[k];
                if (src < 0) src = q;
            }
        double tmin, tmax, tmed = eo_bench_median(m, tmp, &tmin, &tmax);
        m = 0;
        for (int q = 0; q < nrep; q++)
            if (rep[q].n > k) tmp[m++] = rep[q].t2[k];
        const double t2med = eo_bench_median(m, tmp, NULL, NULL);
        double e = rep[src].e[k];
        double pe = rep[0].pe && k < rep[0].n ? rep[0].pe[k] : NAN;
        if (!eo_bench_keep_row(k, nmax, r->s->o.curve_rows)) continue;
        fprintf(r->curves, "%s,%d,%s,%d", b->name, step + 1, c->name, k);
        eo_bench_csv_num(r->curves, tmed);
        eo_bench_csv_num(r->curves, tmin);
        eo_bench_csv_num(r->curves, tmax);
        eo_bench_csv_num(r->curves, k > 0 ? (r->wall ? tmed : t2med) : 0.0);
        eo_bench_csv_num(r->curves, k > 0 ? (r->wall ? t2med : tmed) : 0.0);
        eo_bench_csv_num(r->curves, rep[src].g[k]);
        eo_bench_csv_num(r->curves, e);
        eo_bench_csv_num(r->curves, pe);
        eo_bench_csv_num(r->curves, rep[src].gn[k]);
        fprintf(r->curves, ",%s\n", k == nmax - 1 ? curve_reason_name(res) : "");
        if (k > 0 && tmed > 0 && tmed < r->out->res[r->si].tmin) r->out->res[r->si].tmin = tmed;
        fprintf(dat, "%.6e %.6e\n", k > 0 ? tmed : 0.0, e > 1e-17 ? e : 1e-17);
    }
    fprintf(dat, "\n\n");
}

/* A configuration the scene refuses (eo_sim_check_solver: e.g. admm_pd with collisions):
 * nothing is run; every threshold unreached, every budget's error infinite, an empty
 * plot block per step (the data file's block index stays c·S + k), status "refused". */
static void refuse_pair(FILE *dat, const eo_bench_suite *s, const bench_config *c, bench_pair *p, int R,
                        const int *meas, const char *why)
{
    for (int k = 0; k < p->nsteps; k++) {
        bench_step_res *st = p->st + k;
        st->nrep = R;
        st->reason = EO_DIVERGED_EXTERNAL;
        st->final_err = INFINITY;
        for (int j = 0; j < BENCH_MAX_LIST; j++)
            for (int q = 0; q < BENCH_MAX_REPEATS; q++) st->ttt[j][q] = st->eab[j][q] = INFINITY;
        fprintf(dat, "# %s step %d (refused)\n\n\n", c->name, k + 1);
    }
    bench_aggregate(s, R, p, 0, 0, meas);
    snprintf(p->status, sizeof p->status, "refused");
    snprintf(p->reason, sizeof p->reason, "%s", why);
}

/* Run the curves of one configuration on one step from the current guess. */
static int run_curves(run_ctx *r, eo_sim *sim, eo_solver *sv, int n, const double *x0, double *x,
                      const bench_ref *ref, const double *xstar, const double *wM, rec_buf *w, rec_buf *rep,
                      bench_step_res *res, double budget)
{
    eo_ctx *ctx = r->ctx;
    double de = fabs(ref->g0 - ref->gstar);
    if (!(de > 0)) de = fmax(fabs(ref->gstar), 1e-300);
    double pe0 = mnorm_diff(ctx, n, wM, x0, xstar);
    eo_solve_result sr;
    int rc;
    const int q0 = r->s->o.warmup_iters > 0 ? -1 : 0;
    for (int q = q0; q < r->repeats; q++) {
        rec_buf *b = q < 0 ? w : rep + q;
        b->max_records = q < 0 ? r->s->o.warmup_iters + 1 : 0;
        b->n = 0;
        b->nfree = n;
        b->ctx = ctx;
        b->xstar = xstar;
        b->wM = wM;
        b->pe0 = pe0;
        b->gstar = ref->gstar;
        b->de = de;
        b->target = r->s->o.target;
        b->budget = budget;
        b->wall = r->wall;
        b->cb_wall = b->cb_cpu = 0;
        b->gbest = INFINITY;
        b->since_best = 0;
        b->reached = b->out_of_time = b->stagnated = 0;
        rc = eo_sim_trial(sim, sv, x0, x, curve_iter, b, NULL, &sr);
        if (rc < 0) return rc;
        if (q == 0) {
            res->reason = b->out_of_time ? EO_DIVERGED_TIME_BUDGET : sr.reason;
            res->reached = b->reached;
            res->stagnated = b->stagnated;
        }
        if (!all_finite(n, x)) res->nonfinite = res->nan = 1;
        if (sr.reason == EO_DIVERGED_NONFINITE) res->nonfinite = 1;
    }
    /* iterate times: τ₀ = 0, τₖ = time of record k−1; relative errors */
    res->nrep = r->repeats;
    double tots[BENCH_MAX_REPEATS];
    for (int q = 0; q < r->repeats; q++) {
        rec_buf *b = rep + q;
        for (int k = b->n - 1; k >= 1; k--) {
            b->t[k] = b->t[k - 1];
            b->t2[k] = b->t2[k - 1];
        }
        if (b->n) b->t[0] = b->t2[0] = 0;
        for (int k = 0; k < b->n; k++) {
            if (isnan(b->g[k]) || isnan(b->gn[k])) res->nonfinite = res->nan = 1;
            b->e[k] = (b->g[k] - ref->gstar) / de;
        }
        tots[q] = b->n ? b->t[b->n - 1] : 0;
        for (int j = 0; j < r->s->nthr; j++) res->ttt[j][q] = eo_bench_time_to(b->n, b->t, b->e, r->s->thr[j]);
        for (int j = 0; j < r->s->nbud; j++) res->eab[j][q] = eo_bench_error_at(b->n, b->t, b->e, r->s->bud[j]);
    }
    /* iterations and final error of the median-time repeat */
    double med = eo_bench_median(r->repeats, tots, NULL, NULL);
    int pick = 0;
    for (int q = 0; q < r->repeats; q++)
        if (fabs(tots[q] - med) < fabs(tots[pick] - med)) pick = q;
    res->iters = rep[pick].n ? rep[pick].n - 1 : 0;
    res->final_err = rep[pick].n ? rep[pick].e[rep[pick].n - 1] : NAN;
    (void)ctx;
    return EO_OK;
}

/* Stops the solver at iterate `*limit` (warm-up runs). */
static int fixed_iter(const eo_iter_info *it, void *user)
{
    return it->iteration >= *(const int *)user;
}

/* The time budget of the trajectory and fixed-budget runs in the suite's clock (the
 * solver's own solver.time_budget counts wall seconds, so the harness sets it to 0 and
 * stops the run here), and the fixed iteration budget (limit > 0). */
typedef struct budget_cb {
    int limit;            /* stop at this iterate (0: none) */
    double budget;        /* seconds in the suite's clock (0: none) */
    int wall;
    int hit;              /* the budget stopped the run */
} budget_cb;

static int budget_iter(const eo_iter_info *it, void *user)
{
    budget_cb *c = user;
    if (c->limit > 0 && it->iteration >= c->limit) return 1;
    const double t = c->wall ? it->time : it->cpu_time;
    if (c->budget > 0 && t > c->budget) return c->hit = 1;
    return 0;
}

/* A run the budget callback stopped ends with reason diverged_time_budget. */
static int budget_reason(const budget_cb *c, int reason)
{
    return c->hit && reason == EO_DIVERGED_EXTERNAL ? EO_DIVERGED_TIME_BUDGET : reason;
}

/* Measured steps of a scene from the reference's per-step scores (motion or
 * correction): the block of `S` consecutive steps among skip .. nref−1 with the largest
 * total score (ties: the earlier block; a failed reference step, NaN, disqualifies its
 * blocks), so the trajectory and fixed-budget runs over the window cost S steps;
 * select = first: skip .. skip + S − 1. */
static void select_steps(const bench_scene *b, int nref, const double *motion, const double *correction, int *meas)
{
    const int S = b->steps;
    int start = b->skip;
    if (b->select != BENCH_SELECT_FIRST) {
        const double *score = b->select == BENCH_SELECT_MOTION ? motion : correction;
        double best = -INFINITY;
        for (int k = b->skip; k + S <= nref; k++) {
            double sum = 0;
            for (int m = 0; m < S; m++) sum += isnan(score[k + m]) ? -INFINITY : score[k + m];
            if (sum > best) best = sum, start = k;
        }
    }
    for (int m = 0; m < S; m++) meas[m] = start + m;
}

/* x* of scene step k in the free coordinates of the prepared step (the reference frame
 * after step k). */
static void ref_xstar(eo_step *st, int n, const double *frame_next, double *xstar)
{
    for (int i = 0; i < n; i++) xstar[i] = frame_next[eo_step_free_to_full(st, i)];
}

/* One scene: reference, curves of every configuration, trajectories, fixed budgets. */
static int run_scene(run_ctx *r, int si)
{
    eo_ctx *ctx = r->ctx;
    const int dist = eo_ctx_dist(ctx) != NULL; /* this process runs one part of each scene */
    const eo_bench_suite *s = r->s;
    const bench_scene *b = s->sc + si;
    bench_scene_res *sr = r->out->res + si;
    eo_cfg *scfg = NULL, *ccfg = NULL;
    eo_sim *sim = NULL;
    eo_solver *sv = NULL;
    eo_afile *datf = NULL;
    double *mem = NULL;
    bench_ref *allref = NULL;
    int rc;
    /* measured steps; reference steps (skip + horizon: the steps to select from) */
    const int S = b->steps, NR = b->skip + b->horizon;
    r->si = si;
    sr->tmin = INFINITY;
    progress(r, si, -1, "reference");
    EO_TRY(rc = bench_scene_cfg(ctx, b, &scfg));
    json_object_del(eo_cfg_root(scfg), "solver"); /* the suite's configurations define the solver */
    rc = eo_sim_create(ctx, scfg, &sim);           /* takes scfg over */
    scfg = NULL;
    EO_TRY(rc);
    const eo_scene *sc = eo_sim_scene(sim);
    eo_step *st = eo_sim_step_problem(sim);
    r->repeats = run_repeats(r->ro, b->repeats);
    sr->repeats = r->repeats;
    const int nv = sc->mesh->nv, nf = 3 * nv, cap = b->max_iters + 2, R = r->repeats;
    /* frames (x, v) 0..NR of the reference, x* of the current step, guess, x, wM, tmp,
     * times, motion and correction per reference step, recording buffers; the reference
     * step k starts from frame k and ends in frame k + 1 */
    size_t need = (size_t)(NR + 1) * 2 * nf + 4 * (size_t)nf + 64 + (size_t)(NR + 1) + (size_t)NR +
                  (size_t)(R + 1) * 6 * (size_t)cap + (size_t)nv + 1;
    mem = eo_malloc(ctx, need * sizeof(double));
    sr->ref = eo_calloc(ctx, (size_t)S, sizeof *sr->ref);
    sr->meas = eo_calloc(ctx, (size_t)S, sizeof *sr->meas);
    sr->motion = eo_calloc(ctx, 2 * (size_t)NR, sizeof *sr->motion);
    sr->pair = eo_calloc(ctx, (size_t)s->ncf, sizeof *sr->pair);
    allref = eo_calloc(ctx, (size_t)NR, sizeof *allref);
    if (!mem || !sr->ref || !sr->meas || !sr->motion || !sr->pair || !allref) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (bench scene %s)", b->name);
        goto fail;
    }
    sr->correction = sr->motion + NR;
    sr->nref = NR;
    double *fx = mem, *fv = fx + (size_t)(NR + 1) * nf, *xsm = fv + (size_t)(NR + 1) * nf;
    double *x0 = xsm + nf, *x = x0 + nf, *wM = x + nf, *tmp = wM + nf;
    double *ft = tmp + 64, *ftime = ft + NR + 1, *recmem = ftime + NR; /* ftime: solve time per window frame */
    rec_buf w, rep[BENCH_MAX_REPEATS];
    for (int q = -1; q < R; q++) {
        rec_buf *b2 = q < 0 ? &w : rep + q;
        double *p = recmem + (size_t)(q + 1) * 6 * (size_t)cap;
        memset(b2, 0, sizeof *b2);
        b2->cap = cap;
        b2->t = p, b2->g = p + cap, b2->gn = p + 2 * (size_t)cap, b2->e = p + 3 * (size_t)cap;
        b2->pe = q == 0 ? p + 4 * (size_t)cap : NULL; /* position error: first timed repeat */
        b2->t2 = p + 5 * (size_t)cap;
    }
    /* vertex masses as weights; distributed: a part's lumped masses are its tets' shares,
     * summed over the parts onto each vertex's owner (0 elsewhere), so that every sum over
     * the parts counts each vertex once with its whole mass */
    double *vw = recmem + (size_t)(R + 1) * 6 * (size_t)cap;
    const double *vmass = vw;
    sr->nv = nv;
    if (dist) {
        int ok = r->ro->owned_sum(eo_step_vertex_mass(st), vw) == 0;
        double nown = 0;
        for (int v = 0; v < nv; v++) nown += vw[v] > 0;
        eo_ctx_reduce(ctx, &nown, 1, EO_REDUCE_SUM);
        sr->nv = (int)nown;
        if (!ok) {
            rc = eo_error(ctx, EO_ERR_INVALID, "bench: scene %s: the vertex masses could not be summed over the "
                                               "ranks", b->name);
            goto fail;
        }
    } else {
        memcpy(vw, eo_step_vertex_mass(st), (size_t)nv * sizeof *vw);
    }
    double mtot = 0;
    for (int v = 0; v < nv; v++) mtot += vmass[v];
    eo_ctx_reduce(ctx, &mtot, 1, EO_REDUCE_SUM);

    /* ---- reference */
    eo_solver_opts rso;
    eo_solver_opts_default(&rso);
    snprintf(rso.optimizer, sizeof rso.optimizer, "newton");
    snprintf(rso.hessian_fix, sizeof rso.hessian_fix, "clamp");
    snprintf(rso.linesearch, sizeof rso.linesearch, "backtracking");
    snprintf(rso.stop, sizeof rso.stop, "newton_decrement");
    if (dist) snprintf(rso.backend, sizeof rso.backend, "petsc"); /* newton on the PETSc backend (petsc_ksp), the same settings */
    rso.tol = 1e-300;
    rso.max_iters = s->o.ref_max_iters;
    rso.time_budget = 0;
    EO_TRY(rc = eo_sim_set_solver(sim, &rso, NULL));
    /* the reference solves the nominal steps' problems (a scene's time.adaptive acts in
     * the trajectory runs only) */
    const int adaptive = eo_sim_adaptive(sim);
    EO_TRY(rc = eo_sim_set_adaptive(sim, 0));
    ref_state rs;
    eo_sim_set_iter_callback(sim, ref_iter, &rs);
    eo_objective *obj;
    double *guess;
    eo_step_stats stats;
    EO_TRY(rc = eo_step_stats_compute(st, &stats));
    sr->start_minJ = stats.min_J;
    sr->start_inverted = stats.inverted;
    sr->start_elastic = stats.elastic;
    for (int k = 0; k < NR; k++) {
        eo_sim_get_state(sim, fx + (size_t)k * nf, fv + (size_t)k * nf, &ft[k], NULL);
        EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
        const int n = obj->n;
        double g0;
        EO_TRY(rc = eo_objective_value(obj, guess, &g0));
        eo_ctx_reduce(ctx, &g0, 1, EO_REDUCE_SUM); /* distributed: the parts' shares */
        memcpy(x0, guess, (size_t)n * sizeof(double));
        double rsc[3] = {0, 0, 0};
        int rok = eo_objective_rounding_scale(obj, guess, rsc) >= 0 && isfinite(rsc[0]) && isfinite(rsc[2]);
        if (dist) { /* the parts' scales summed (as the distributed solver does), if every part has them */
            double ok = rok;
            eo_ctx_reduce(ctx, &ok, 1, EO_REDUCE_MIN);
            rok = ok > 0;
            if (rok) eo_ctx_reduce(ctx, rsc, 3, EO_REDUCE_SUM);
        }
        if (!rok) rsc[0] = rsc[2] = 0;
        const double gs = fmax(fmax(fabs(g0), DBL_EPSILON * rsc[2]), 1e-300);
        rs = (ref_state){.tol = s->o.ref_tol * gs, .gscale = gs, .floor = EO_STOP_FLOOR * DBL_EPSILON * DBL_EPSILON * rsc[0],
                         .dec = NAN, .prev_g = INFINITY, .prev_dec = INFINITY};
        eo_sim_step_result res;
        EO_TRY(rc = eo_sim_step(sim, &res));
        bench_ref *q = allref + k;
        q->t = ft[k] + sc->time.dt;
        q->g0 = g0;
        q->gstar = res.g;
        q->dec = rs.dec;
        q->time = r->wall ? res.time : res.cpu_time;
        q->iters = res.iterations;
        q->reason = rs.stopped ? EO_CONVERGED_DECREMENT : res.reason;
        q->converged = rs.stopped || res.reason > 0;
        q->rounding = rs.rounding;
        q->n = n;
        q->floor = 2.2e-16 * fmax(fabs(g0), fabs(res.g)) / fmax(fabs(g0 - res.g), 1e-300);
        q->ip_reason = -1000; /* the Ipopt check: not run */
        if (!q->converged) r->out->sum->ref_failures++;
        /* per-step scores: the motion of the step and the distance from its start guess
         * to x* (free coordinates; constrained vertices contribute 0), both m RMS */
        const double *xa = eo_step_x(st);
        sr->motion[k] = rms_dist(ctx, nv, vmass, xa, fx + (size_t)k * nf);
        double c2 = 0;
        for (int i = 0; i < n; i++) {
            int fi = eo_step_free_to_full(st, i);
            double d = xa[fi] - x0[i];
            c2 += vmass[fi / 3] * d * d;
        }
        eo_ctx_reduce(ctx, &c2, 1, EO_REDUCE_SUM);
        sr->correction[k] = mtot > 0 ? sqrt(c2 / mtot) : NAN;
        if (!q->converged || eo_sim_index(sim) == k) sr->motion[k] = sr->correction[k] = NAN;
    }
    eo_sim_set_iter_callback(sim, NULL, NULL);
    eo_sim_get_state(sim, fx + (size_t)NR * nf, fv + (size_t)NR * nf, &ft[NR], NULL);
    select_steps(b, NR, sr->motion, sr->correction, sr->meas);
    for (int m = 0; m < S; m++) sr->ref[m] = allref[sr->meas[m]];
    /* the data profiles' cost unit: one gradient evaluation of each measured step's
     * objective at its starting guess, in the suite's clock (median of 5 after one
     * untimed call) */
    for (int m = 0; m < S; m++) {
        const int k = sr->meas[m];
        const size_t fr = (size_t)k * nf;
        EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[k], k));
        EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
        double gv, tg[5];
        EO_TRY(rc = eo_objective_gradient(obj, guess, &gv, x));
        for (int q = 0; q < 5; q++) {
            const double a = r->wall ? eo_wtime() : eo_cputime();
            EO_TRY(rc = eo_objective_gradient(obj, guess, &gv, x));
            tg[q] = (r->wall ? eo_wtime() : eo_cputime()) - a;
        }
        sr->ref[m].tgrad = eo_bench_median(5, tg, NULL, NULL);
    }
    sr->win0 = sr->meas[0];
    sr->win1 = sr->meas[S - 1];
    /* the trajectory runs: scene steps t0 .. win1 */
    const int t0 = b->traj_window ? sr->win0 : 0, NT = sr->win1 + 1 - t0, NW = sr->win1 + 1 - sr->win0;
    r->units_total += scene_units(s, b, R, NT) - scene_units(s, b, R, traj_steps_estimate(b)); /* now known */
    const void *ipopt_type = NULL;
    if (s->o.ipopt_check && !dist && eo_registry_find(ctx, EO_KIND_OPTIMIZER, "ipopt", &ipopt_type) == EO_OK) {
        eo_solver_opts io;
        eo_solver_opts_default(&io);
        snprintf(io.optimizer, sizeof io.optimizer, "ipopt");
        snprintf(io.hessian_fix, sizeof io.hessian_fix, "clamp");
        io.max_iters = s->o.ref_max_iters;
        io.time_budget = 0;
        EO_TRY(rc = eo_solver_create(ctx, &io, NULL, &sv));
        for (int m = 0; m < S; m++) {
            const int k = sr->meas[m];
            const size_t fr = (size_t)k * nf;
            EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[k], k));
            EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
            const int n = obj->n;
            for (int i = 0; i < n; i++) wM[i] = vmass[eo_step_free_to_full(st, i) / 3];
            memcpy(x0, guess, (size_t)n * sizeof(double));
            ref_xstar(st, n, fx + fr + nf, xsm);
            eo_solve_result ir;
            EO_TRY(rc = eo_sim_trial(sim, sv, x0, x, NULL, NULL, NULL, &ir));
            bench_ref *q = sr->ref + m;
            double de = fabs(q->g0 - q->gstar), pe0 = mnorm_diff(ctx, n, wM, x0, xsm);
            q->ip_reason = ir.reason;
            q->ip_iters = ir.iterations;
            q->ip_time = r->wall ? ir.time : ir.cpu_time;
            q->ip_de = (ir.g - q->gstar) / (de > 0 ? de : fmax(fabs(q->gstar), 1e-300));
            q->ip_pe = all_finite(n, x) ? mnorm_diff(ctx, n, wM, x, xsm) / (pe0 > 0 ? pe0 : 1) : NAN;
        }
        eo_solver_destroy(&sv);
    }
    sr->ref_disp = rms_dist(ctx, nv, vmass, fx + (size_t)(sr->win1 + 1) * nf, fx + (size_t)t0 * nf);
    sr->win_disp = rms_dist(ctx, nv, vmass, fx + (size_t)(sr->win1 + 1) * nf, fx + (size_t)sr->win0 * nf);
    EO_TRY(rc = eo_sim_set_state(sim, fx + (size_t)(sr->win1 + 1) * nf, fv + (size_t)(sr->win1 + 1) * nf,
                                 ft[sr->win1 + 1], sr->win1 + 1));
    EO_TRY(rc = eo_step_stats_compute(st, &stats));
    sr->end_minJ = stats.min_J;
    sr->end_inverted = stats.inverted;
    sr->end_elastic = stats.elastic;
    r->units_done += (double)b->nt * NR;
    sr->allref = allref; /* kept for reference.csv */
    allref = NULL;

    /* ---- plot data */
    char name[200], path[1400];
    eo_bench_file_name(b->name, name, sizeof name);
    snprintf(path, sizeof path, "%s/plots/%s.dat", r->out->dir, name);
    EO_TRY(rc = eo_afile_open(ctx, path, &datf));
    fprintf(eo_afile_fp(datf), "# %s: blocks (configuration c, step k) at index c*%d + k: time (s), relative energy error\n",
            b->name, S);

    /* ---- configurations */
    for (int ci = 0; ci < s->ncf; ci++) {
        const bench_config *c = s->cf + ci;
        bench_pair *p = sr->pair + ci;
        p->nsteps = S;
        p->ntraj = NT;
        p->traj_first = t0;
        p->st = eo_calloc(ctx, (size_t)S, sizeof *p->st);
        p->tr = eo_calloc(ctx, (size_t)NT, sizeof *p->tr);
        if (!p->st || !p->tr) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
            goto fail;
        }
        eo_solver_opts so, cso;
        EO_TRY(rc = bench_config_cfg(ctx, c, &ccfg, &so));
        /* one iteration cap and one time budget for the speed (curve) and the status
         * (trajectory) runs: the configuration's own solver.max_iters if it sets one (at most
         * the scene's: the recording buffers hold that many), else the scene's; its own
         * solver.time_budget if set, else the scene's, in the suite's clock */
        const int cap_iters = c->own_max_iters && so.max_iters < b->max_iters ? so.max_iters : b->max_iters;
        const double budget = so.time_budget > 0 ? so.time_budget : b->time_budget;
        p->max_iters = cap_iters;
        p->budget = budget;
        cso = so;
        cso.tol = 1e-300;
        cso.max_iters = cap_iters;
        cso.time_budget = 0; /* the harness enforces the budget, excluding its own time */
        progress(r, si, ci, "curves");
        EO_TRY(rc = eo_solver_create(ctx, &cso, ccfg, &sv));
        if (eo_sim_check_solver(sim, sv) < 0) { /* the configuration cannot take this scene */
            refuse_pair(eo_afile_fp(datf), s, c, p, R, sr->meas, eo_ctx_message(ctx));
            eo_ctx_clear_error(ctx);
            eo_solver_destroy(&sv);
            eo_cfg_destroy(&ccfg);
            r->out->sum->runs++;
            for (int q = 0; q < s->nreq; q++)
                if (s->req[q] == ci) r->out->sum->required_failures++;
            r->units_done += (double)b->nt * (S * (R + 1) + S * 0.3 * b->nibud_on + (s->o.trajectory ? NT : 0));
            continue;
        }
        for (int k = 0; k < S; k++) {
            const int ks = sr->meas[k];
            const size_t fr = (size_t)ks * nf;
            EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[ks], ks));
            EO_TRY(rc = eo_sim_prepare(sim, &obj, &guess));
            int n = obj->n;
            memcpy(x0, guess, (size_t)n * sizeof(double));
            for (int i = 0; i < n; i++) wM[i] = vmass[eo_step_free_to_full(st, i) / 3];
            ref_xstar(st, n, fx + fr + nf, xsm);
            EO_TRY(rc = run_curves(r, sim, sv, n, x0, x, sr->ref + k, xsm, wM, &w, rep, p->st + k, budget));
            write_curve(r, eo_afile_fp(datf), b, c, k, rep, R, p->st + k, tmp);
            r->units_done += (double)b->nt * (R + 1);
            progress(r, si, ci, "curves");
        }
        if (r->ro->profile) {
            eo_profile pv = *eo_solver_get_profile(sv);
            if (!r->wall) eo_profile_cpu_view(eo_solver_get_profile(sv), &pv);
            r->ro->profile(b->name, c->name, &pv, r->ro->profile_user);
        }
        eo_solver_destroy(&sv);
        /* trajectory with the configuration's own stopping rule, from scene step t0 to
         * the last measured step, up to the first step the rule does not meet; an untimed
         * warm-up of at most warmup_iters iterations on the first step first */
        if (s->o.trajectory) {
            progress(r, si, ci, "trajectory");
            eo_solver_opts tso = so;
            tso.max_iters = cap_iters; /* the curve runs' cap */
            tso.time_budget = 0; /* the budget in the suite's clock: budget_iter */
            EO_TRY(rc = eo_sim_set_solver(sim, &tso, ccfg));
            EO_TRY(rc = eo_sim_set_adaptive(sim, adaptive)); /* the scene's time.adaptive */
            EO_TRY(rc = eo_sim_set_state(sim, fx + (size_t)t0 * nf, fv + (size_t)t0 * nf, ft[t0], t0));
            if (s->o.warmup_iters > 0) {
                int left = s->o.warmup_iters;
                eo_solve_result wr;
                EO_TRY(rc = eo_sim_trial(sim, NULL, NULL, x, fixed_iter, &left, NULL, &wr));
            }
            budget_cb tb = {.limit = 0, .budget = budget, .wall = r->wall};
            eo_sim_set_iter_callback(sim, budget_iter, &tb);
            for (int k = t0; k <= sr->win1; k++) {
                eo_sim_step_result res;
                tb.hit = 0;
                if ((rc = eo_sim_step(sim, &res)) < 0) break;
                /* a step whose new state was not finite is undone by the sim */
                const int rejected = eo_sim_index(sim) == k;
                bench_traj_res *t = p->tr + (k - t0);
                t->iters = res.iterations;
                t->reason = budget_reason(&tb, res.reason);
                t->time = r->wall ? res.time : res.cpu_time;
                t->time2 = r->wall ? res.cpu_time : res.time;
                t->g = res.g;
                t->nan = rejected || isnan(res.g);
                t->nonfinite = t->nan || res.reason == EO_DIVERGED_NONFINITE;
                p->traj_done = k - t0 + 1;
                if (rejected) {
                    t->dist = NAN;
                    break;
                }
                t->dist = rms_dist(ctx, nv, vmass, eo_step_x(st), fx + (size_t)(k + 1) * nf);
                fprintf(r->traj, "%s,%s,%d,%.6g,%d,%s", b->name, c->name, k + 1, ft[k + 1], t->iters,
                        eo_reason_name(t->reason));
                eo_bench_csv_num(r->traj, t->time);
                eo_bench_csv_num(r->traj, res.time);
                eo_bench_csv_num(r->traj, res.cpu_time);
                eo_bench_csv_num(r->traj, t->g);
                eo_bench_csv_num(r->traj, t->dist);
                eo_bench_csv_num(r->traj, rms_dist(ctx, nv, vmass, fx + (size_t)(k + 1) * nf, fx + (size_t)t0 * nf));
                fputc('\n', r->traj);
                if (!(t->reason > 0)) break;
            }
            eo_sim_set_iter_callback(sim, NULL, NULL);
            EO_TRY(rc);
            r->units_done += (double)b->nt * NT;
        }
        /* fixed iteration budgets over the measured window: exactly k iterations per
         * frame (stopping rule disabled; the solver's iteration cap max_iters = k, which
         * stops it before a (k+1)-th direction, solvers/optim/descent.c), the solver's
         * time per frame and the distance to the reference. One solver per budget, each
         * warmed up (untimed) on the window's first step before its timed frames. */
        if (b->nibud_on) {
            progress(r, si, ci, "fixed");
            /* exactly k iterations per nominal step: no substeps */
            EO_TRY(rc = eo_sim_set_adaptive(sim, 0));
            const size_t fr = (size_t)sr->win0 * nf;
            /* the iteration limit (backstop for optimizers with their own loops: nlopt counts
             * evaluations) and the time budget in the suite's clock */
            budget_cb fb = {.limit = 0, .budget = budget, .wall = r->wall};
            for (int j = 0; j < s->nibud; j++) {
                if (!b->ibud_on[j]) continue;
                bench_fixed_res *fz = p->fixed + j;
                const int limit = s->ibud[j];
                eo_solver_opts fso = so;
                fso.tol = 1e-300;
                fso.max_iters = limit;
                fso.time_budget = 0; /* the budget in the suite's clock: budget_iter */
                EO_TRY(rc = eo_sim_set_solver(sim, &fso, ccfg));
                EO_TRY(rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[sr->win0], sr->win0));
                if (s->o.warmup_iters > 0) {
                    int left = s->o.warmup_iters < limit ? s->o.warmup_iters : limit;
                    eo_solve_result wr;
                    EO_TRY(rc = eo_sim_trial(sim, NULL, NULL, x, fixed_iter, &left, NULL, &wr));
                }
                fb.limit = limit;
                eo_sim_set_iter_callback(sim, budget_iter, &fb);
                rc = eo_sim_set_state(sim, fx + fr, fv + fr, ft[sr->win0], sr->win0);
                for (int k = sr->win0; rc >= 0 && k <= sr->win1; k++) {
                    eo_sim_step_result res;
                    fb.hit = 0;
                    if ((rc = eo_sim_step(sim, &res)) < 0) break;
                    res.reason = budget_reason(&fb, res.reason);
                    const int rejected = eo_sim_index(sim) == k, f = k - sr->win0;
                    ftime[f] = r->wall ? res.time : res.cpu_time;
                    fz->frames = f + 1;
                    fz->iters += res.iterations;
                    if (res.iterations < limit && !fz->short_frames++) fz->first_short_reason = res.reason;
                    if (rejected || isnan(res.g)) fz->nan = 1;
                    if (fz->nan || res.reason == EO_DIVERGED_NONFINITE) fz->nonfinite = 1;
                    double d = rejected ? NAN : rms_dist(ctx, nv, vmass, eo_step_x(st), fx + (size_t)(k + 1) * nf);
                    if (!rejected) {
                        fz->max_dist = fmax(fz->max_dist, d);
                        fz->final_dist = d;
                    }
                    fprintf(r->fixed, "%s,%s,%d,%d,%.6g,%d,%s", b->name, c->name, limit, k + 1, ft[k + 1],
                            res.iterations, eo_reason_name(res.reason));
                    eo_bench_csv_num(r->fixed, ftime[f]);
                    eo_bench_csv_num(r->fixed, res.time);
                    eo_bench_csv_num(r->fixed, res.cpu_time);
                    eo_bench_csv_num(r->fixed, d);
                    eo_bench_csv_num(r->fixed, rms_dist(ctx, nv, vmass, fx + (size_t)(k + 1) * nf, fx + fr));
                    fputc('\n', r->fixed);
                    if (rejected) break;
                }
                if (rc < 0) break;
                fz->ms_med = eo_bench_median(fz->frames, ftime, &fz->ms_min, &fz->ms_max); /* first 64 frames */
                if (fz->frames < NW) fz->final_dist = NAN;
                r->units_done += (double)b->nt * S * 0.3;
            }
            eo_sim_set_iter_callback(sim, NULL, NULL);
            EO_TRY(rc);
        }
        eo_cfg_destroy(&ccfg);
        bench_aggregate(s, R, p, s->o.trajectory, sr->ref_disp, sr->meas);
        r->out->sum->runs++;
        if (p->nonfinite) r->out->sum->nonfinite++;
        if (p->nan) r->out->sum->nan++;
        for (int q = 0; q < s->nreq; q++)
            if (s->req[q] == ci && strcmp(p->status, "converged") != 0) r->out->sum->required_failures++;
        fflush(r->curves);
        fflush(r->traj);
        fflush(r->fixed);
    }
    EO_TRY(rc = eo_afile_commit(ctx, &datf));
    progress(r, si, -1, "done");
    rc = EO_OK;
fail:
    eo_afile_abort(ctx, &datf);
    if (rc < 0 && !strstr(eo_ctx_message(ctx), b->name)) rc = bench_wrap_err(ctx, rc, s->path, "scene", b->name);
    eo_solver_destroy(&sv);
    eo_cfg_destroy(&ccfg);
    eo_sim_destroy(&sim);
    eo_cfg_destroy(&scfg);
    eo_free(ctx, mem);
    eo_free(ctx, allref);
    return rc;
}

static void read_loadavg(char *buf, size_t n)
{
    double l[3];
    if (getloadavg(l, 3) == 3) snprintf(buf, n, "%.2f %.2f %.2f", l[0], l[1], l[2]);
    else snprintf(buf, n, "unknown");
}

int eo_bench_run(eo_ctx *ctx, const eo_bench_suite *s, const eo_bench_run_opts *opts, eo_bench_summary *sum)
{
    memset(sum, 0, sizeof *sum);
    if (!opts || !opts->out_dir) return eo_error(ctx, EO_ERR_INVALID, "bench: no output folder");
    run_ctx r = {.ctx = ctx, .s = s, .ro = opts};
    bench_out out = {.s = s, .dir = opts->out_dir, .sum = sum};
    r.out = &out;
    out.repeats = run_repeats(opts, s->o.repeats); /* the suite's; scenes may set their own */
    const char *clk = opts->clock ? opts->clock : s->o.clock;
    if (strcmp(clk, "cpu") && strcmp(clk, "wall"))
        return eo_error(ctx, EO_ERR_INVALID, "bench: clock '%s': expected cpu or wall", clk);
    r.wall = out.wall = strcmp(clk, "wall") == 0;
    if (eo_ctx_dist(ctx)) { /* every configuration distributed, before anything is written */
        if (!opts->owned_sum) return eo_error(ctx, EO_ERR_INVALID, "bench: a distributed run needs opts->owned_sum");
        char bad[400] = "";
        size_t k = 0;
        int nbad = 0;
        for (int c = 0; c < s->ncf; c++) {
            eo_cfg *cc = NULL;
            eo_solver_opts so;
            int rc2 = bench_config_cfg(ctx, s->cf + c, &cc, &so);
            eo_cfg_destroy(&cc);
            if (rc2 < 0) return rc2;
            const char *on = so.optimizer;
            if (strcmp(so.backend, "petsc") == 0 || strncmp(on, "petsc_", 6) == 0 || strncmp(on, "snes_", 5) == 0 ||
                strncmp(on, "tao_", 4) == 0)
                continue;
            if (k + strlen(s->cf[c].name) + 8 < sizeof bad)
                k += (size_t)snprintf(bad + k, sizeof bad - k, "%s%s (%s)", nbad ? ", " : "", s->cf[c].name, on);
            nbad++;
        }
        if (nbad)
            return eo_error_at(ctx, EO_ERR_UNSUPPORTED, EO_ERRLOC_FILE(s->path, -1),
                               "under mpirun (%d ranks) every configuration must run distributed (solver.backend = "
                               "petsc, or a petsc_, snes_ or tao_ optimizer); %d would run on each rank's part of the "
                               "mesh alone: %s", eo_ctx_dist(ctx)->nparts, nbad, bad);
    }
    out.plots = opts->plots >= 0 ? opts->plots : s->o.plots;
    eo_afile *cf = NULL, *tf = NULL, *xf = NULL;
    int rc;
    char path[1200];
    out.res = eo_calloc(ctx, (size_t)s->nsc, sizeof *out.res);
    if (!out.res) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    snprintf(path, sizeof path, "%s/plots", opts->out_dir);
    EO_TRY(rc = eo_mkdir_p(ctx, path));
    snprintf(path, sizeof path, "%s/curves.csv", opts->out_dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &cf));
    snprintf(path, sizeof path, "%s/trajectory.csv", opts->out_dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &tf));
    snprintf(path, sizeof path, "%s/fixed.csv", opts->out_dir);
    EO_TRY(rc = eo_afile_open(ctx, path, &xf));
    r.curves = eo_afile_fp(cf);
    r.traj = eo_afile_fp(tf);
    r.fixed = eo_afile_fp(xf);
    /* time columns: solve_time / time = the suite's clock (the one in the report), then
     * wall and CPU seconds both */
    fprintf(r.fixed, "scene,config,iter_budget,step,t,iterations,reason,solve_time,solve_wall,solve_cpu,dist_rms,"
                     "ref_disp_rms\n");
    fprintf(r.curves, "scene,step,config,iteration,time,time_min,time_max,wall_time,cpu_time,g,rel_energy_err,"
                      "rel_pos_err,grad_norm,reason\n");
    fprintf(r.traj, "scene,config,step,t,iterations,reason,solve_time,solve_wall,solve_cpu,g,dist_rms,ref_disp_rms\n");
    for (int i = 0; i < s->nsc; i++)
        r.units_total += scene_units(s, s->sc + i, run_repeats(opts, s->sc[i].repeats), traj_steps_estimate(s->sc + i));
    read_loadavg(out.load_start, sizeof out.load_start);
    r.t0 = out.t_start = eo_wtime();
    const double c0 = eo_cputime();
    for (int i = 0; i < s->nsc; i++) EO_TRY(rc = run_scene(&r, i));
    out.t_end = eo_wtime();
    out.cpu_seconds = eo_cputime() - c0;
    read_loadavg(out.load_end, sizeof out.load_end);
    sum->seconds = out.t_end - out.t_start;
    EO_TRY(rc = eo_afile_commit(ctx, &cf));
    EO_TRY(rc = eo_afile_commit(ctx, &tf));
    EO_TRY(rc = eo_afile_commit(ctx, &xf));
    if (out.plots) {
        out.gnuplot = system("command -v gnuplot >/dev/null 2>&1") == 0;
        if (out.gnuplot) {
            for (int i = 0; i < s->nsc; i++)
                if (eo_bench_plot_scene(ctx, &out, i) >= 0) sum->plots_made++;
            if (eo_bench_plot_pareto(ctx, &out) >= 0) sum->plots_made++;
            EO_TRY(rc = eo_bench_plot_profiles(ctx, &out));
        }
    }
    EO_TRY(rc = eo_bench_write_profiles(ctx, &out));
    EO_TRY(rc = eo_bench_write_summary(ctx, &out));
    EO_TRY(rc = eo_bench_write_report(ctx, &out));
    rc = EO_OK;
fail:
    eo_afile_abort(ctx, &cf);
    eo_afile_abort(ctx, &tf);
    eo_afile_abort(ctx, &xf);
    for (int i = 0; i < s->nsc; i++) {
        bench_scene_res *sr = out.res + i;
        eo_free(ctx, sr->meas);
        eo_free(ctx, sr->motion);
        eo_free(ctx, sr->allref);
        for (int c = 0; sr->pair && c < s->ncf; c++) {
            eo_free(ctx, sr->pair[c].st);
            eo_free(ctx, sr->pair[c].tr);
        }
        eo_free(ctx, sr->pair);
        eo_free(ctx, sr->ref);
    }
    eo_free(ctx, out.res);
    return rc;
}
