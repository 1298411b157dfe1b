/* Projective dynamics, the local/global solver (registry key "pd_local_global").
 *
 * Energy      PD minimizes its own energy (Bouaziz, Martin, Liu, Kavan & Pauly,
 *             "Projective Dynamics: Fusing Constraint Projections for Fast Simulation",
 *             SIGGRAPH 2014, eq. 10–13): the step objective
 *                 g(x) = ½‖x − y‖²_M + w·[ Σᵢ (wᵢ/2)‖Gᵢx − pᵢ(x)‖² − fᵀx ],
 *             pᵢ(x) = proj_Cᵢ(Gᵢx) the closest point of constraint set Cᵢ, when every
 *             elastic term is a PD constraint energy: tets of the materials pd_arap
 *             (C = SO(3), wᵢ = 2μVᵢ), pd_strain_limit (singular values in [pd_min,
 *             pd_max], 2μVᵢ), pd_volume (SO(3) with 2μVᵢ plus det F ∈ [pd_min, pd_max]
 *             with 3λVᵢ) and springs (‖x_a − x_b‖ = L, wᵢ = k: the fast mass-springs of
 *             Liu, Bouaziz & Kavan, "Fast Simulation of Mass-Spring Systems", SIGGRAPH
 *             Asia 2013). Gravity and Newmark's linear term are the linear −fᵀx.
 * Global      L = M + w·Σᵢ wᵢ GᵢᵀGᵢ, the objective's constant_hessian (problems/
 *             pd_matrix.c; each PD material gives its wᵢ through op pd_weight, springs
 *             the isotropic block k[[1,−1],[−1,1]] ⊗ I₃), factored ONCE with
 *             solver.linear by eo_pd_factor (pd_factor.h, shared with
 *             projective_dynamics, lbfgs h0 = pd, ncg precond = pd) and reused by every
 *             iteration and every later step while the objective, the matrix and its
 *             version are unchanged (a release makes a new pattern: one new
 *             factorization; solvers/linsys/updown.c has the rank update/downdate of
 *             such a factor). An objective without the op (not a step problem: tests'
 *             analytic problems, Poisson) gets its Hessian at the first iterate,
 *             projected by the Hessian fix, factored once per minimization.
 * Iteration   local step: pᵢ = proj(Gᵢx) for every constraint (inside the objective's
 *             gradient: P = wᵢ(F − proj(F)) per tet, k(‖d‖ − L)d/‖d‖ per spring);
 *             global step: x⁺ = L⁻¹ b(x), b = M y + w(Σ wᵢGᵢᵀpᵢ + f). Because
 *             ∇g(x) = L x − b(x) (envelope theorem), this is computed in correction form
 *                 d = −L⁻¹∇g(x),   G(x) = x + d = L⁻¹ b(x)
 *             (one solve with the prefactored L per iteration, no line search). It is a
 *             block coordinate descent on (x, p), so g(G(x)) ≤ g(x) for every
 *             PD-expressible objective (tests/test_pd_local_global.c checks it). An
 *             objective that is not (collision penalties, a classical material) still
 *             runs: where the plain iterate raises g beyond rounding (1e-12|g|), the
 *             configured line search along d takes over for that iteration.
 * Anderson    anderson = true (Peng, Deng, Zhang, Geng, Qin & Liu, "Anderson
 *             Acceleration for Geometry Optimization and Physics Simulation", SIGGRAPH
 *             2018, Alg. 2): the local/global map G is a fixed-point iteration with
 *             residual f(x) = G(x) − x = d. With the last m = window differences
 *             ΔF = [f_{j+1} − f_j], ΔG = [G(x_{j+1}) − G(x_j)],
 *                 θ = argmin ‖f_k − ΔF θ‖₂  (m×m normal equations, Cholesky),
 *                 x_AA = G(x_k) − ΔG θ          (mixing β = 1, the paper's choice).
 *             Safeguard: x_AA is accepted only if g(x_AA) < g(x_k); otherwise the
 *             plain iterate G(x_k) is taken (one more evaluation) and the history is
 *             cleared, which keeps g monotone and the method globally convergent.
 * Chebyshev   chebyshev = true (Wang, "A Chebyshev Semi-Iterative Approach for
 *             Accelerating Projective and Position-based Dynamics", ACM TOG 34(6), 2015,
 *             with the direct solver for the global step): after S = delay plain
 *             iterations, x⁺ = ω(γ(G(x) − x) + x − x₋₁) + x₋₁ with ω_{S+1} = 2/(2 − ρ²),
 *             ω_{k+1} = 4/(4 − ρ²ω_k) (chebyshev.h); γ = gamma (1: none). ρ = rho, Wang's
 *             offline estimate, or rho = 0: measured online from the shrinking of the
 *             last plain corrections of the delay (chebyshev.h; Wang measures it offline
 *             from the plain iteration's error). Restart: an accelerated iterate that
 *             raises g (beyond 1e-12|g|; below that, raises ‖∇g‖: eo_cheb_accept) is
 *             replaced by the plain one, x + γ(G(x) − x),
 *             and the acceleration starts again after S plain iterations (ρ measured
 *             again when automatic); counted in n_fallback. The iteration record's α is ω
 *             for an accelerated iterate. Not combined with anderson (EO_ERR_INVALID).
 * Stopping    the configured rule at every iterate: gradient (‖∇g‖ relative),
 *             newton_decrement with λ²/2 = ∇gᵀL⁻¹∇g/2 (an estimate of g − g* only as
 *             good as L is of ∇²g), or relative_decrement (the default: λ_k ≤ tol·λ₀,
 *             with λ₀ of the first iteration and the previous λ for its plateau test,
 *             passed in eo_stop_info as the descent loop does).
 * Memory      workspace (7 + 2m vectors of n, m² + 2m scalars) in setup, the copy of L
 *             once per new matrix; nothing inside the iterations. */
