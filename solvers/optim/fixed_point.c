/* Fixed-point iteration of the implicit step (registry key "fixed_point"), notes 001
 * §2.5 eq. 28: y⁽ᵏ⁺¹⁾ = yₙ + h f(tₙ₊₁, y⁽ᵏ⁾), for the step objective
 * g(x) = ½‖x − x̃‖²_M + w E(x) (backward Euler: x̃ = xₙ + h vₙ, w = h²):
 *
 *     x⁽ᵏ⁺¹⁾ = x̃ − w M⁻¹∇E(x⁽ᵏ⁾) = x⁽ᵏ⁾ − M⁻¹∇g(x⁽ᵏ⁾),
 *
 * i.e. the position form of eq. 28 (its velocity half, v = (x − xₙ)/h, is eliminated;
 * two sweeps of eq. 28 on y = (x, v) are one sweep here). M is the objective's mass
 * matrix (objective op `inertia`), factored once per pattern with solver.linear; the
 * update needs one gradient and one solve with M per iteration, no Hessian.
 * The same update applies to every integrator with an inertia term (Newmark: w = h²/4
 * and the linear term inside ∇g); the static integrator has no M: EO_ERR_UNSUPPORTED.
 *
 * Initialization (`init`, the notes' two choices): "previous" x⁽⁰⁾ = xₙ; "predictor"
 * x⁽⁰⁾ = x̃ = xₙ + h vₙ, the position of the explicit Euler predictor yₙ + h f(tₙ, yₙ)
 * (for Newmark x̃ is its own predictor); "guess": the x handed in (the step engine's
 * starting guess).
 *
 * Convergence: the map Φ(x) = x̃ − w M⁻¹∇E(x) has Jacobian −w M⁻¹K, so it contracts
 * iff ρ(w M⁻¹K) < 1 — for a spring of stiffness k and mass m under backward Euler
 * iff h²k/m < 1, i.e. h < 1/ω. The ratio is measured from successive updates
 * Δₖ = x⁽ᵏ⁺¹⁾ − x⁽ᵏ⁾ in the M-norm, ρ = (‖Δₖ‖_M/‖Δₖ₋ₘ‖_M)^(1/m) with m = `window`
 * (‖Δₖ‖_M = ‖Δₖ₋₁‖_M·ρ exactly for a linear force dominated by one mode); once m + 1
 * updates are known and ρ ≥ 1 the run stops with EO_DIVERGED_NOT_CONTRACTING (the
 * iterate of the smallest update is returned) instead of running to max_iters.
 *
 * Stopping: the stopping rule sees the gradient at each iterate and, as the decrement,
 * ½‖Δₖ‖²_M = ½∇gᵀM⁻¹∇g (the decrease the quadratic model with Hessian M predicts; it
 * estimates g − g* only when w M⁻¹K is small: the error after the step is at most
 * ρ/(1 − ρ)·‖Δₖ‖). g need not decrease monotonically; no line search is used. */
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "external.h" /* eo_external_inverted */

/// Fixed-point iteration of the implicit step (config `solver.fixed_point.*`).
typedef struct eo_fixed_point_params {
    char init[16];       ///< first iterate: "previous" (xₙ), "predictor" (x̃ = xₙ + h vₙ, the
                         ///< explicit Euler position) or "guess" (the x passed in) (previous)
    int window;          ///< contraction ratio ρ = (‖Δₖ‖/‖Δₖ₋ₘ‖)^(1/m) over m = window
                         ///< updates; ρ ≥ 1 → EO_DIVERGED_NOT_CONTRACTING (default 3)
} eo_fixed_point_params;

/* One update larger than this many times the previous one ends the iteration at once
 * as not contracting (before the iterates overflow), without waiting for the window. */
#define EO_FIXED_POINT_BLOWUP 100.0

typedef struct fp_state {
    int n;
    double *d, *grad, *best, *hist; /* n, n, n, window + 1 norms */
    int window;
    const eo_csc *M;               /* factored matrix (identity of the objective's M) */
    unsigned long version;
    const eo_linsolve *ls;
    int factored;
    double rho;                    /* last measured contraction ratio (NAN before m + 1 updates) */
} fp_state;

