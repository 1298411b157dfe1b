/* Newton's method with a line search (registry key "newton").
 *
 * Quadratic model at x (002 eq. 9, remainder O(‖p‖³)):
 *     g(x + p) ≈ g(x) + ∇gᵀp + ½ pᵀ H p,     H = ∇²g(x) (assembled with the Hessian fix's
 *                                                     per-element projection)
 * Direction     p = −(H + cI)⁻¹ ∇g           (002 eq. 10 with Note 4's shift c ≥ 0)
 * Decrement     λ² = ∇gᵀ(H + cI)⁻¹∇g = −∇gᵀp  (ERRATA for 002 Def. 4); the stopping rule
 *               newton_decrement stops when λ²/2 ≤ tol, λ²/2 estimating g(x) − g*.
 *               At x_{k+1}, before assembling H_{k+1}, the rule is first tested with
 *               λ̃² = ∇g_{k+1}ᵀ H̃_k⁻¹ ∇g_{k+1}, one solve with the factor of x_k's matrix
 *               (only after a full step α = 1 with an unshifted H̃_k; H̃_{k+1} − H̃_k =
 *               O(‖p_k‖), so near the solution λ̃² = λ²(1 + O(‖p_k‖))): a step that ends
 *               after k iterations assembles and factors k matrices, not k + 1. Where the
 *               estimate does not stop the run, the exact decrement of the new direction
 *               is tested as before (res.decrement_estimated tells which one stopped it).
 * Estimate gate (solver.newton.estimate_gate = s > 0): the estimate solve can only end
 *               the run, so at x_k, k ≥ 2, it is done only when the rule could pass:
 *               with d_j = λ_j²/2 the exact decrements of the last two directions, the
 *               rule is probed with decrements from the quadratic-phase prediction
 *               d_{k−1}³/d_{k−2}² (λ_k = C λ_{k−1}² with C from the last pair) divided
 *               by s up to d_{k−1} itself (no progress: the rounding-floor test of
 *               relative_decrement), geometrically spaced (gate_open); if none passes,
 *               no solve. The prediction is the
 *               optimistic one for Newton (a linear phase shrinks d by less), and s
 *               covers a faster-than-predicted step, because a skipped estimate that
 *               would have passed costs an assembly and a factorization (default s = 10:
 *               on the built-in scenes even s = 1 skipped no estimate that would have
 *               passed; with the clamp fix Newton often converges linearly, d falling
 *               10-25x per iteration on the bunny, where the prediction is optimistic
 *               and the quadratic prediction saves less: there, when the last ratio
 *               d_{k−1}/d_{k−2} is at least half the one before (not accelerating), the
 *               linear-phase prediction d_{k−1}²/d_{k−2} divided by s is used instead).
 *               At k = 1 (no pair yet) it is always tried. (The pair of the previous
 *               minimization once stood in there, saving 1 of 10 solves per bunny step:
 *               but a minimization must not depend on the ones before it, or a restarted
 *               run would not continue bit for bit; without it, 30 twist steps at 22k
 *               unknowns take the same 257 iterations and 418 solves instead of 390.)
 *               s = 0: always tried.
 * Line search   x ← x + αp, first trial α = 1 (the configured solver.linesearch); a
 *               trial where g = +∞ (inverted element of a barrier material) is rejected
 *               and the step shrunk by the line search.
 *
 * Hessian fix  the system H̃ and p come from the configured fix (sc->hessfix, its op
 *               `factor`, solver.h): which projection the Hessian is assembled with,
 *               whether H̃ = H_proj + cI is shifted, retried or replaced by −∇g is the
 *               fix's business (solvers/hessfix/); Newton supplies the matrix through the
 *               callback `assemble` and reports each accepted step to the fix's
 *               `accepted` hook (α, actual and predicted reduction) before the next
 *               direction. shift = c of H̃ and the fraction of elements projected go to
 *               the iteration record.
 *
 * Linear algebra: the Hessian pattern is fixed for an objective, so
 * eo_linsolve_analyze runs once per pattern (the H pointer and its colptr/rowind arrays
 * are remembered; a new pattern is analyzed again, inside `assemble`) and
 * eo_linsolve_factor at every factorization (by the fix). Nothing is allocated.
 * A factorization or solve error (negative status) ends the run with
 * EO_DIVERGED_LINSOLVE (status in res.status); a non-finite Hessian diagonal with
 * EO_DIVERGED_NONFINITE.
 *
 * Inexact Newton (solver.newton.forcing, forcing.c): before each direction the forcing
 * term η_k goes to the linear solver (eo_linsolve_set_rtol; direct solvers ignore it),
 * so an iterative solve stops at ‖H̃p + ∇g‖ ≤ η_k‖∇g‖. Non-positive curvature met by
 * the inner CG is counted (res.n_neg_curvature, iteration record neg_curvature) and left
 * to the Hessian fix, which never uses that direction (`none` takes the clamp-projected
 * system for that iteration, `shift` a larger shift). */
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "forcing.h"