#include <stddef.h>
#include <string.h>

#include "chebyshev.h"
#include "descent.h"
#include "pd_factor.h"
#include "external.h" /* eo_external_inverted */

/// Projective dynamics, local/global solver (config `solver.pd_local_global.*`; Bouaziz
/// et al. 2014). Minimizes the step objective of PD constraint energies (materials
/// pd_arap, pd_strain_limit, pd_volume; springs) with the objective's constant matrix.
typedef struct eo_pd_local_global_params {
    int anderson;        ///< Anderson acceleration of the local/global map, with the energy
                         ///< safeguard of Peng et al. 2018 (default false)
    int window;          ///< Anderson window m, differences kept (default 5, range [1, 100])
    /// Chebyshev semi-iterative acceleration of the local/global map (Wang 2015; not with
    /// anderson): x⁺ = ω(γ(G(x) − x) + x − x₋₁) + x₋₁ after `delay` plain iterations,
    /// restarted when g rises (default false)
    int chebyshev;
    double rho;          ///< its spectral radius estimate, [0, 1); 0 = measured from the
                         ///< plain iterations of the delay (default 0)
    int delay;           ///< S, plain iterations before the acceleration (default 10)
    double gamma;        ///< under-relaxation γ, (0, 1] (default 1)
} eo_pd_local_global_params;

typedef struct pdlg_state {
    int n, m;
    double *buf;
    double *grad, *d, *xg, *xt, *gt, *fprev, *gprev, *work;
    double *dF, *dG;          /* m columns of n each (ring) */
    double *gram, *rhs, *chol, *theta; /* m×m, m, m×m, m */
    int count, head, have_prev;
    eo_pd_factor pf;          /* L factored once (pd_factor.h, shared with projective_dynamics) */
    eo_ctx *ctx;
} pdlg_state;

static const eo_param_desc pdlg_desc[] = {
    {.key = "anderson", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_pd_local_global_params, anderson),
     .def.i = 0, .help = "Anderson acceleration of the local/global map with the energy safeguard (Peng 2018)"},
    {.key = "window", .kind = EO_PARAM_INT, .offset = offsetof(eo_pd_local_global_params, window), .def.i = 5,
     .min = 1, .max = 100, .range = EO_RANGE_CLOSED, .help = "Anderson window m (differences kept)"},
    {.key = "chebyshev", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_pd_local_global_params, chebyshev),
     .def.i = 0, .help = "Chebyshev semi-iterative acceleration (Wang 2015), restarted when g rises; not with anderson"},
    {.key = "rho", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_pd_local_global_params, rho), .def.d = 0, .min = 0,
     .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "Chebyshev spectral radius estimate, [0, 1); 0 = measured from the plain iterations of the delay"},
    {.key = "delay", .kind = EO_PARAM_INT, .offset = offsetof(eo_pd_local_global_params, delay), .def.i = 10,
     .min = 1, .max = 1000, .range = EO_RANGE_CLOSED, .help = "Chebyshev delay S: plain iterations before it starts"},
    {.key = "gamma", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_pd_local_global_params, gamma), .def.d = 1,
     .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX,
     .help = "Chebyshev under-relaxation gamma, (0, 1]"},
    {0},
};

