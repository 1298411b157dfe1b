/* Ipopt's interior-point method as an elastopt optimizer (registry key "ipopt"; built only
 * when Ipopt is found, EO_HAVE_IPOPT). Written against the C interface of Ipopt 3.11
 * (Debian 12: coinor-libipopt 3.11.9, types Number/Index/Bool = double/int/int).
 *
 * Solves  min_x g(x),  x ∈ Rⁿ,  as Ipopt's NLP with n variables, bounds ±1e19 (= none) and
 * m = 0 constraints, so the barrier is empty and Ipopt runs a damped Newton method on g:
 * (W + δ_w I) Δx = −∇g with W = obj_factor·∇²g, the inertia correction δ_w ≥ 0 chosen by
 * Ipopt so that the matrix is positive definite, and a filter line search on g
 * (A. Wächter, L. T. Biegler, Math. Program. 106 (2006) 25–57).
 *
 * Mapping to elastopt:
 *  - eval_f = eo_objective_value; a non-finite g returns FALSE, which Ipopt treats as an
 *    evaluation error at a trial point and cuts the step back (never accepted).
 *    eval_grad_f = eo_objective_gradient.
 *  - eval_h (`hessian` = exact): eo_objective_hessian with the Hessian fix's per-element
 *    projection (sc->hessfix->elem_proj, none if no fix is given), times obj_factor.
 *    Our eo_csc stores the upper triangle by columns; entry q of column j, row i ≤ j, is
 *    Ipopt's lower-triangle triplet (iRow = j, jCol = i), so values are copied in CSC
 *    order. The structure is the pattern of the Hessian at x₀ (evaluated once before
 *    Ipopt starts) and must stay the same object (pattern arrays and nnz) afterwards.
 *    `hessian` = limited-memory: Ipopt's L-BFGS approximation, no Hessian calls.
 *  - Iterations: Ipopt's intermediate callback runs once per iteration at the iterate
 *    x_k, before Ipopt's own convergence test. Ipopt 3.11 cannot hand x_k to the callback
 *    (GetIpoptCurrentIterate is 3.14+), so x_k is taken as the point of the last gradient
 *    evaluation (Ipopt evaluates ∇g at accepted iterates only); its g must equal the
 *    callback's obj_value (checked). At callback k ≥ 1 record k−1 is reported complete:
 *    α = alpha_pr, ls_evals = ls_trials and shift = δ_w of the step x_{k−1} → x_k, and
 *    decrement = λ²/2 = −∇g(x_{k−1})ᵀΔx/2 of Ipopt's direction Δx = (x_k − x_{k−1})/α
 *    (exact Hessian: the Newton decrement of W + δ_w I, as newton reports it with a shift;
 *    limited-memory: a quasi-Newton estimate, as lbfgs reports it). Then the stop rule and
 *    solver.time_budget are checked at x_k, the rule seeing that decrement: so
 *    newton_decrement stops at the iterate AFTER the step whose λ²/2 ≤ tol (one step
 *    later than newton, never less accurate). Returning FALSE stops Ipopt and the run
 *    ends with the rule's reason. The last record (x out = x_k of the last callback)
 *    carries the reason (decrement NAN: no direction from x_k; res.decrement is that of
 *    the step into x_k).
 *  - Ipopt's own termination, by `tol` (its scaled NLP error, here ≈ ‖∇g‖_∞ times Ipopt's
 *    gradient-based objective scaling; default 1e-12 so that normally the elastopt rule
 *    decides), is EO_CONVERGED_EXTERNAL. Ipopt's "acceptable" early exit is disabled
 *    (acceptable_iter = 0); options files (ipopt.opt) are not read; the banner is off.
 *  - ApplicationReturnStatus → reason: Solve_Succeeded, Solved_To_Acceptable_Level →
 *    EO_CONVERGED_EXTERNAL; Search_Direction_Becomes_Too_Small → EO_CONVERGED_STEP;
 *    Maximum_Iterations_Exceeded (max_iter = solver.max_iters) → EO_DIVERGED_MAX_ITERS;
 *    Maximum_CpuTime_Exceeded → EO_DIVERGED_TIME_BUDGET; Restoration_Failed →
 *    EO_DIVERGED_LINESEARCH; Error_In_Step_Computation → EO_DIVERGED_LINSOLVE;
 *    Invalid_Number_Detected → EO_DIVERGED_NONFINITE; Diverging_Iterates, exceptions and
 *    the rest → EO_DIVERGED_EXTERNAL; Invalid_Option, Invalid_Problem_Definition,
 *    Not_Enough_Degrees_Of_Freedom → status EO_ERR_INVALID; Insufficient_Memory →
 *    EO_ERR_NOMEM. An objective error (negative status) stops Ipopt and is returned.
 *  - Memory: our buffers are sized in setup and the callbacks allocate nothing. The
 *    IpoptProblem is created per minimization (its Hessian size is known only then) and
 *    Ipopt/MUMPS allocate internally with C++ new/malloc, outside the context's counter.
 * Parameters live in a private struct (the backend is optional, so solver.h does not
 * declare them); the descriptor table below is their documentation. */