/// Newton (config `solver.newton.*`).
///
/// Inexact Newton: with an iterative solver.linear (cg, pcg, gmres) the direction solve
/// H̃p = −∇g stops at ‖H̃p + ∇g‖ ≤ η_k‖∇g‖, η_k set by `forcing` through
/// eo_linsolve_set_rtol before each direction (direct solvers ignore it):
///   auto      ew2 while the solves are iterative and Newton converges fast (the last
///             step full, α = 1, and the last decrement at most local_ratio times the one
///             before), else η_k = eta_global; none while the solves are direct
///             (default; solvers/optim/forcing.h says why)
///   none      the linear solver's own `tol`
///   constant  η_k = eta
///   ew1       Eisenstat–Walker choice 1: η_k = |‖∇g_k‖ − ‖∇g_{k−1} + αH̃_{k−1}p_{k−1}‖| / ‖∇g_{k−1}‖,
///             safeguard η_k ≥ η_{k−1}^φ (φ = (1+√5)/2) when that is > 0.1
///   ew2       Eisenstat–Walker choice 2: η_k = ew_gamma (‖∇g_k‖/‖∇g_{k−1}‖)^ew_alpha,
///             safeguard η_k ≥ ew_gamma η_{k−1}^ew_alpha when that is > 0.1
/// η_0 = eta, then η_k ∈ [eta_min, eta_max] (Eisenstat & Walker 1996; solvers/optim/forcing.c).
typedef struct eo_newton_params {
    double descent_eps;  ///< p is a descent direction iff ∇gᵀp < −eps‖∇g‖‖p‖ (1e-12)
    char forcing[16];    ///< "auto", "none", "constant", "ew1", "ew2" (default "auto")
    double eta;          ///< constant: η_k; ew1/ew2: η_0 (default 0.5)
    double ew_gamma;     ///< ew2: γ ∈ (0, 1] (default 0.9)
    double ew_alpha;     ///< ew2: α ∈ (1, 2] (default 2)
    double eta_max;      ///< upper bound of η_k (default 0.9)
    double eta_min;      ///< lower bound of η_k (default 1e-12)
    double local_ratio;  ///< auto: ew2 only after a full step whose decrement fell to at most
                         ///< this times the previous one (default 0.1)
    double eta_global;   ///< auto: η_k before that (default 1e-4)
    int global_max_iters; ///< auto: a solve at eta_global needing more linear iterations ends the
                          ///< guard for the minimization (default 20)
    double estimate_gate; ///< decrement-estimate gate (solvers/optim/newton.c): at x_k (k ≥ 2)
                          ///< the estimate solve is skipped unless the stopping rule passes
                          ///< with a decrement between d_{k−1}³/d_{k−2}² / estimate_gate
                          ///< (quadratic progress, with this safety factor) and d_{k−1} (no
                          ///< progress: a plateau rule); d = exact λ²/2 of the last
                          ///< directions. 0 = always try (default 10)
} eo_newton_params;

static const char *const forcing_names[] = {"auto", "none", "constant", "ew1", "ew2", NULL};