static const char *const init_choices[] = {"previous", "predictor", "guess", NULL};

static const eo_param_desc fp_desc[] = {
    {.key = "init", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_fixed_point_params, init),
     .size = sizeof(((eo_fixed_point_params *)0)->init), .def.s = "previous", .choices = init_choices,
     .help = "first iterate: previous (x_n), predictor (x_n + h v_n, explicit Euler) or guess (the given x)"},
    {.key = "window", .kind = EO_PARAM_INT, .offset = offsetof(eo_fixed_point_params, window), .def.i = 3,
     .min = 1, .range = EO_RANGE_MIN,
     .help = "updates over which the contraction ratio is measured; ratio >= 1 -> diverged_not_contracting"},
    {0},
};

static void fp_destroy(void *vst, eo_ctx *ctx)
{
    fp_state *st = vst;
    eo_free(ctx, st->d);
    st->d = NULL;
}

static int fp_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    fp_state *st = vst;
    eo_fixed_point_params def;
    if (!params) {
        eo_params_default(fp_desc, &def);
        params = &def;
    }
    const eo_fixed_point_params *pp = params;
    fp_destroy(st, ctx);
    memset(st, 0, sizeof *st);
    size_t m = (size_t)(n > 0 ? n : 1);
    st->n = n;
    st->window = pp->window;
    st->d = eo_calloc(ctx, 3 * m + (size_t)pp->window + 1, sizeof(double));
    if (!st->d) return eo_error(ctx, EO_ERR_NOMEM, "fixed_point: out of memory (n = %d)", n);
    st->grad = st->d + m;
    st->best = st->d + 2 * m;
    st->hist = st->d + 3 * m;
    return EO_OK;
}

/* Factor M once per (matrix, version, linear solver). Returns EO_OK, a negative status,
 * or sets *reason = EO_DIVERGED_LINSOLVE when M is not positive definite. */
static int factor_mass(fp_state *st, const eo_solver_ctx *sc, const eo_objective_inertia *in, int *reason,
                       eo_solve_result *res)
{
    if (st->factored && st->M == in->M && st->version == in->version && st->ls == sc->linear) return EO_OK;
    st->factored = 0;
    int rc = eo_linsolve_analyze(sc->linear, in->M);
    if (rc < 0) return rc;
    rc = eo_linsolve_factor(sc->linear, in->M);
    res->n_factor++;
    if (rc < 0) return rc;
    if (rc > 0) {
        *reason = EO_DIVERGED_LINSOLVE;
        res->status = rc;
        return EO_OK;
    }
    st->M = in->M;
    st->version = in->version;
    st->ls = sc->linear;
    st->factored = 1;
    return EO_OK;
}