#include <coin/IpStdCInterface.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "external.h" /* eo_external_inverted, eo_norm2 */

typedef struct eo_ipopt_params {
    char hessian[16];        /* "exact" (default) or "limited-memory" */
    char mu_strategy[16];    /* "adaptive" (default) or "monotone" */
    char linear_solver[16];  /* Ipopt's linear_solver, default "mumps" */
    int print_level;         /* Ipopt's print_level 0..12 (default 0 = silent) */
    double tol;              /* Ipopt's tol (default 1e-12) */
} eo_ipopt_params;

#define IP_STR(f) .size = sizeof(((eo_ipopt_params *)0)->f)
static const char *const ip_hessians[] = {"exact", "limited-memory", NULL};
static const char *const ip_mus[] = {"adaptive", "monotone", NULL};
/* mumps is linked into Debian's libipopt; the HSL solvers load libhsl.so and pardiso
 * libpardiso.so at run time (absent: Ipopt fails, status EO_ERR_INVALID). */
static const char *const ip_linear[] = {"mumps", "ma27", "ma57", "ma77", "ma86", "ma97",
                                        "pardiso", NULL};

static const eo_param_desc ip_desc[] = {
    {.key = "hessian", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_ipopt_params, hessian),
     IP_STR(hessian), .def.s = "exact", .choices = ip_hessians,
     .help = "exact = objective Hessian with the hessian_fix projection; limited-memory = "
             "Ipopt's L-BFGS"},
    {.key = "mu_strategy", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_ipopt_params, mu_strategy),
     IP_STR(mu_strategy), .def.s = "adaptive", .choices = ip_mus,
     .help = "Ipopt's barrier parameter update (no bounds here, so it barely matters)"},
    {.key = "linear_solver", .kind = EO_PARAM_CHOICE,
     .offset = offsetof(eo_ipopt_params, linear_solver), IP_STR(linear_solver), .def.s = "mumps",
     .choices = ip_linear,
     .help = "Ipopt's linear solver (mumps is built in; ma* need libhsl.so, pardiso libpardiso.so)"},
    {.key = "print_level", .kind = EO_PARAM_INT, .offset = offsetof(eo_ipopt_params, print_level),
     .def.i = 0, .min = 0, .max = 12, .range = EO_RANGE_CLOSED,
     .help = "Ipopt's output to stdout, 0 = none"},
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_ipopt_params, tol), .def.d = 1e-12,
     .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "Ipopt's own tolerance on its scaled NLP error (~ |grad g|_inf); the elastopt "
             "stop rule with solver.tol is applied every iteration as well"},
    {0},
};

typedef struct ip_state {
    int n;
    double *xl, *xu;         /* n: -1e19, +1e19 */
    double *xg, *gradg;      /* n each: point of the last gradient evaluation, ∇g there */
    double *xcur, *gradcur;  /* n each: iterate of the last intermediate callback, ∇g there */
    eo_ctx *ctx;
    /* per minimization */
    const eo_solver_ctx *sc;
    eo_proj proj;
    const eo_csc *H;         /* Hessian whose pattern Ipopt was given */
    const int *colptr, *rowind;
    int nnz;
    double t0, gn0;
    double glast, gnlast;    /* g, ‖∇g‖ at xg */
    double gcur, gncur;      /* at xcur */
    double dec;              /* λ²/2 of the last step's direction (NAN if none) */
    int kcur, ncb, reason, status, user_stop, mismatch;
} ip_state;