typedef struct newton_state {
    eo_descent_ws w;
    const eo_csc *H;        /* pattern last analyzed */
    const int *colptr, *rowind;
    int pn, pnnz;
    /* the current direction call (for assemble) */
    const eo_solver_ctx *sc;
    const double *x;
    eo_solve_result *res;
    /* the last direction, reported to the fix once its step is accepted */
    int pending;
    double g_old, dg, alpha;
    double proj_sum;
    long proj_count;
    eo_inexact inexact;     /* forcing terms (forcing.h) */
    int eta_due;            /* the direction's forcing term is still to be set ... */
    double eta_gnorm, eta;  /* ... from this ‖∇g‖; the term set (0: none) */
    double shift_last;      /* c of the last direction's matrix, for ew1's residual */
    double *Hp;             /* ew1: H̃p workspace (n) */
    /* the decrement estimate from the last factor (newton_decrement_estimate) */
    int est_ok;             /* the linear solver holds the factor of the unshifted H̃ of the
                               last direction and its step was a full one (α = 1) */
    double *est;            /* n: H̃⁻¹∇g */
    double dec_last, dec_prev, dec_prev2; /* λ²/2 of the last three directions (NAN: none yet) */
} newton_state;

static const eo_param_desc newton_desc[] = {
    {.key = "descent_eps", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, descent_eps),
     .def.d = 1e-12, .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "p is a descent direction iff grad'p < -eps*|grad|*|p|"},
    {.key = "forcing", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_newton_params, forcing),
     .size = sizeof(((eo_newton_params *)0)->forcing), .def.s = "auto", .choices = forcing_names,
     .help = "inexact Newton with an iterative solver.linear: inner relative tolerance eta_k = auto (ew2 "
             "while the linear solves are iterative, e.g. solver.linear = auto's reused factor or multigrid, "
             "but eta_global until Newton converges fast (see local_ratio); none while they are direct), "
             "none (the solver's own tol), constant (eta), ew1 / ew2 (Eisenstat-Walker choice 1 / 2)"},
    {.key = "eta", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, eta), .def.d = 0.5,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "forcing = constant: eta_k; ew1/ew2: eta_0"},
    {.key = "ew_gamma", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, ew_gamma), .def.d = 0.9,
     .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX,
     .help = "ew2: eta_k = ew_gamma (|grad_k|/|grad_k-1|)^ew_alpha"},
    {.key = "ew_alpha", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, ew_alpha), .def.d = 2,
     .min = 1, .max = 2, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX, .help = "ew2: exponent in (1, 2]"},
    {.key = "eta_max", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, eta_max), .def.d = 0.9,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "upper bound of the forcing term"},
    {.key = "eta_min", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, eta_min), .def.d = 1e-12,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "lower bound of the forcing term"},
    {.key = "local_ratio", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, local_ratio),
     .def.d = 0.1, .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX,
     .help = "forcing = auto: Eisenstat-Walker terms only after a full step (alpha = 1) whose decrement fell to "
             "at most local_ratio times the previous one (fast local convergence); else eta_global "
             "(1 = only the full-step condition)"},
    {.key = "eta_global", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, eta_global),
     .def.d = 1e-4, .min = 0, .max = 1, .range = EO_RANGE_OPEN,
     .help = "forcing = auto: the inner relative tolerance before fast local convergence (see local_ratio)"},
    {.key = "global_max_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_newton_params, global_max_iters),
     .def.i = 20, .min = 0, .range = EO_RANGE_MIN,
     .help = "forcing = auto: a solve at eta_global that needs more linear iterations than this ends the guard "
             "for the rest of the minimization (ew2 from then on: tight solves are costly with this solver)"},
    {.key = "estimate_gate", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_params, estimate_gate),
     .def.d = 10, .min = 0, .range = EO_RANGE_MIN,
     .help = "decrement-estimate solve at x_k (k >= 2) only if the stopping rule passes with a decrement between "
             "d_{k-1}^3/d_{k-2}^2/estimate_gate (quadratic phase; d_{k-1}^2/d_{k-2}/estimate_gate when the "
             "decrease is not accelerating) and d_{k-1} (d = exact lambda^2/2 of the last directions); at k = 1 "
             "always tried; 0 = try it after every full step"},
    {0},
};

static int newton_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    newton_state *st = vst;
    (void)params;
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->Hp);
    eo_free(ctx, st->est);
    memset(st, 0, sizeof *st);
    st->Hp = eo_calloc(ctx, (size_t)(n > 0 ? n : 1), sizeof(double));
    st->est = eo_calloc(ctx, (size_t)(n > 0 ? n : 1), sizeof(double));
    if (!st->Hp || !st->est) return eo_error(ctx, EO_ERR_NOMEM, "newton: out of memory (n = %d)", n);
    return eo_descent_ws_init(ctx, n, &st->w);
}