static void pdlg_free(pdlg_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->buf);
    st->buf = NULL;
    eo_pd_factor_deinit(ctx, &st->pf);
}

static int pdlg_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    pdlg_state *st = vst;
    eo_pd_local_global_params def;
    const eo_pd_local_global_params *pp = params;
    if (!pp) {
        eo_params_default(pdlg_desc, &def);
        pp = &def;
    }
    pdlg_free(st, ctx);
    memset(st, 0, sizeof *st);
    st->ctx = ctx;
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "pd_local_global: n = %d < 0", n);
    if (pp->anderson && pp->chebyshev)
        return eo_error(ctx, EO_ERR_INVALID, "pd_local_global: anderson and chebyshev cannot both be on");
    int rc = eo_pd_factor_init(ctx, n, "pd_local_global", &st->pf);
    if (rc < 0) return rc;
    const size_t nn = (size_t)(n > 0 ? n : 1), m = (size_t)pp->window;
    st->buf = eo_calloc(ctx, (8 + 2 * m) * nn + 2 * m * m + 2 * m, sizeof(double));
    if (!st->buf) return eo_error(ctx, EO_ERR_NOMEM, "pd_local_global: out of memory (n = %d, window %zu)", n, m);
    double *p = st->buf;
    double **vec[] = {&st->grad, &st->d, &st->xg, &st->xt, &st->gt, &st->fprev, &st->gprev, &st->work};
    for (size_t i = 0; i < sizeof vec / sizeof vec[0]; i++, p += nn) *vec[i] = p;
    st->dF = p, p += m * nn;
    st->dG = p, p += m * nn;
    st->gram = p, p += m * m;
    st->chol = p, p += m * m;
    st->rhs = p, p += m;
    st->theta = p;
    st->n = n;
    st->m = (int)m;
    return EO_OK;
}

static void pdlg_destroy(void *vst, eo_ctx *ctx) { pdlg_free(vst, ctx); }

/* Anderson: push the differences of (f, G) against the previous iterate's, then
 * θ = argmin ‖f − ΔF θ‖ and xt = xg − ΔG θ. Returns 1 if xt holds an accelerated point. */
static int anderson(pdlg_state *st, const double *f, const double *xg, double *xt)
{
    const int n = st->n, m = st->m;
    int ok = 0;
    if (st->have_prev) {
        const int j = st->head;
        double *df = st->dF + (size_t)j * n, *dg = st->dG + (size_t)j * n;
        for (int i = 0; i < n; i++) {
            df[i] = f[i] - st->fprev[i];
            dg[i] = xg[i] - st->gprev[i];
        }
        st->head = (st->head + 1) % m;
        if (st->count < m) st->count++;
        for (int q = 0; q < st->count; q++) {
            double v = eo_dot(n, df, st->dF + (size_t)q * n);
            st->gram[j * m + q] = st->gram[q * m + j] = v;
        }
        const int c = st->count;
        double tr = 0;
        for (int q = 0; q < c; q++) {
            st->rhs[q] = eo_dot(n, st->dF + (size_t)q * n, f);
            tr += st->gram[q * m + q];
        }
        /* Cholesky of the Gram matrix (+ tiny relative regularization) */
        const double reg = 1e-12 * (tr > 0 ? tr / c : 1);
        ok = tr > 0;
        for (int a = 0; a < c && ok; a++) {
            for (int b = 0; b <= a; b++) {
                double s = st->gram[a * m + b] + (a == b ? reg : 0);
                for (int k = 0; k < b; k++) s -= st->chol[a * m + k] * st->chol[b * m + k];
                if (a == b) {
                    if (!(s > 0)) {
                        ok = 0;
                        break;
                    }
                    st->chol[a * m + a] = sqrt(s);
                } else {
                    st->chol[a * m + b] = s / st->chol[b * m + b];
                }
            }
        }
        if (ok) {
            for (int a = 0; a < c; a++) { /* forward */
                double s = st->rhs[a];
                for (int k = 0; k < a; k++) s -= st->chol[a * m + k] * st->theta[k];
                st->theta[a] = s / st->chol[a * m + a];
            }
            for (int a = c - 1; a >= 0; a--) { /* backward */
                double s = st->theta[a];
                for (int k = a + 1; k < c; k++) s -= st->chol[k * m + a] * st->theta[k];
                st->theta[a] = s / st->chol[a * m + a];
            }
            for (int a = 0; a < c; a++) ok &= isfinite(st->theta[a]);
        }
        if (ok) {
            memcpy(xt, xg, (size_t)n * sizeof(double));
            for (int q = 0; q < c; q++) {
                const double th = st->theta[q], *dgq = st->dG + (size_t)q * n;
                for (int i = 0; i < n; i++) xt[i] -= th * dgq[i];
            }
        }
    }
    memcpy(st->fprev, f, (size_t)n * sizeof(double));
    memcpy(st->gprev, xg, (size_t)n * sizeof(double));
    st->have_prev = 1;
    return ok;
}