static void ip_free(ip_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->xl);
    st->xl = NULL;
}

static const eo_ipopt_params *ip_params(const void *params, eo_ipopt_params *def)
{
    if (params) return params;
    eo_params_default(ip_desc, def);
    return def;
}

static int ip_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    ip_state *st = vst;
    (void)params;
    ip_free(st, ctx);
    memset(st, 0, sizeof *st);
    st->ctx = ctx;
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "ipopt: n = %d < 0", n);
    st->n = n;
    size_t m = (size_t)(n > 0 ? n : 1);
    st->xl = eo_calloc(ctx, 6 * m, sizeof(double));
    if (!st->xl) return eo_error(ctx, EO_ERR_NOMEM, "ipopt: out of memory (n = %d)", n);
    st->xu = st->xl + m;
    st->xg = st->xl + 2 * m;
    st->gradg = st->xl + 3 * m;
    st->xcur = st->xl + 4 * m;
    st->gradcur = st->xl + 5 * m;
    for (int i = 0; i < n; i++) st->xl[i] = -1e19, st->xu[i] = 1e19;
    return EO_OK;
}

static void ip_destroy(void *vst, eo_ctx *ctx) { ip_free(vst, ctx); }

/* ---- Ipopt callbacks (no allocation) ------------------------------------------------ */
static Bool ip_eval_f(Index n, Number *x, Bool new_x, Number *obj_value, UserDataPtr user)
{
    ip_state *st = user;
    (void)n, (void)new_x;
    if (st->status < 0) return FALSE;
    int rc = eo_objective_value(st->sc->obj, x, obj_value);
    if (rc < 0) {
        st->status = rc;
        return FALSE;
    }
    return isfinite(*obj_value) ? TRUE : FALSE;
}

static Bool ip_eval_grad_f(Index n, Number *x, Bool new_x, Number *grad_f, UserDataPtr user)
{
    ip_state *st = user;
    (void)new_x;
    if (st->status < 0) return FALSE;
    double g = NAN;
    int rc = eo_objective_gradient(st->sc->obj, x, &g, grad_f);
    if (rc < 0) {
        st->status = rc;
        return FALSE;
    }
    double gn = isfinite(g) ? eo_norm2(n, grad_f) : NAN;
    if (!(isfinite(g) && isfinite(gn))) return FALSE;
    memcpy(st->xg, x, sizeof(double) * (size_t)n);
    memcpy(st->gradg, grad_f, sizeof(double) * (size_t)n);
    st->glast = g;
    st->gnlast = gn;
    return TRUE;
}

static Bool ip_eval_g(Index n, Number *x, Bool new_x, Index m, Number *g, UserDataPtr user)
{
    (void)n, (void)x, (void)new_x, (void)m, (void)g, (void)user;
    return TRUE; /* m = 0 */
}

static Bool ip_eval_jac_g(Index n, Number *x, Bool new_x, Index m, Index nele_jac, Index *iRow,
                          Index *jCol, Number *values, UserDataPtr user)
{
    (void)n, (void)x, (void)new_x, (void)m, (void)nele_jac, (void)iRow, (void)jCol, (void)values;
    (void)user;
    return TRUE; /* m = 0: empty Jacobian */
}

