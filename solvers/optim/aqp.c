/* Accelerated Quadratic Proxy (registry key "aqp").
 *
 * Paper       Kovalsky, Galun & Lipman, "Accelerated Quadratic Proxy for Geometric
 *             Optimization", ACM TOG 35(4) (SIGGRAPH 2016), Algorithm 1, and the authors'
 *             code (OptimSolverAcclQuadProx.m).
 * Proxy       the paper minimizes f = ½xᵀHx + (rest) with H = L_mesh ⊗ I_d, the mesh's
 *             cotangent Laplacian, a constant SPD matrix capturing the energy's
 *             Laplacian-like part at rest, factored once. Here H is the objective's
 *             constant matrix L = M + w·Σₜ Vₜ kₜ GₜᵀGₜ (problems/pd_matrix.c): the
 *             mass plus the time-step-weighted, stiffness-scaled (λ + 2μ) tet Laplacian
 *             (GₜᵀGₜ = (BₜBₜᵀ) ⊗ I₃ is the tet's cotangent-Laplacian block times its
 *             volume), i.e. exactly the paper's proxy made dynamic by the inertia term;
 *             factored ONCE by eo_pd_factor (pd_factor.h) and reused by every iteration
 *             and step (the scalar form L₁ ⊗ I₃ as the paper's L ⊗ I_d).
 * Iteration   from x₀ (x₋₁ = x₀):
 *               y  = x_k + a (x_k − x_{k−1}),  a = θ = (1 − √(1/κ))/(1 + √(1/κ))
 *                    (the paper's constant-momentum rule; κ = solver.aqp.kappa, 100 as
 *                    in the authors' examples -> θ = 0.818; accelerate = false: a = 0,
 *                    the plain proxy iteration)
 *               p  = −L⁻¹∇g(y)                       (minimizer of the quadratic proxy)
 *               x_{k+1} = y + t p, t by the authors' backtracking from y: Armijo
 *                    g(y + tp) ≤ g(y) + c1 t ∇g(y)ᵀp with c1 = ls_c1 = 0.2, t ← t/2,
 *                    first trial min(1, 2^5.5·t_prev) (step memory). solver.linesearch
 *                    is not used: the large c1 is part of the method (with the usual
 *                    1e-4 a unit step is accepted on modes where L underestimates ∇²g
 *                    up to 2x, and the momentum then amplifies them: on the cantilever
 *                    L⁻¹∇²g reaches 1.85, and AQP with backtracking c1 = 1e-4 diverged)
 *             one gradient (at y) per iteration plus the line search's values.
 * Safeguards  (a) momentum step limit: the authors limit a by half the largest step
 *                 along x_k − x_{k−1} that keeps every element from flipping; here, where
 *                 g(y) is +∞ (a barrier material inverted at y) a is halved until g(y) is
 *                 finite (materials that are finite through inversion need no limit);
 *             (b) the line search from y is barrier-aware the same way (a trial with
 *                 g = +∞ is shrunk) instead of starting below the flip-free max step;
 *             (c) restart = true (default): when g(x_{k+1}) > g(x_k) the momentum is
 *                 dropped for the next iteration (x_{k} := x_{k+1} as its x_{k−1}; the
 *                 function-value restart of O'Donoghue & Candès 2015). The paper's
 *                 algorithm keeps the momentum; restart = false reproduces it.
 * Stopping    the iterate tested is y_k with ∇g(y_k), the only gradient AQP computes:
 *             eo_solver_stop_check at every y_k (metric gradient ratio of the default
 *             rule); on convergence x = y_k is returned. A decrement rule gets
 *             λ²/2 = ∇gᵀL⁻¹∇g/2 of the proxy direction.
 * Memory      7 vectors of n in setup; nothing inside the iterations. */
#include <float.h>
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "external.h" /* eo_external_inverted */
#include "pd_factor.h"

/// Parameters (config `solver.aqp.*`).
typedef struct eo_aqp_params {
    int accelerate;      ///< momentum step (default true); false: plain proxy iteration (θ = 0)
    double kappa;        ///< κ of θ = (1 − √(1/κ))/(1 + √(1/κ)) (default 100, θ = 0.818)
    int restart;         ///< drop the momentum after an iteration that raised g (default true)
    double ls_c1;        ///< Armijo constant of the line search (default 0.2, the authors')
} eo_aqp_params;

