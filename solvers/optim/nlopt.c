/* NLopt's gradient-based local optimizers as an elastopt optimizer (registry key "nlopt";
 * built only when NLopt is found, EO_HAVE_NLOPT).
 *
 * Solves the unconstrained problem  min_x g(x),  x ∈ Rⁿ  with one of (`algorithm`):
 *   lbfgs    NLOPT_LD_LBFGS: Lukšan's limited-memory BFGS with a More–Thuente-like line
 *            search (default)
 *   tnewton  NLOPT_LD_TNEWTON_PRECOND_RESTART: truncated Newton, inner CG on finite
 *            differences of ∇g, preconditioned by L-BFGS, with steepest-descent restarts
 *   var2     NLOPT_LD_VAR2: shifted limited-memory variable-metric, rank-2 updates
 *   mma      NLOPT_LD_MMA: Svanberg's method of moving asymptotes (conservative
 *            separable approximations; globally convergent, slow on ill-conditioned g)
 * (S. G. Johnson, The NLopt nonlinear-optimization package, and the references there.)
 *
 * Mapping to elastopt:
 *  - NLopt's objective callback returns g and ∇g from one eo_objective_gradient call. A
 *    non-finite g (+∞ outside the domain of a barrier material) is returned as HUGE_VAL
 *    with a zero gradient; the line searches then shrink the step. If NLopt gives up after
 *    such a value (NLOPT_FAILURE / NLOPT_ROUNDOFF_LIMITED with the last value non-finite),
 *    the reason is EO_DIVERGED_NONFINITE. HUGE_VAL is never a best point.
 *  - Iterations: NLopt has none visible, so an iteration is an evaluation that improves
 *    the best g (strictly). x₀ is evaluated first (record 0); when x_{k+1} is found, record
 *    k (x_k, g_k, ‖∇g_k‖, ls_evals = evaluations after x_k up to x_{k+1}) is reported, and
 *    the stop rule, the time budget and the iteration cap are checked at x_{k+1}; any of
 *    them calls nlopt_force_stop. The last record (x out = the best point) carries the
 *    reason. alpha and decrement are NAN (no direction is exposed), shift is 0.
 *  - Stop rule: see external.h (newton_decrement falls back to `gradient`).
 *  - Caps: solver.max_iters bounds the improvements (EO_DIVERGED_MAX_ITERS); NLopt's
 *    maxeval = `max_evals` (0: 50·(solver.max_iters + 1)) bounds evaluations (also
 *    EO_DIVERGED_MAX_ITERS); solver.time_budget is NLopt's maxtime and is checked in the
 *    callback (EO_DIVERGED_TIME_BUDGET).
 *  - NLopt's own tests (`ftol_rel`, `xtol_rel`, 0 = off) end with EO_CONVERGED_ENERGY
 *    (NLOPT_FTOL_REACHED), EO_CONVERGED_STEP (NLOPT_XTOL_REACHED) or, for its other
 *    successes, EO_CONVERGED_EXTERNAL; NLOPT_FAILURE and NLOPT_ROUNDOFF_LIMITED are
 *    EO_DIVERGED_EXTERNAL; bad arguments EO_ERR_INVALID, out of memory EO_ERR_NOMEM.
 *  - Memory: our buffers are sized in setup and the callback allocates nothing; the
 *    nlopt_opt object and NLopt's own work arrays (allocated inside each nlopt_optimize)
 *    use malloc, outside the context's counter.
 * Parameters live in a private struct (the backend is optional, so solver.h does not
 * declare them); the descriptor table below is their documentation. */
#include <math.h>
#include <nlopt.h>
#include <stddef.h>
#include <string.h>

#include "external.h"

typedef struct eo_nlopt_params {
    char algorithm[16];  /* "lbfgs" (default), "tnewton", "var2", "mma" */
    int memory;          /* vectors stored by lbfgs/var2/tnewton (default 10; 0 = NLopt's) */
    double ftol_rel;     /* NLopt's relative change of g, 0 = off (default 0) */
    double xtol_rel;     /* NLopt's relative change of x, 0 = off (default 0) */
    int max_evals;       /* evaluation cap, 0 = 50·(solver.max_iters + 1) (default 0) */
} eo_nlopt_params;

static const char *const nl_algorithms[] = {"lbfgs", "tnewton", "var2", "mma", NULL};
static const nlopt_algorithm nl_codes[] = {NLOPT_LD_LBFGS, NLOPT_LD_TNEWTON_PRECOND_RESTART,
                                           NLOPT_LD_VAR2, NLOPT_LD_MMA};