static Bool ip_eval_h(Index n, Number *x, Bool new_x, Number obj_factor, Index m, Number *lambda,
                      Bool new_lambda, Index nele_hess, Index *iRow, Index *jCol, Number *values,
                      UserDataPtr user)
{
    ip_state *st = user;
    (void)new_x, (void)m, (void)lambda, (void)new_lambda;
    if (!st->H || nele_hess != st->nnz) return FALSE; /* limited-memory: never called */
    if (!values) { /* structure: upper (i ≤ j) by columns → Ipopt's lower (j, i) */
        for (Index j = 0; j < n; j++)
            for (int q = st->colptr[j]; q < st->colptr[j + 1]; q++) iRow[q] = j, jCol[q] = st->rowind[q];
        return TRUE;
    }
    if (st->status < 0) return FALSE;
    eo_csc *H = NULL;
    int rc = eo_objective_hessian(st->sc->obj, x, st->proj, &H);
    if (rc < 0) {
        st->status = rc;
        return FALSE;
    }
    if (H != st->H || H->nnz != st->nnz || H->colptr != st->colptr || H->rowind != st->rowind) {
        st->status = eo_error(st->ctx, EO_ERR_INVALID,
                              "ipopt: the objective's Hessian pattern changed during a minimization");
        return FALSE;
    }
    for (int q = 0; q < st->nnz; q++) {
        values[q] = obj_factor * H->val[q];
        if (!isfinite(values[q])) return FALSE;
    }
    return TRUE;
}

static Bool ip_intermediate(Index alg_mod, Index iter_count, Number obj_value, Number inf_pr,
                            Number inf_du, Number mu, Number d_norm, Number regularization_size,
                            Number alpha_du, Number alpha_pr, Index ls_trials, UserDataPtr user)
{
    ip_state *st = user;
    const eo_solver_ctx *sc = st->sc;
    const int n = st->n;
    (void)alg_mod, (void)iter_count, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm;
    (void)alpha_du;
    if (st->status < 0) return FALSE;
    /* x_k = the last gradient point, if its g is the g Ipopt reports for x_k */
    double g = obj_value, gn = NAN;
    if (fabs(st->glast - obj_value) <= 1e-12 * fmax(1, fabs(obj_value))) gn = st->gnlast;
    else st->mismatch++;
    /* decrement of the direction Δx = (x_k − x_{k−1})/α taken from x_{k−1} */
    double dec = NAN;
    if (st->ncb > 0 && !isnan(gn) && !isnan(st->gncur) && alpha_pr > 0) {
        double d = 0;
        for (int i = 0; i < n; i++) d -= st->gradcur[i] * (st->xg[i] - st->xcur[i]);
        dec = d / (2 * alpha_pr);
    }
    if (st->ncb > 0) { /* record k−1 is complete */
        eo_iter_info info = {.iteration = st->kcur, .g = st->gcur, .grad_norm = st->gncur,
                             .decrement = dec, .alpha = alpha_pr, .ls_evals = ls_trials,
                             .shift = regularization_size,
                             .inverted = eo_external_inverted(sc, st->xcur), .reason = 0,
                             .x = st->xcur};
        if (eo_solver_report(sc, st->t0, &info)) {
            st->reason = EO_DIVERGED_EXTERNAL; /* x out = x_{k−1}, no further record */
            st->user_stop = 1;
            return FALSE;
        }
        st->kcur++;
    }
    st->ncb++;
    double s2 = 0;
    for (int i = 0; i < n; i++) {
        double s = st->xg[i] - st->xcur[i];
        s2 += s * s;
    }
    double g_prev = st->gcur;
    memcpy(st->xcur, st->xg, sizeof(double) * (size_t)n);
    memcpy(st->gradcur, st->gradg, sizeof(double) * (size_t)n);
    st->gcur = g;
    st->gncur = gn;
    st->dec = dec;
    int reason = 0;
    if (!isnan(gn)) {
        eo_stop_info si = {.iteration = st->kcur, .g = g, .g_prev = st->kcur ? g_prev : NAN,
                           .grad_norm = gn, .grad_norm0 = st->gn0, .decrement = dec,
                           .step_norm = st->kcur ? sqrt(s2) : NAN, .x_norm = eo_norm2(n, st->xcur),
                           .tol = sc->tol};
        reason = eo_solver_stop_check(sc, &si, st->xcur, st->gradcur);
    }
    if (!reason && sc->time_budget > 0 && eo_wtime() - st->t0 > sc->time_budget)
        reason = EO_DIVERGED_TIME_BUDGET;
    if (reason) {
        st->reason = reason;
        return FALSE;
    }
    return TRUE;
}