static void newton_destroy(void *vst, eo_ctx *ctx)
{
    newton_state *st = vst;
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->Hp);
    st->Hp = NULL;
    eo_free(ctx, st->est);
    st->est = NULL;
}

/* eo_hessfix_assemble_fn: the objective's Hessian at st->x, analyzed on a new pattern. */
static int newton_assemble(void *user, eo_proj proj, const unsigned char *proj_of, eo_csc **out,
                           int *reason)
{
    newton_state *st = user;
    const eo_solver_ctx *sc = st->sc;
    const int n = sc->obj->n;
    eo_csc *H = NULL;
    const double t0 = eo_wtime(), c0 = eo_cputime();
    int rc = proj_of ? eo_objective_hessian_masked(sc->obj, st->x, proj_of, &H)
                     : eo_objective_hessian(sc->obj, st->x, proj, &H);
    st->res->t_assembly += eo_wtime() - t0;
    st->res->c_assembly += eo_cputime() - c0;
    st->res->n_assembly++;
    if (rc < 0) return rc;
    if (!H || H->n != n)
        return eo_error(sc->ctx, EO_ERR_INVALID, "newton: Hessian has n = %d, objective has n = %d",
                        H ? H->n : -1, n);
    if (H != st->H || H->colptr != st->colptr || H->rowind != st->rowind || H->n != st->pn ||
        H->nnz != st->pnnz) {
        for (int j = 0; j < n; j++) {
            int e = H->colptr[j + 1] - 1;
            if (e < H->colptr[j] || H->rowind[e] != j)
                return eo_error(sc->ctx, EO_ERR_INVALID,
                                "newton: Hessian column %d has no stored diagonal entry", j);
        }
        st->H = NULL;
        rc = eo_linsolve_analyze(sc->linear, H);
        if (rc < 0) {
            st->res->status = rc;
            *reason = EO_DIVERGED_LINSOLVE;
            return EO_OK;
        }
        st->H = H;
        st->colptr = H->colptr;
        st->rowind = H->rowind;
        st->pn = H->n;
        st->pnnz = H->nnz;
    }
    /* the forcing term once the linear solver has seen the pattern: a policy (`auto`)
     * knows only after its first analyze whether its solves are iterative, and the first
     * direction of a process must get the term that the same direction of a longer run
     * gets (a restarted run continues bit for bit) */
    if (st->eta_due) {
        st->eta_due = 0;
        st->eta = eo_inexact_before(&st->inexact, sc->linear, st->eta_gnorm);
    }
    *out = H;
    return EO_OK;
}

static eo_hessfix_env newton_env(newton_state *st, const eo_newton_params *np,
                                 const eo_solver_ctx *sc, const double *x, double g,
                                 const double *grad, eo_solve_result *res)
{
    st->sc = sc;
    st->x = x;
    st->res = res;
    return (eo_hessfix_env){.obj = sc->obj, .linear = sc->linear, .ctx = sc->ctx, .n = sc->obj->n,
                            .x = x, .g = g, .grad = grad, .want_direction = 1,
                            .descent_eps = np->descent_eps, .assemble = newton_assemble,
                            .user = st, .res = res};
}

static int newton_begin(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                        double g, const double *grad, eo_solve_result *res)
{
    newton_state *st = vst;
    st->pending = 0;
    st->est_ok = 0;
    st->dec_last = st->dec_prev = st->dec_prev2 = NAN;
    st->proj_sum = 0;
    st->proj_count = 0;
    const eo_newton_params *np = params;
    eo_inexact_begin(&st->inexact, eo_forcing_kind(np->forcing), np->eta, np->ew_gamma, np->ew_alpha,
                     np->eta_min, np->eta_max);
    st->inexact.local_ratio = np->local_ratio;
    st->inexact.eta_global = np->eta_global;
    st->inexact.global_max_iters = np->global_max_iters;
    if (!sc->linear) return eo_error(sc->ctx, EO_ERR_INVALID, "newton needs a linear solver");
    if (!sc->hessfix) return eo_error(sc->ctx, EO_ERR_INVALID, "newton needs a Hessian fix");
    if (!sc->hessfix->begin) return EO_OK;
    eo_hessfix_env env = newton_env(st, params, sc, x, g, grad, res);
    return sc->hessfix->begin(sc->hessfix_state, sc->hessfix_params, &env);
}