static const eo_param_desc aqp_desc[] = {
    {.key = "accelerate", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_aqp_params, accelerate), .def.i = 1,
     .help = "momentum y = x_k + theta (x_k - x_k-1) (false: the plain quadratic-proxy iteration)"},
    {.key = "kappa", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_aqp_params, kappa), .def.d = 100, .min = 1,
     .range = EO_RANGE_MIN_OPEN,
     .help = "condition estimate kappa of the momentum theta = (1 - sqrt(1/kappa)) / (1 + sqrt(1/kappa))"},
    {.key = "restart", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_aqp_params, restart), .def.i = 1,
     .help = "drop the momentum for one iteration when an iteration raised g (function-value restart)"},
    {.key = "ls_c1", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_aqp_params, ls_c1), .def.d = 0.2, .min = 0,
     .max = 0.5, .range = EO_RANGE_OPEN,
     .help = "Armijo constant of AQP's backtracking (the authors' 0.2: a step of 1 is taken only where the "
             "proxy does not underestimate the curvature by more than 1.6x)"},
    {0},
};

typedef struct aqp_state {
    int n;
    double *buf;
    double *xprev, *y, *gy, *p, *xt, *work, *dl; /* n each */
    eo_pd_factor pf;
} aqp_state;

static void aqp_free(aqp_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->buf);
    st->buf = NULL;
    eo_pd_factor_deinit(ctx, &st->pf);
}

static int aqp_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    aqp_state *st = vst;
    (void)params;
    aqp_free(st, ctx);
    memset(st, 0, sizeof *st);
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "aqp: n = %d < 0", n);
    int rc = eo_pd_factor_init(ctx, n, "aqp", &st->pf);
    if (rc < 0) return rc;
    const size_t nn = (size_t)(n > 0 ? n : 1);
    st->buf = eo_calloc(ctx, 7 * nn, sizeof(double));
    if (!st->buf) return eo_error(ctx, EO_ERR_NOMEM, "aqp: out of memory (n = %d)", n);
    double **v[] = {&st->xprev, &st->y, &st->gy, &st->p, &st->xt, &st->work, &st->dl};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) *v[i] = st->buf + i * nn;
    st->n = n;
    return EO_OK;
}

static void aqp_destroy(void *vst, eo_ctx *ctx) { aqp_free(vst, ctx); }

/* halvings of the momentum before giving it up for the iteration */
#define AQP_MOMENTUM_HALVINGS 30
/* the line search's first trial is min(1, this times the last accepted step) (the
 * authors' lineSearchStepSizeMemoryFactor), and its trial limit */
#define AQP_STEP_MEMORY 45.254833995939045 /* 2^5.5 */
#define AQP_LS_TRIALS 60
/* iterations in which neither g(x) fell by more than its rounding (8ε|g|) nor ‖∇g(y)‖
 * reached a new low before
 * EO_DIVERGED_STAGNATED (the tolerance is below what g's rounding lets the line search
 * resolve) */
#define AQP_STALL_LIMIT 200