/* ---- driver -------------------------------------------------------------------------- */
static int ip_reason(ip_state *st, enum ApplicationReturnStatus s, int *status)
{
    *status = EO_OK;
    switch (s) {
    case Solve_Succeeded:
    case Solved_To_Acceptable_Level:
    case Feasible_Point_Found: return EO_CONVERGED_EXTERNAL;
    case Search_Direction_Becomes_Too_Small: return EO_CONVERGED_STEP;
    case Maximum_Iterations_Exceeded: return EO_DIVERGED_MAX_ITERS;
    case Maximum_CpuTime_Exceeded: return EO_DIVERGED_TIME_BUDGET;
    case Restoration_Failed: return EO_DIVERGED_LINESEARCH;
    case Error_In_Step_Computation: return EO_DIVERGED_LINSOLVE;
    case Invalid_Number_Detected: return EO_DIVERGED_NONFINITE;
    case Not_Enough_Degrees_Of_Freedom:
    case Invalid_Problem_Definition:
    case Invalid_Option:
        *status = eo_error(st->ctx, EO_ERR_INVALID,
                           "ipopt: IpoptSolve returned %d (invalid option or problem; is the "
                           "linear solver available?)",
                           (int)s);
        return EO_DIVERGED_EXTERNAL;
    case Insufficient_Memory:
        *status = eo_error(st->ctx, EO_ERR_NOMEM, "ipopt: insufficient memory");
        return EO_DIVERGED_EXTERNAL;
    default:
        eo_log(st->ctx, EO_LOG_DEBUG, "ipopt: IpoptSolve returned %d", (int)s);
        return EO_DIVERGED_EXTERNAL;
    }
}

static int ip_set_options(ip_state *st, IpoptProblem p, const eo_ipopt_params *pp,
                          const eo_solver_ctx *sc)
{
    int ok = AddIpoptStrOption(p, "sb", "yes") && AddIpoptStrOption(p, "option_file_name", "") &&
             AddIpoptIntOption(p, "print_level", pp->print_level) &&
             AddIpoptStrOption(p, "hessian_approximation", (char *)pp->hessian) &&
             AddIpoptStrOption(p, "mu_strategy", (char *)pp->mu_strategy) &&
             AddIpoptStrOption(p, "linear_solver", (char *)pp->linear_solver) &&
             AddIpoptNumOption(p, "tol", pp->tol) &&
             AddIpoptIntOption(p, "acceptable_iter", 0) &&
             AddIpoptIntOption(p, "max_iter", sc->max_iters) &&
             SetIntermediateCallback(p, ip_intermediate);
    return ok ? EO_OK : eo_error(st->ctx, EO_ERR_INVALID, "ipopt: an option was rejected "
                                 "(hessian %s, mu_strategy %s, linear_solver %s)",
                                 pp->hessian, pp->mu_strategy, pp->linear_solver);
}