static const eo_param_desc nl_desc[] = {
    {.key = "algorithm", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_nlopt_params, algorithm),
     .size = sizeof(((eo_nlopt_params *)0)->algorithm), .def.s = "lbfgs", .choices = nl_algorithms,
     .help = "lbfgs = LD_LBFGS (limited-memory BFGS), tnewton = LD_TNEWTON_PRECOND_RESTART "
             "(preconditioned truncated Newton), var2 = LD_VAR2 (shifted variable metric, "
             "rank 2), mma = LD_MMA (moving asymptotes)"},
    {.key = "memory", .kind = EO_PARAM_INT, .offset = offsetof(eo_nlopt_params, memory), .def.i = 10,
     .min = 0, .max = 10000, .range = EO_RANGE_CLOSED,
     .help = "stored vectors of lbfgs/var2/tnewton (0 = NLopt's heuristic)"},
    {.key = "ftol_rel", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_nlopt_params, ftol_rel),
     .def.d = 0, .min = 0, .range = EO_RANGE_MIN,
     .help = "NLopt's stop on relative change of g (0 = off; reason converged_energy)"},
    {.key = "xtol_rel", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_nlopt_params, xtol_rel),
     .def.d = 0, .min = 0, .range = EO_RANGE_MIN,
     .help = "NLopt's stop on relative change of x (0 = off; reason converged_step)"},
    {.key = "max_evals", .kind = EO_PARAM_INT, .offset = offsetof(eo_nlopt_params, max_evals),
     .def.i = 0, .min = 0, .range = EO_RANGE_MIN,
     .help = "objective evaluations per minimization, 0 = 50*(solver.max_iters+1)"},
    {0},
};

typedef struct nl_state {
    nlopt_opt opt;           /* for (algorithm, memory, n) of setup; NULL if n = 0 */
    int n, alg, memory;
    double *xbest, *gradw;   /* n each: best point x_k, gradient scratch */
    eo_ctx *ctx;
    /* per minimization */
    const eo_solver_ctx *sc;
    double t0, gbest, gnbest, gn0, g_prev, step_norm;
    int k, reason, status, last_nonfinite, user_stop;
    long evals, evals_at_record;
} nl_state;

static void nl_free(nl_state *st, eo_ctx *ctx)
{
    if (st->opt) nlopt_destroy(st->opt);
    st->opt = NULL;
    eo_free(ctx, st->xbest);
    st->xbest = NULL;
}

static int nl_alg_index(const char *name)
{
    for (int i = 0; nl_algorithms[i]; i++)
        if (strcmp(name, nl_algorithms[i]) == 0) return i;
    return -1;
}

static const eo_nlopt_params *nl_params(const void *params, eo_nlopt_params *def)
{
    if (params) return params;
    eo_params_default(nl_desc, def);
    return def;
}

static double nl_objective(unsigned un, const double *x, double *grad, void *data);

static int nl_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    nl_state *st = vst;
    eo_nlopt_params def;
    const eo_nlopt_params *pp = nl_params(params, &def);
    nl_free(st, ctx);
    memset(st, 0, sizeof *st);
    st->ctx = ctx;
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "nlopt: n = %d < 0", n);
    st->n = n;
    st->alg = nl_alg_index(pp->algorithm);
    st->memory = pp->memory;
    if (st->alg < 0) return eo_error(ctx, EO_ERR_INVALID, "nlopt: unknown algorithm '%s'", pp->algorithm);
    size_t m = (size_t)(n > 0 ? n : 1);
    st->xbest = eo_calloc(ctx, 2 * m, sizeof(double));
    if (!st->xbest) return eo_error(ctx, EO_ERR_NOMEM, "nlopt: out of memory (n = %d)", n);
    st->gradw = st->xbest + m;
    if (n == 0) return EO_OK;
    st->opt = nlopt_create(nl_codes[st->alg], (unsigned)n);
    if (!st->opt) return eo_error(ctx, EO_ERR_NOMEM, "nlopt: nlopt_create failed (n = %d)", n);
    if (nlopt_set_min_objective(st->opt, nl_objective, st) < 0 ||
        (pp->memory > 0 && nlopt_set_vector_storage(st->opt, (unsigned)pp->memory) < 0))
        return eo_error(ctx, EO_ERR_INVALID, "nlopt: %s", nlopt_get_errmsg(st->opt));
    return EO_OK;
}

static void nl_destroy(void *vst, eo_ctx *ctx) { nl_free(vst, ctx); }

/* A new best point x (g, ‖∇g‖): record k (the previous best) is complete; report it, move
 * to x_{k+1} and check the stop rule, the time budget and the cap there. */