static int fp_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    fp_state *st = vst;
    eo_fixed_point_params def;
    if (!params) {
        eo_params_default(fp_desc, &def);
        params = &def;
    }
    const eo_fixed_point_params *pp = params;
    eo_objective *obj = sc->obj;
    const int n = obj->n, m = st->window;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    int rc = EO_OK, reason = 0, k = 0;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, dmin = INFINITY;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    eo_objective_inertia in;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "fixed_point set up for n = %d, objective has n = %d", st->n, n);
        goto done;
    }
    if (!sc->linear) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "fixed_point: no linear solver for the mass matrix");
        goto done;
    }
    if ((rc = eo_objective_inertia_get(obj, &in)) < 0) {
        if (rc == EO_ERR_UNSUPPORTED)
            rc = eo_error(sc->ctx, EO_ERR_UNSUPPORTED,
                          "fixed_point needs an objective with a mass matrix (an implicit integrator with inertia)");
        goto done;
    }
    if ((rc = factor_mass(st, sc, &in, &reason, res)) < 0) goto done;
    if (!strcmp(pp->init, "previous")) memcpy(x, in.x_prev, (size_t)n * sizeof(double));
    else if (!strcmp(pp->init, "predictor")) memcpy(x, in.x_pred, (size_t)n * sizeof(double));
    memcpy(st->best, x, (size_t)n * sizeof(double));
    st->rho = NAN;
    for (k = 0;; k++) {
        if ((rc = eo_objective_gradient(obj, x, &g, st->grad)) < 0) goto done;
        gn = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
        if (k == 0) gn0 = gn;
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .inverted = eo_external_inverted(sc, x), .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .step_norm = step_norm, .x_norm = eo_norm2(n, x), .tol = sc->tol};
        double dn = NAN;
        if (!reason && (!isfinite(g) || !isfinite(gn))) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, st->grad);
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason) { /* Δ = −M⁻¹∇g */
            for (int i = 0; i < n; i++) st->grad[i] = -st->grad[i];
            rc = eo_linsolve_solve(sc->linear, st->grad, st->d);
            if (rc < 0) goto done;
            if (rc > 0) {
                res->status = rc;
                reason = EO_DIVERGED_LINSOLVE;
            }
        }
        if (!reason) {
            double d2 = eo_dot(n, st->grad, st->d); /* ΔᵀMΔ = ∇gᵀM⁻¹∇g */
            dn = sqrt(d2 > 0 ? d2 : 0);
            info.decrement = 0.5 * d2;
            if (!isfinite(dn)) reason = EO_DIVERGED_NONFINITE;
            else if (sc->stop->needs_direction) {
                si.decrement = info.decrement;
                reason = eo_solver_stop_check(sc, &si, x, NULL); /* st->grad holds −∇g now */
            }
        }
        if (!reason) { /* contraction ratio over the last m updates */
            if (k <= m) st->hist[k] = dn;
            else {
                memmove(st->hist, st->hist + 1, (size_t)m * sizeof(double));
                st->hist[m] = dn;
            }
            if (dn < dmin) { /* the iterate with the smallest update so far */
                dmin = dn;
                memcpy(st->best, x, (size_t)n * sizeof(double));
            }
            const double dprev = k == 0 ? NAN : st->hist[k <= m ? k - 1 : m - 1];
            if (dprev > 0 && dn > EO_FIXED_POINT_BLOWUP * dprev) { /* one update grew by orders */
                st->rho = dn / dprev;
                reason = EO_DIVERGED_NOT_CONTRACTING;
                eo_log(sc->ctx, EO_LOG_INFO, "fixed_point: update grew %.3g-fold in one iteration", st->rho);
            } else if (k >= m && st->hist[0] > 0) {
                double rho = pow(st->hist[m] / st->hist[0], 1.0 / m);
                st->rho = rho;
                if (!(rho < 1)) {
                    reason = EO_DIVERGED_NOT_CONTRACTING;
                    eo_log(sc->ctx, EO_LOG_INFO, "fixed_point: measured contraction ratio %.6g >= 1 over %d updates", rho, m);
                }
            }
        }
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            info.reason = reason;
            res->decrement = info.decrement;
            eo_solver_report(sc, t0, &info);
            if (reason == EO_DIVERGED_NOT_CONTRACTING || reason == EO_DIVERGED_NONFINITE) {
                memcpy(x, st->best, (size_t)n * sizeof(double));
                rc = eo_objective_gradient(obj, x, &g, st->grad);
                if (rc < 0) goto done;
                gn = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
            }
            break;
        }
        info.alpha = 1;
        if (eo_solver_report(sc, t0, &info)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        for (int i = 0; i < n; i++) x[i] += st->d[i];
        step_norm = eo_norm2(n, st->d);
        g_prev = g;
        res->iterations++;
    }
done:
    res->reason = reason;
    res->g = g;
    res->grad_norm = gn;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_fixed_point = {
    .info = {.name = "fixed_point",
             .summary = "fixed-point iteration x <- x - M^-1 grad g (001 eq. 28), contraction measured",
             .params = fp_desc,
             .params_size = sizeof(eo_fixed_point_params)},
    .state_size = sizeof(fp_state),
    .needs_ops = EO_OBJ_NEEDS_INERTIA,
    .needs_linear = 1,
    .needs_hessian = 0,
    .setup = fp_setup,
    .minimize = fp_minimize,
    .destroy = fp_destroy,
};