static int ip_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                       eo_solve_result *res)
{
    ip_state *st = vst;
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    eo_ipopt_params def;
    const eo_ipopt_params *pp = ip_params(params, &def);
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    const int exact = strcmp(pp->hessian, "exact") == 0;
    IpoptProblem prob = NULL;
    int rc = EO_OK, reason = 0;

    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    st->sc = sc;
    st->t0 = eo_wtime();
    st->proj = sc->hessfix ? sc->hessfix->elem_proj : EO_PROJ_NONE;
    st->H = NULL;
    st->colptr = st->rowind = NULL;
    st->nnz = 0;
    st->kcur = st->ncb = st->reason = st->status = st->user_stop = st->mismatch = 0;
    st->gcur = st->gncur = st->dec = NAN;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "ipopt: set up for n = %d, objective has n = %d",
                      st->n, n);
        goto done;
    }
    /* record 0: the start point, evaluated here so a bad or optimal start needs no Ipopt */
    memcpy(st->xcur, x, sizeof(double) * (size_t)n);
    rc = eo_objective_gradient(obj, x, &st->gcur, st->gradcur);
    if (rc < 0) goto done;
    st->gncur = st->gn0 = isfinite(st->gcur) ? eo_norm2(n, st->gradcur) : NAN;
    st->glast = NAN;
    if (!isfinite(st->gcur) || !isfinite(st->gncur)) {
        reason = EO_DIVERGED_NONFINITE;
    } else {
        eo_stop_info si = {.iteration = 0, .g = st->gcur, .g_prev = NAN, .grad_norm = st->gncur,
                           .grad_norm0 = st->gn0, .decrement = NAN, .step_norm = NAN,
                           .x_norm = eo_norm2(n, x), .tol = sc->tol};
        reason = eo_solver_stop_check(sc, &si, x, st->gradcur);
        if (!reason && sc->max_iters <= 0) reason = EO_DIVERGED_MAX_ITERS;
    }
    if (!reason) {
        if (exact) { /* the structure Ipopt is given: the pattern at x₀ */
            eo_csc *H = NULL;
            rc = eo_objective_hessian(obj, x, st->proj, &H);
            if (rc < 0) goto done;
            if (!H || H->n != n) {
                rc = eo_error(sc->ctx, EO_ERR_INVALID, "ipopt: objective Hessian missing or not %d x %d",
                              n, n);
                goto done;
            }
            st->H = H;
            st->colptr = H->colptr;
            st->rowind = H->rowind;
            st->nnz = H->nnz;
        }
        prob = CreateIpoptProblem(n, st->xl, st->xu, 0, NULL, NULL, 0, st->nnz, 0, ip_eval_f,
                                  ip_eval_g, ip_eval_grad_f, ip_eval_jac_g, ip_eval_h);
        if (!prob) {
            rc = eo_error(sc->ctx, EO_ERR_INTERNAL, "ipopt: CreateIpoptProblem failed (n = %d)", n);
            goto done;
        }
        rc = ip_set_options(st, prob, pp, sc);
        if (rc < 0) goto done;
        Number fval = NAN;
        enum ApplicationReturnStatus s =
            IpoptSolve(prob, x, NULL, &fval, NULL, NULL, NULL, st);
        if (st->status < 0) {
            rc = st->status;
            goto done;
        }
        if (st->mismatch)
            eo_log(sc->ctx, EO_LOG_DEBUG,
                   "ipopt: %d iterations whose g differs from the last gradient point's", st->mismatch);
        if (st->reason) reason = st->reason;
        else {
            reason = ip_reason(st, s, &rc);
            if (rc < 0) goto done;
        }
    }
    if (!st->user_stop) {
        eo_iter_info info = {.iteration = st->kcur, .g = st->gcur, .grad_norm = st->gncur,
                             .decrement = NAN, .alpha = NAN, .ls_evals = 0, .shift = 0,
                             .inverted = eo_external_inverted(sc, st->xcur), .reason = reason,
                             .x = st->xcur};
        eo_solver_report(sc, st->t0, &info);
    }
    memcpy(x, st->xcur, sizeof(double) * (size_t)n);
done:
    if (prob) FreeIpoptProblem(prob);
    res->reason = reason;
    res->iterations = st->kcur;
    res->g = st->gcur;
    res->grad_norm = st->gncur;
    res->decrement = st->dec;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, st->t0, rc);
    st->sc = NULL;
    st->H = NULL;
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_ipopt = {
    .info = {.name = "ipopt",
             .summary = "Ipopt interior-point Newton (exact projected or limited-memory Hessian)",
             .params = ip_desc,
             .params_size = sizeof(eo_ipopt_params)},
    .state_size = sizeof(ip_state),
    .needs_ops = EO_OBJ_NEEDS_WHOLE,
    .needs_linear = 0,
    .needs_hessian = 1,
    .setup = ip_setup,
    .minimize = ip_minimize,
    .destroy = ip_destroy,
};

/* ---- constrained minimization (ipopt.h) ----------------------------------------------
 * min g(x) s.t. lower ≤ c(x) ≤ upper through Ipopt's full NLP interface. Ipopt's own
 * termination decides (tol, max_iter); the Lagrangian Hessian σ∇²g + Σλᵢ∇²cᵢ is a dense
 * lower triangle: the objective's upper CSC (row i ≤ col j) goes to lower (j, i), the
 * constraint callback's dense n×n lower triangle is added. Workspace is allocated once
 * per call, before Ipopt starts; the callbacks allocate nothing. */
#include "elastopt/ipopt.h"