/* The step along the last direction was accepted and g = g(x_{k+1}): tell the fix (its
 * hook `accepted`), once, before anything else is done at x_{k+1}. */
static void report_accepted(newton_state *st, const eo_solver_ctx *sc, double g)
{
    const eo_hessfix_type *hf = sc->hessfix;
    if (st->pending && hf->accepted) {
        const double a = st->alpha;
        eo_hessfix_step_info si = {.alpha = a, .g_old = st->g_old, .g_new = g, .dg = st->dg,
                                   .actual = st->g_old - g,
                                   .predicted = -a * st->dg * (1 - a / 2)};
        hf->accepted(sc->hessfix_state, sc->hessfix_params, &si);
    }
    st->pending = 0;
}

/* 1 if the stopping rule passes, at si, with some decrement in [min(a, b), max(a, b)]:
 * tested at the ends and at geometric steps between them (ratio at most 1.25, at most 65
 * values; a rule may pass on a window only, e.g. relative_decrement's rounding floor). */
static int gate_open(const eo_solver_ctx *sc, const eo_stop_info *si, double a, double b)
{
    const double lo = fmin(a, b), hi = fmax(a, b);
    const double f = fmax(1.25, pow(hi / lo, 1.0 / 64));
    eo_stop_info probe = *si;
    for (double d = hi; d > lo; d /= f) {
        probe.decrement = d;
        if (sc->stop->check(sc->stop_params, &probe) > 0) return 1;
    }
    probe.decrement = lo;
    return sc->stop->check(sc->stop_params, &probe) > 0;
}

/* λ̃²/2 = ½∇g(x_{k+1})ᵀH̃_k⁻¹∇g(x_{k+1}) with the factor of the last direction's matrix
 * (one solve, no assembly, no factorization): NAN unless that factor is of the
 * unshifted H̃_k and the step along it was a full Newton step (α = 1), where
 * H̃_{k+1} − H̃_k = O(‖p_k‖) and the estimate is the decrement to first order. */
static int newton_decrement_estimate(void *vst, const void *params, const eo_solver_ctx *sc,
                                     const double *x, double g, const double *grad,
                                     const eo_stop_info *si, double *est, eo_solve_result *res)
{
    newton_state *st = vst;
    const eo_newton_params *np = params;
    (void)x, (void)res;
    report_accepted(st, sc, g);
    *est = NAN;
    if (!st->est_ok) return EO_OK;
    st->est_ok = 0; /* used once: the next direction factors again */
    if (np->estimate_gate > 0 && si && st->dec_last > 0 && st->dec_prev > 0) {
        /* the gate (file comment): could the rule pass at all? */
        const double r = st->dec_last / st->dec_prev;
        double pred = st->dec_last * r * r / np->estimate_gate;
        /* a linear phase (the last ratio no smaller than half the one before: not
         * accelerating, e.g. projected Newton far from a PD Hessian) shrinks d by about
         * r per iteration, not r²: predict d_{k−1}·r/s there */
        if (st->dec_prev2 > 0 && r < 1 && r >= 0.5 * (st->dec_prev / st->dec_prev2))
            pred = st->dec_last * r / np->estimate_gate;
        if (isfinite(pred) && !gate_open(sc, si, pred, st->dec_last)) return EO_OK;
    }
    int rc = eo_linsolve_solve(sc->linear, grad, st->est);
    if (rc < 0) return rc;
    if (rc != EO_OK) return EO_OK; /* e.g. an iterative solve that did not converge */
    const double d = eo_vdot(sc->obj->space, sc->obj->n, grad, st->est);
    if (d >= 0 && isfinite(d)) *est = d / 2;
    return EO_OK;
}