static void nl_improved(nl_state *st, const double *x, double g, double gn)
{
    const eo_solver_ctx *sc = st->sc;
    const int n = st->n;
    eo_iter_info info = {.iteration = st->k, .g = st->gbest, .grad_norm = st->gnbest,
                         .decrement = NAN, .alpha = NAN,
                         .ls_evals = (int)(st->evals - st->evals_at_record), .shift = 0,
                         .inverted = eo_external_inverted(sc, st->xbest), .reason = 0,
                         .x = st->xbest};
    if (eo_solver_report(sc, st->t0, &info)) {
        st->reason = EO_DIVERGED_EXTERNAL; /* x stays x_k, no further record */
        st->user_stop = 1;
        nlopt_force_stop(st->opt);
        return;
    }
    double s2 = 0;
    for (int i = 0; i < n; i++) {
        double s = x[i] - st->xbest[i];
        s2 += s * s;
        st->xbest[i] = x[i];
    }
    st->step_norm = sqrt(s2);
    st->g_prev = st->gbest;
    st->gbest = g;
    st->gnbest = gn;
    st->k++;
    st->evals_at_record = st->evals;
    eo_stop_info si = {.iteration = st->k, .g = g, .g_prev = st->g_prev, .grad_norm = gn,
                       .grad_norm0 = st->gn0, .decrement = NAN, .step_norm = st->step_norm,
                       .x_norm = eo_norm2(n, x), .tol = sc->tol};
    int reason = eo_external_stop(sc, &si, x, st->gradw);
    if (!reason && sc->time_budget > 0 && eo_wtime() - st->t0 > sc->time_budget)
        reason = EO_DIVERGED_TIME_BUDGET;
    if (!reason && st->k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
    if (reason) {
        st->reason = reason;
        nlopt_force_stop(st->opt);
    }
}

/* NLopt's objective: g and ∇g; HUGE_VAL where g is not finite. No allocation. */
static double nl_objective(unsigned un, const double *x, double *grad, void *data)
{
    nl_state *st = data;
    const eo_solver_ctx *sc = st->sc;
    const size_t bytes = sizeof(double) * un;
    double g = NAN;
    if (st->reason || st->status < 0) { /* already stopping */
        if (grad) memset(grad, 0, bytes);
        return HUGE_VAL;
    }
    st->evals++;
    int rc = eo_objective_gradient(sc->obj, x, &g, st->gradw);
    if (rc < 0) {
        st->status = rc;
        nlopt_force_stop(st->opt);
        if (grad) memset(grad, 0, bytes);
        return HUGE_VAL;
    }
    double gn = isfinite(g) ? eo_norm2(st->n, st->gradw) : NAN;
    st->last_nonfinite = !(isfinite(g) && isfinite(gn));
    if (st->last_nonfinite) {
        if (grad) memset(grad, 0, bytes);
        return HUGE_VAL;
    }
    if (grad) memcpy(grad, st->gradw, bytes);
    if (g < st->gbest) nl_improved(st, x, g, gn);
    else if (sc->time_budget > 0 && eo_wtime() - st->t0 > sc->time_budget) {
        st->reason = EO_DIVERGED_TIME_BUDGET;
        nlopt_force_stop(st->opt);
    }
    return g;
}

/* Reason for an NLopt result when our callback did not stop the run; negative status
 * for results that are errors. */
static int nl_reason(nl_state *st, nlopt_result r, int *status)
{
    *status = EO_OK;
    switch (r) {
    case NLOPT_SUCCESS:
    case NLOPT_STOPVAL_REACHED: return EO_CONVERGED_EXTERNAL;
    case NLOPT_FTOL_REACHED: return EO_CONVERGED_ENERGY;
    case NLOPT_XTOL_REACHED: return EO_CONVERGED_STEP;
    case NLOPT_MAXEVAL_REACHED: return EO_DIVERGED_MAX_ITERS;
    case NLOPT_MAXTIME_REACHED: return EO_DIVERGED_TIME_BUDGET;
    case NLOPT_INVALID_ARGS:
        *status = eo_error(st->ctx, EO_ERR_INVALID, "nlopt: invalid arguments: %s",
                           nlopt_get_errmsg(st->opt) ? nlopt_get_errmsg(st->opt) : "");
        return EO_DIVERGED_EXTERNAL;
    case NLOPT_OUT_OF_MEMORY:
        *status = eo_error(st->ctx, EO_ERR_NOMEM, "nlopt: out of memory");
        return EO_DIVERGED_EXTERNAL;
    case NLOPT_FAILURE:
    case NLOPT_ROUNDOFF_LIMITED:
    default:
        eo_log(st->ctx, EO_LOG_DEBUG, "nlopt: %s%s", nlopt_result_to_string(r),
               st->last_nonfinite ? " after a non-finite objective value" : "");
        return st->last_nonfinite ? EO_DIVERGED_NONFINITE : EO_DIVERGED_EXTERNAL;
    }
}

static int nl_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                       eo_solve_result *res)
{
    nl_state *st = vst;
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    eo_nlopt_params def;
    const eo_nlopt_params *pp = nl_params(params, &def);
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    int rc = EO_OK, reason = 0;

    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    st->sc = sc;
    st->t0 = eo_wtime();
    st->k = 0;
    st->reason = st->status = st->last_nonfinite = st->user_stop = 0;
    st->evals = st->evals_at_record = 0;
    st->g_prev = st->step_norm = NAN;
    if (n != st->n || nl_alg_index(pp->algorithm) != st->alg || pp->memory != st->memory) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID,
                      "nlopt: set up for n = %d, algorithm %s, memory %d; called with n = %d, %s, %d",
                      st->n, nl_algorithms[st->alg], st->memory, n, pp->algorithm, pp->memory);
        goto done;
    }
    eo_external_note_rule(sc, "nlopt");
    /* record 0: the start point, evaluated here so a bad or optimal start needs no NLopt */
    memcpy(st->xbest, x, sizeof(double) * n);
    rc = eo_objective_gradient(obj, x, &st->gbest, st->gradw);
    if (rc < 0) goto done;
    st->gnbest = st->gn0 = isfinite(st->gbest) ? eo_norm2(n, st->gradw) : NAN;
    if (!isfinite(st->gbest) || !isfinite(st->gnbest)) {
        st->gbest = isfinite(st->gbest) ? st->gbest : INFINITY;
        reason = EO_DIVERGED_NONFINITE;
    } else {
        eo_stop_info si = {.iteration = 0, .g = st->gbest, .g_prev = NAN, .grad_norm = st->gnbest,
                           .grad_norm0 = st->gn0, .decrement = NAN, .step_norm = NAN,
                           .x_norm = eo_norm2(n, x), .tol = sc->tol};
        reason = eo_external_stop(sc, &si, x, st->gradw);
        if (!reason && sc->max_iters <= 0) reason = EO_DIVERGED_MAX_ITERS;
    }
    if (!reason) {
        double maxev = pp->max_evals > 0 ? pp->max_evals : 50.0 * ((double)sc->max_iters + 1);
        nlopt_set_maxeval(st->opt, maxev < 2e9 ? (int)maxev : 2000000000);
        nlopt_set_maxtime(st->opt, sc->time_budget > 0 ? sc->time_budget : 0);
        nlopt_set_ftol_rel(st->opt, pp->ftol_rel);
        nlopt_set_xtol_rel(st->opt, pp->xtol_rel);
        double fmin = HUGE_VAL;
        nlopt_result r = nlopt_optimize(st->opt, x, &fmin);
        if (st->status < 0) {
            rc = st->status;
            goto done;
        }
        if (st->reason) reason = st->reason;
        else {
            reason = nl_reason(st, r, &rc);
            if (rc < 0) goto done;
        }
    }
    if (!st->user_stop) {
        eo_iter_info info = {.iteration = st->k, .g = st->gbest, .grad_norm = st->gnbest,
                             .decrement = NAN, .alpha = NAN,
                             .ls_evals = (int)(st->evals - st->evals_at_record), .shift = 0,
                             .inverted = eo_external_inverted(sc, st->xbest), .reason = reason,
                             .x = st->xbest};
        eo_solver_report(sc, st->t0, &info);
    }
    memcpy(x, st->xbest, sizeof(double) * n);
done:
    res->reason = reason;
    res->iterations = st->k;
    res->g = st->gbest;
    res->grad_norm = st->gnbest;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, st->t0, rc);
    st->sc = NULL;
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_nlopt = {
    .info = {.name = "nlopt",
             .summary = "NLopt gradient-based local optimizers (lbfgs, tnewton, var2, mma)",
             .params = nl_desc,
             .params_size = sizeof(eo_nlopt_params)},
    .state_size = sizeof(nl_state),
    .needs_ops = EO_OBJ_NEEDS_WHOLE,
    .needs_linear = 0,
    .needs_hessian = 0,
    .setup = nl_setup,
    .minimize = nl_minimize,
    .destroy = nl_destroy,
};