typedef struct ipc_state {
    eo_ctx *ctx;
    eo_objective *obj;
    const eo_constraints *con;
    int n, m, status, iters;
    double *J;   /* m×n */
    double *Hc;  /* n×n */
} ipc_state;

void eo_ipopt_constrained_opts_default(eo_ipopt_constrained_opts *o)
{
    o->tol = 1e-10;
    o->max_iter = 200;
    o->print_level = 0;
}

static Bool ipc_f(Index n, Number *x, Bool new_x, Number *f, UserDataPtr u)
{
    ipc_state *st = u;
    (void)n, (void)new_x;
    int rc = eo_objective_value(st->obj, x, f);
    if (rc < 0) st->status = rc;
    return rc >= 0 && isfinite(*f) ? TRUE : FALSE;
}

static Bool ipc_grad(Index n, Number *x, Bool new_x, Number *gr, UserDataPtr u)
{
    ipc_state *st = u;
    (void)n, (void)new_x;
    double g;
    int rc = eo_objective_gradient(st->obj, x, &g, gr);
    if (rc < 0) st->status = rc;
    return rc >= 0 && isfinite(g) ? TRUE : FALSE;
}

static Bool ipc_g(Index n, Number *x, Bool new_x, Index m, Number *c, UserDataPtr u)
{
    ipc_state *st = u;
    (void)n, (void)new_x, (void)m;
    int rc = st->con->value(st->con->data, x, c);
    if (rc < 0) st->status = rc;
    return rc >= 0 ? TRUE : FALSE;
}

static Bool ipc_jac(Index n, Number *x, Bool new_x, Index m, Index nele, Index *iRow, Index *jCol, Number *values,
                    UserDataPtr u)
{
    ipc_state *st = u;
    (void)new_x, (void)nele;
    if (!values) {
        for (Index i = 0, q = 0; i < m; i++)
            for (Index j = 0; j < n; j++, q++) iRow[q] = i, jCol[q] = j;
        return TRUE;
    }
    int rc = st->con->jacobian(st->con->data, x, values);
    if (rc < 0) st->status = rc;
    return rc >= 0 ? TRUE : FALSE;
}

static Bool ipc_h(Index n, Number *x, Bool new_x, Number sigma, Index m, Number *lambda, Bool new_lambda, Index nele,
                  Index *iRow, Index *jCol, Number *values, UserDataPtr u)
{
    ipc_state *st = u;
    (void)new_x, (void)m, (void)new_lambda, (void)nele;
    if (!values) {
        for (Index i = 0, q = 0; i < n; i++)
            for (Index j = 0; j <= i; j++, q++) iRow[q] = i, jCol[q] = j;
        return TRUE;
    }
    for (Index q = 0; q < n * (n + 1) / 2; q++) values[q] = 0;
    eo_csc *H = NULL;
    int rc = eo_objective_hessian(st->obj, x, EO_PROJ_NONE, &H);
    if (rc < 0 || !H || H->n != n) {
        st->status = rc < 0 ? rc : eo_error(st->ctx, EO_ERR_INVALID, "ipopt: objective Hessian missing or not n x n");
        return FALSE;
    }
    for (Index j = 0; j < n; j++)
        for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++) {
            int i = H->rowind[q]; /* i ≤ j: lower entry (j, i) */
            values[j * (j + 1) / 2 + i] += sigma * H->val[q];
        }
    if (st->con->hessian && st->m > 0) {
        if ((rc = st->con->hessian(st->con->data, x, lambda, st->Hc)) < 0) {
            st->status = rc;
            return FALSE;
        }
        for (Index i = 0; i < n; i++)
            for (Index j = 0; j <= i; j++) values[i * (i + 1) / 2 + j] += st->Hc[(size_t)i * n + j];
    }
    for (Index q = 0; q < n * (n + 1) / 2; q++)
        if (!isfinite(values[q])) return FALSE;
    return TRUE;
}