static int newton_direction(void *vst, const void *params, const eo_solver_ctx *sc,
                            const double *x, double g, const double *grad, double *p,
                            eo_direction_out *out, eo_solve_result *res)
{
    newton_state *st = vst;
    const eo_hessfix_type *hf = sc->hessfix;
    report_accepted(st, sc, g);
    st->est_ok = 0;
    eo_hessfix_env env = newton_env(st, params, sc, x, g, grad, res);
    eo_hessfix_out fo = {.shift = 0, .projected = 0, .factored = 0, .reason = 0};
    st->eta_due = 1;
    st->eta_gnorm = eo_vnorm2(sc->obj->space, sc->obj->n, grad);
    st->eta = 0;
    int rc = hf->factor(sc->hessfix_state, sc->hessfix_params, &env, p, &fo);
    if (st->eta_due) { /* no Hessian assembled (a fix that falls back at once): keep the sequence */
        st->eta_due = 0;
        st->eta = eo_inexact_before(&st->inexact, sc->linear, st->eta_gnorm);
    }
    out->eta = st->eta;
    if (rc < 0) return rc;
    const eo_linsolve_stats *ls = eo_linsolve_get_stats(sc->linear);
    out->lin_iters = ls->iterations;
    res->lin_iters += ls->iterations;
    out->neg_curvature = fo.neg_curvature;
    if (fo.neg_curvature) res->n_neg_curvature++;
    st->shift_last = fo.shift;
    st->est_ok = fo.factored && fo.shift == 0 && !fo.reason && sc->linear;
    out->shift = fo.shift;
    out->projected = fo.projected;
    st->proj_sum += fo.projected;
    st->proj_count++;
    res->projected = st->proj_sum / (double)st->proj_count;
    if (fo.reason) {
        out->reason = fo.reason;
        return EO_OK;
    }
    st->g_old = g;
    st->dg = eo_vdot(sc->obj->space, sc->obj->n, grad, p);
    st->dec_prev2 = st->dec_prev;
    st->dec_prev = st->dec_last;
    st->dec_last = -st->dg / 2;
    out->alpha0 = 1;
    return EO_OK;
}

static void newton_accepted(void *vst, const void *params, const double *x, const double *x_new,
                            const double *grad, const double *grad_new, const double *p,
                            double alpha)
{
    newton_state *st = vst;
    (void)params, (void)x, (void)x_new, (void)grad_new;
    st->alpha = alpha;
    st->pending = 1;
    if (alpha != 1) st->est_ok = 0;
    if (st->inexact.kind == EO_FORCING_NONE) return;
    const int n = st->sc->obj->n;
    double linres = NAN;
    const eo_vspace *vs = st->sc->obj->space;
    if (st->inexact.kind == EO_FORCING_EW1 && st->H) { /* ‖∇g + α(H + cI)p‖ */
        eo_csc_symv(st->H, p, st->Hp);
        if (vs && vs->assemble(st->Hp, vs->user) < 0) /* a part's H: the parts' products summed */
            for (int i = 0; i < n; i++) st->Hp[i] = NAN;
        double r2 = 0;
        for (int i = 0; i < n; i++) {
            double r = grad[i] + alpha * (st->Hp[i] + st->shift_last * p[i]);
            if (!vs || vs->own[i]) r2 += r * r;
        }
        eo_vreduce(vs, &r2, 1, EO_REDUCE_SUM);
        linres = sqrt(r2);
    }
    eo_inexact_after(&st->inexact, eo_vnorm2(vs, n, grad), linres, alpha, st->dec_last);
}

static const eo_descent_ops newton_ops = {
    .begin = newton_begin,
    .direction = newton_direction,
    .accepted = newton_accepted,
    .decrement_estimate = newton_decrement_estimate,
};

static int newton_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                           eo_solve_result *res)
{
    newton_state *st = vst;
    eo_newton_params def;
    if (!params) {
        eo_params_default(newton_desc, &def);
        params = &def;
    }
    return eo_descent_minimize(&newton_ops, st, params, sc, &st->w, x, res);
}

const eo_optimizer_type eo_optimizer_newton = {
    .info = {.name = "newton",
             .summary = "Newton's method: p = -(H + cI)^-1 grad, line search, Hessian fix",
             .params = newton_desc,
             .params_size = sizeof(eo_newton_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(newton_state),
    .needs_linear = 1,
    .needs_hessian = 1,
    .setup = newton_setup,
    .minimize = newton_minimize,
    .destroy = newton_destroy,
    .newton_decrement = 1,
};