static int aqp_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    aqp_state *st = vst;
    eo_aqp_params def;
    const eo_aqp_params *pp = params;
    if (!pp) {
        eo_params_default(aqp_desc, &def);
        pp = &def;
    }
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    const double q = sqrt(1 / pp->kappa), theta = pp->accelerate ? (1 - q) / (1 + q) : 0;
    double gx = NAN, gy = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, last_dec = NAN;
    double dec0 = NAN, dec_prev = NAN, t_prev = 1 / AQP_STEP_MEMORY;
    int rc = EO_OK, reason = 0, k = 0, stalled = 0;
    long restarts = 0;
    double gn_best = INFINITY;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "aqp set up for n = %d; called with %d", st->n, n);
        goto done;
    }
    if (!sc->linear) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "aqp needs a linear solver");
        goto done;
    }
    rc = eo_pd_factor_prepare(&st->pf, sc, x, res);
    if (rc < 0) goto done;
    if (!st->pf.factored) reason = st->pf.fail_reason ? st->pf.fail_reason : EO_DIVERGED_LINSOLVE;
    memcpy(st->xprev, x, (size_t)n * sizeof(double));
    for (k = 0;; k++) {
        /* the extrapolated point y and ∇g(y); a halved where g(y) = +∞ */
        double a = k > 0 ? theta : 0;
        for (int i = 0; i < n; i++) st->dl[i] = x[i] - st->xprev[i];
        for (int h = 0;; h++) {
            for (int i = 0; i < n; i++) st->y[i] = x[i] + a * st->dl[i];
            rc = eo_objective_gradient(obj, st->y, &gy, st->gy);
            if (rc < 0) goto done;
            if (isfinite(gy) || a == 0) break;
            a = h < AQP_MOMENTUM_HALVINGS ? 0.5 * a : 0;
        }
        if (k == 0) gx = gy;
        gn = isfinite(gy) ? eo_norm2(n, st->gy) : NAN;
        if (k == 0) gn0 = gn;
        eo_iter_info info = {.iteration = k, .g = gy, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .ls_evals = 0, .shift = st->pf.shift, .inverted = eo_external_inverted(sc, st->y),
                             .reason = 0, .x = st->y};
        eo_stop_info si = {.iteration = k, .g = gy, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .decrement0 = dec0, .decrement_prev = dec_prev,
                           .step_norm = step_norm, .x_norm = eo_norm2(n, st->y), .tol = sc->tol};
        if (!reason && (!isfinite(gy) || !isfinite(gn))) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, st->y, st->gy);
        if (!reason) { /* the proxy's minimizer: p = −L⁻¹∇g(y) */
            int sr = eo_pd_factor_solve(&st->pf, sc, st->gy, st->p, res);
            if (sr < 0) {
                reason = sr;
            } else {
                for (int i = 0; i < n; i++) st->p[i] = -st->p[i];
                const double dg = eo_dot(n, st->gy, st->p);
                if (!(dg < 0) || !isfinite(dg)) {
                    reason = EO_DIVERGED_NOT_DESCENT;
                } else {
                    info.decrement = last_dec = -dg / 2;
                    if (k == 0) si.decrement0 = dec0 = last_dec;
                    if (sc->stop->needs_direction) {
                        si.decrement = last_dec;
                        reason = eo_solver_stop_check(sc, &si, st->y, st->gy);
                    }
                }
            }
        }
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason && stalled >= AQP_STALL_LIMIT) reason = EO_DIVERGED_STAGNATED;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            if (isfinite(gy)) memcpy(x, st->y, (size_t)n * sizeof(double)); /* the iterate tested */
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        /* the paper's backtracking from y along p: Armijo with c1 = ls_c1, t ← t/2, first
         * trial min(1, 2^5.5 t_prev); a trial with g = +∞ (barrier) is shrunk like any */
        double gt = NAN, t = fmin(1, t_prev * AQP_STEP_MEMORY);
        int ls_n = 0, ok = 0;
        for (; ls_n < AQP_LS_TRIALS && !ok; ls_n++) {
            if (ls_n > 0) t *= 0.5;
            for (int i = 0; i < n; i++) st->xt[i] = st->y[i] + t * st->p[i];
            rc = eo_objective_value(obj, st->xt, &gt);
            if (rc < 0) goto done;
            /* strict Armijo: a rounding-level acceptance (g ≤ g(y) + 4ε|g|, as the
             * backtracking search has) let the momentum accumulate noise and stall the
             * cantilever's first step at 1.9e-7 of the motion (442 iterations; strict:
             * converged in 197) */
            ok = isfinite(gt) && gt <= gy - pp->ls_c1 * t * 2 * last_dec;
        }
        info.alpha = t;
        info.ls_evals = ls_n;
        if (!ok) {
            memcpy(x, st->y, (size_t)n * sizeof(double));
            reason = info.reason = EO_DIVERGED_LINESEARCH;
            eo_solver_report(sc, t0, &info);
            break;
        }
        t_prev = t;
        rc = EO_OK;
        if (eo_solver_report(sc, t0, &info)) {
            memcpy(x, st->y, (size_t)n * sizeof(double));
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        /* x_{k−1} := x_k, or x_{k+1} itself (no momentum next) after a rise of g */
        const int rose = pp->restart && gt > gx;
        restarts += rose;
        double s2 = 0;
        for (int i = 0; i < n; i++) {
            const double d = st->xt[i] - x[i];
            s2 += d * d;
            st->xprev[i] = rose ? st->xt[i] : x[i];
            x[i] = st->xt[i];
        }
        step_norm = sqrt(s2);
        stalled = (gt < gx - 8 * DBL_EPSILON * fabs(gx) || gn < gn_best) ? 0 : stalled + 1;
        if (gn < gn_best) gn_best = gn;
        g_prev = gy;
        gx = gt;
        dec_prev = last_dec;
        last_dec = NAN;
    }
    eo_log(sc->ctx, EO_LOG_DEBUG, "aqp: %d iterations, theta %.4g, %ld restarts", k, theta, restarts);
done:
    res->reason = reason;
    res->iterations = k;
    res->g = gy;
    res->grad_norm = gn;
    res->decrement = last_dec;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_aqp = {
    .info = {.name = "aqp",
             .summary = "Accelerated Quadratic Proxy (Kovalsky 2016): constant Laplacian-type proxy L factored "
                        "once, momentum extrapolation, line search, restart",
             .params = aqp_desc,
             .params_size = sizeof(eo_aqp_params)},
    .state_size = sizeof(aqp_state),
    .needs_linear = 1,
    .needs_hessian = 0,
    .setup = aqp_setup,
    .minimize = aqp_minimize,
    .destroy = aqp_destroy,
};