static Bool ipc_iter(Index alg_mod, Index iter_count, Number obj_value, Number inf_pr, Number inf_du, Number mu,
                     Number d_norm, Number regularization_size, Number alpha_du, Number alpha_pr, Index ls_trials,
                     UserDataPtr u)
{
    ipc_state *st = u;
    (void)alg_mod, (void)obj_value, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm, (void)regularization_size;
    (void)alpha_du, (void)alpha_pr, (void)ls_trials;
    st->iters = iter_count;
    return TRUE;
}

int eo_ipopt_minimize_constrained(eo_ctx *ctx, eo_objective *obj, const eo_constraints *con,
                                  const eo_ipopt_constrained_opts *opts, double *x, double *lambda,
                                  eo_solve_result *res)
{
    eo_ipopt_constrained_opts def;
    if (!opts) {
        eo_ipopt_constrained_opts_default(&def);
        opts = &def;
    }
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    const int n = obj->n, m = con ? con->m : 0;
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    const double t0 = eo_wtime();
    if (!con || m < 0 || n < 1 || (m > 0 && (!con->value || !con->jacobian || !con->lower || !con->upper)))
        return eo_error(ctx, EO_ERR_INVALID, "ipopt: constrained problem needs n >= 1, m >= 0 and the value and "
                        "jacobian callbacks with bounds (n = %d, m = %d)", n, m);
    if ((double)n * n > 1e8 || (double)m * n > 1e8)
        return eo_error(ctx, EO_ERR_INVALID, "ipopt: constrained path is dense; n = %d, m = %d is too large", n, m);
    ipc_state st = {.ctx = ctx, .obj = obj, .con = con, .n = n, .m = m};
    size_t nw = 2 * (size_t)n + (size_t)n * n + (size_t)(m ? m : 1) * n + 2 * (size_t)(m ? m : 1);
    double *w = eo_calloc(ctx, nw, sizeof(double));
    if (!w) return eo_error(ctx, EO_ERR_NOMEM, "ipopt: out of memory (n = %d, m = %d)", n, m);
    double *xl = w, *xu = w + n, *gl = w + 2 * n + (size_t)n * n + (size_t)(m ? m : 1) * n, *gu = gl + (m ? m : 1);
    st.Hc = w + 2 * n;
    st.J = st.Hc + (size_t)n * n;
    for (int i = 0; i < n; i++) xl[i] = -1e19, xu[i] = 1e19;
    for (int i = 0; i < m; i++) gl[i] = con->lower[i], gu[i] = con->upper[i];
    IpoptProblem prob = CreateIpoptProblem(n, xl, xu, m, gl, gu, m * n, n * (n + 1) / 2, 0, ipc_f, ipc_g, ipc_grad,
                                           ipc_jac, ipc_h);
    int rc = EO_OK, reason = EO_DIVERGED_EXTERNAL;
    if (!prob) {
        rc = eo_error(ctx, EO_ERR_INTERNAL, "ipopt: CreateIpoptProblem failed (n = %d, m = %d)", n, m);
        goto done;
    }
    if (!(AddIpoptStrOption(prob, "sb", "yes") && AddIpoptStrOption(prob, "option_file_name", "") &&
          AddIpoptIntOption(prob, "print_level", opts->print_level) && AddIpoptNumOption(prob, "tol", opts->tol) &&
          AddIpoptIntOption(prob, "max_iter", opts->max_iter) && SetIntermediateCallback(prob, ipc_iter))) {
        rc = eo_error(ctx, EO_ERR_INVALID, "ipopt: an option was rejected (tol %g, max_iter %d)", opts->tol,
                      opts->max_iter);
        goto done;
    }
    Number fval = NAN;
    enum ApplicationReturnStatus s = IpoptSolve(prob, x, NULL, &fval, lambda, NULL, NULL, &st);
    if (st.status < 0) {
        rc = st.status;
        goto done;
    }
    ip_state tmp = {.ctx = ctx};
    reason = ip_reason(&tmp, s, &rc);
    if (rc < 0) goto done;
    res->iterations = st.iters;
    double *grad = w; /* xl is no longer needed */
    rc = eo_objective_gradient(obj, x, &res->g, grad);
    if (rc >= 0) res->grad_norm = eo_norm2(n, grad);
done:
    if (prob) FreeIpoptProblem(prob);
    eo_free(ctx, w);
    res->reason = reason;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}