static void anderson_clear(pdlg_state *st)
{
    st->count = st->head = st->have_prev = 0;
}

/* accepted steps without a strict decrease of g (and no new smallest ‖∇g‖) before
 * EO_DIVERGED_STAGNATED: the tolerance is below the rounding level of g */
#define PDLG_STALL_LIMIT 5

static int pdlg_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                         eo_solve_result *res)
{
    pdlg_state *st = vst;
    eo_pd_local_global_params def;
    const eo_pd_local_global_params *pp = params;
    if (!pp) {
        eo_params_default(pdlg_desc, &def);
        pp = &def;
    }
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, last_dec = NAN, gn_best = INFINITY;
    double dec0 = NAN, dec_prev = NAN; /* λ₀²/2 and the previous iteration's, for relative_decrement */
    int rc = EO_OK, reason = 0, k = 0, stalled = 0;
    eo_cheb cheb;
    eo_cheb_start(&cheb, pp->rho, pp->delay);
    double *xm1 = st->fprev; /* Chebyshev's x₋₁ (fprev is Anderson's, never both) */
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (pp->anderson && pp->chebyshev) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "pd_local_global: anderson and chebyshev cannot both be on");
        goto done;
    }
    if (n != st->n || pp->window != st->m) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "pd_local_global set up for n = %d, window %d; called with %d, %d",
                      st->n, st->m, n, pp->window);
        goto done;
    }
    if (!sc->linear) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "pd_local_global needs a linear solver");
        goto done;
    }
    rc = eo_objective_gradient(obj, x, &g, st->grad);
    if (rc < 0) goto done;
    gn = gn0 = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
    rc = eo_pd_factor_prepare(&st->pf, sc, x, res);
    if (rc < 0) goto done;
    if (!st->pf.factored) reason = st->pf.fail_reason ? st->pf.fail_reason : EO_DIVERGED_LINSOLVE;
    anderson_clear(st);
    memcpy(xm1, x, (size_t)n * sizeof(double));
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .ls_evals = 0, .shift = 0, .inverted = eo_external_inverted(sc, x), .reason = 0,
                             .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .decrement0 = dec0, .decrement_prev = dec_prev,
                           .step_norm = step_norm, .x_norm = eo_norm2(n, x), .tol = sc->tol};
        if (!reason && (!isfinite(g) || !isfinite(gn))) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, st->grad);
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason) { /* global step: d = −L⁻¹∇g */
            info.shift = st->pf.shift;
            int sr = eo_pd_factor_solve(&st->pf, sc, st->grad, st->d, res);
            if (sr < 0) {
                reason = sr;
            } else {
                for (int i = 0; i < n; i++) st->d[i] = -st->d[i];
                const double dg = eo_dot(n, st->grad, st->d);
                if (!(dg < 0) || !isfinite(dg)) {
                    reason = EO_DIVERGED_NOT_DESCENT;
                } else {
                    info.decrement = last_dec = -dg / 2;
                    if (k == 0) si.decrement0 = dec0 = last_dec;
                    if (sc->stop->needs_direction) {
                        si.decrement = info.decrement;
                        reason = eo_solver_stop_check(sc, &si, x, st->grad);
                    }
                }
            }
        }
        if (!reason && stalled >= PDLG_STALL_LIMIT) reason = EO_DIVERGED_STAGNATED;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        /* the plain local/global iterate G(x) = x + d (x + γd with Chebyshev), and
         * Anderson's or Chebyshev's candidate */
        const double gam = pp->chebyshev ? pp->gamma : 1;
        for (int i = 0; i < n; i++) st->xg[i] = x[i] + gam * st->d[i];
        int accel = pp->anderson && anderson(st, st->d, st->xg, st->xt);
        double gt = NAN, alpha = 1, omega = 1;
        int nev = 0;
        if (pp->chebyshev) {
            omega = eo_cheb_next(&cheb, gam * eo_norm2(n, st->d));
            if (omega != 1) {
                for (int i = 0; i < n; i++) st->xt[i] = omega * (st->xg[i] - xm1[i]) + xm1[i];
                nev++;
                rc = eo_objective_gradient(obj, st->xt, &gt, st->gt);
                if (rc < 0) goto done;
                accel = eo_cheb_accept(g, gn, gt, eo_norm2(n, st->gt));
                if (!accel) { /* restart: the plain iterate, S plain iterations again */
                    eo_cheb_restart(&cheb);
                    res->n_fallback++;
                    omega = 1;
                } else {
                    alpha = omega;
                }
            }
        }
        if (accel && !pp->chebyshev) {
            nev++;
            rc = eo_objective_gradient(obj, st->xt, &gt, st->gt);
            if (rc < 0) goto done;
            if (!(isfinite(gt) && gt < g)) { /* safeguard: back to G(x), history cleared */
                accel = 0;
                anderson_clear(st);
                res->n_fallback++;
            }
        }
        if (!accel) {
            memcpy(st->xt, st->xg, (size_t)n * sizeof(double));
            nev++;
            rc = eo_objective_gradient(obj, st->xt, &gt, st->gt);
            if (rc < 0) goto done;
            if (!(isfinite(gt) && gt <= g + 1e-12 * fabs(g))) {
                /* not a PD energy (or non-finite): the configured line search along d */
                int ls_n = 0;
                eo_ls_extra ex = {.grad_new = st->gt, .have_grad = 0, .c2 = 0};
                rc = sc->linesearch->search(sc->linesearch_params, obj, x, st->d, g, -2 * last_dec, 1, st->xt, &gt,
                                            &alpha, &ls_n, st->work, sc->ctx, &ex);
                nev += ls_n;
                if (rc < 0) goto done;
                if (!isfinite(gt) || !(rc == EO_OK || gt < g) || !(alpha > 0)) {
                    rc = EO_OK;
                    info.ls_evals = nev;
                    reason = info.reason = EO_DIVERGED_LINESEARCH;
                    eo_solver_report(sc, t0, &info);
                    break;
                }
                rc = EO_OK;
                if (!ex.have_grad) {
                    nev++;
                    rc = eo_objective_gradient(obj, st->xt, &gt, st->gt);
                    if (rc < 0) goto done;
                }
                anderson_clear(st);
                eo_cheb_restart(&cheb);
            }
        }
        info.alpha = alpha;
        info.ls_evals = nev;
        if (gn < gn_best) gn_best = gn;
        if (eo_solver_report(sc, t0, &info)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        double s2 = 0;
        if (pp->chebyshev) memcpy(xm1, x, (size_t)n * sizeof(double));
        for (int i = 0; i < n; i++) {
            double s = st->xt[i] - x[i];
            s2 += s * s;
            x[i] = st->xt[i];
        }
        step_norm = sqrt(s2);
        double *t = st->grad;
        st->grad = st->gt;
        st->gt = t;
        g_prev = g;
        g = gt;
        gn = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
        dec_prev = last_dec;
        last_dec = NAN;
        stalled = (g < g_prev || gn < gn_best) ? 0 : stalled + 1;
    }
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    res->decrement = last_dec;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_pd_local_global = {
    .info = {.name = "pd_local_global",
             .summary = "projective dynamics local/global solver (Bouaziz 2014): per-constraint projections, "
                        "constant matrix factored once, optional Anderson acceleration (Peng 2018)",
             .params = pdlg_desc,
             .params_size = sizeof(eo_pd_local_global_params)},
    .state_size = sizeof(pdlg_state),
    .needs_ops = EO_OBJ_NEEDS_CONSTANT,
    .needs_linear = 1,
    .needs_hessian = 0,
    .setup = pdlg_setup,
    .minimize = pdlg_minimize,
    .destroy = pdlg_destroy,
};
