/* Trust-region Newton with the Steihaug–Toint truncated CG inner solve (registry key
 * "newton_tr").
 *
 * Model at x_k (Nocedal & Wright, Numerical Optimization, 2nd ed., ch. 4, eq. 4.3):
 *     m_k(p) = g_k + ∇g_kᵀp + ½ pᵀH_k p,   ‖p‖_M ≤ Δ_k,
 * H_k = ∇²g(x_k) assembled with no projection (hessian = "true", the default: the trust
 * region, not a Hessian fix, handles indefiniteness) or with the per-element projection
 * of solver.hessian_fix (hessian = "fix": its eo_hessfix_type.elem_proj; clamp/abs give a
 * PSD H, none/shift/... the true one). The norm is ‖p‖_M = √(pᵀMp) with the
 * preconditioner M (precond = "none": M = I; "jacobi": M = diag|H_ii|, zero or non-finite
 * entries replaced by the mean |H_ii|), an ellipsoidal trust region (N&W §4.5,
 * eq. 4.45 with D = M^½).
 *
 * Inner solve: preconditioned CG on H p = −∇g from p = 0, truncated (Steihaug 1983,
 * "The conjugate gradient method and trust regions in large scale optimization", SIAM J.
 * Numer. Anal. 20; Toint 1981; N&W Alg. 7.2 in the M-norm; Conn, Gould & Toint,
 * Trust-Region Methods, Alg. 7.5.1 for the recurrences of pᵀMp, pᵀMd, dᵀMd):
 *     r = ∇g, z = M⁻¹r, d = −z
 *     loop: κ = dᵀHd
 *       κ ≤ 0 (negative curvature):  p ← p + τd on the boundary ‖p + τd‖_M = Δ, τ the
 *                                    root (of the two) with the smaller model value; stop
 *       α = rᵀz/κ; ‖p + αd‖_M ≥ Δ:   p ← p + τd, τ > 0 the boundary root; stop
 *       p ← p + αd, r ← r + αHd;     ‖r‖ ≤ η_k‖∇g‖: stop (interior, inexact Newton step)
 *       z = M⁻¹r, β = rᵀz/r₋ᵀz₋, d ← −z + βd
 * Forcing term (N&W Thm. 7.2, relative to ‖∇g₀‖ so it is free of units):
 *     forcing = "quadratic"    η_k = min(cg_rtol_max, ‖∇g_k‖/‖∇g₀‖)   (q-quadratic)
 *               "superlinear"  η_k = min(cg_rtol_max, √(‖∇g_k‖/‖∇g₀‖))
 * at most cg_max_iters CG iterations (0 = n; then the last iterate is the step).
 *
 * Step acceptance and radius (N&W Alg. 4.1): ρ = actual / predicted reduction,
 * predicted = m(0) − m(p) = −½(∇gᵀp + rᵀp) (r = ∇g + Hp, the model gradient at p).
 * Where g(x + p) differs from g(x) by less than noise·|g(x)| (values at the rounding
 * level of g) the actual reduction is the trapezoidal estimate −½(∇g(x) + ∇g(x+p))ᵀp,
 * exact for a quadratic and accurate to the rounding of ∇g (the idea of Hager & Zhang's
 * approximate Wolfe test, used by the wolfe line search). A non-finite g(x+p) (an
 * inverted element of a barrier material) gives ρ = −∞.
 *     ρ < rho_low:                         Δ ← shrink·‖p‖_M
 *     ρ > rho_high and ‖p‖_M = Δ:          Δ ← min(grow·Δ, delta_max)
 *     ρ > eta:                             accept x ← x + p; else solve again from x_k
 *                                          with the smaller Δ (same H, no reassembly)
 * Δ₀ = delta0, or (0) none at first: the first inner solve is unconstrained; if it
 * meets negative curvature there, Δ becomes max(2‖p‖_M, τ*‖d‖_M), τ* = rᵀz/|κ| (the
 * step along d with the curvature's modulus). Δ carries over between the iterations of
 * one minimization and starts anew in the next.
 *
 * One record per accepted iterate: ls_evals = trial points evaluated from x_k (one
 * value+gradient call each), alpha = 1, decrement = the predicted reduction of the first
 * inner solve at x_k when that step is interior (it is then the Newton decrement λ²/2
 * of H up to the forcing term; NAN for a boundary step, so newton_decrement does not
 * stop on a truncated step), shift = 0, projected = 1 if H is projected, else 0.
 * Reasons: those of the stopping rule, EO_DIVERGED_NONFINITE (non-finite g, ∇g or H),
 * EO_DIVERGED_MAX_ITERS, EO_DIVERGED_TIME_BUDGET, EO_DIVERGED_LINESEARCH (max_rejects
 * trial steps in a row rejected, or Δ below 1e-15·max(‖x‖_M, 1)), EO_DIVERGED_STAGNATED
 * (as the descent loop: 25 + k/10 accepted steps without a decrease of g by more than
 * 1e-15|g| or a new ‖∇g‖ below 0.9 of its best), EO_DIVERGED_EXTERNAL.
 * Counters: res.n_inner (CG iterations), res.n_negcurv (inner solves that met
 * negative curvature), res.n_hessian. Everything is allocated in setup. */
#include <float.h>
#include <stddef.h>
#include <string.h>

#include "descent.h"  /* eo_dot, eo_norm2, eo_solve_result_finish */
#include "external.h" /* eo_external_inverted */

/// Trust-region Newton with Steihaug–Toint CG (config `solver.newton_tr.*`;
/// solvers/optim/newton_tr.c has the algorithm).
typedef struct eo_newton_tr_params {
    char hessian[16];    ///< model Hessian: "true" (unprojected) or "fix" (per-element
                         ///< projection of solver.hessian_fix) (default "true")
    char precond[16];    ///< "none" (M = I) or "jacobi" (M = diag|H_ii|): CG preconditioner
                         ///< and trust-region norm √(pᵀMp) (default "none")
    double delta0;       ///< first radius in that norm (m for none); 0 = the first inner
                         ///< solve is unconstrained (default 0)
    double delta_max;    ///< largest radius, 0 = none (0)
    double eta;          ///< accept when ρ = actual/predicted reduction > eta (1e-4)
    double rho_low;      ///< Δ ← shrink·‖p‖ when ρ < rho_low (0.25)
    double rho_high;     ///< Δ ← grow·Δ when ρ > rho_high on the boundary (0.75)
    double shrink;       ///< (0.25)
    double grow;         ///< (2)
    char forcing[16];    ///< CG tolerance η_k = min(cg_rtol_max, ‖∇g‖/‖∇g₀‖) "quadratic"
                         ///< or its square root "superlinear" (default "quadratic")
    double cg_rtol_max;  ///< largest η_k (0.5)
    int cg_max_iters;    ///< CG iterations per inner solve, 0 = n (0)
    int max_rejects;     ///< rejected trial steps in a row before diverged_linesearch (50)
    double noise;        ///< where |g(x+p) − g(x)| ≤ noise·|g(x)| the actual reduction is
                         ///< −½(∇g(x) + ∇g(x+p))ᵀp (1e-10)
} eo_newton_tr_params;

enum { HESS_TRUE, HESS_FIX };
enum { PRE_NONE, PRE_JACOBI };
enum { FORCE_QUADRATIC, FORCE_SUPERLINEAR };
enum { CG_INTERIOR, CG_BOUNDARY, CG_NEGCURV, CG_MAXIT };

/* accepted steps without significant progress before EO_DIVERGED_STAGNATED (+ k/10) */
#define TR_WEAK_LIMIT 25

typedef struct tr_state {
    int n;
    double *store;
    double *grad, *grad_new, *x_new, *p, *r, *z, *d, *hd, *minv;
} tr_state;

static const char *const hessian_choices[] = {"true", "fix", NULL};
static const char *const precond_choices[] = {"none", "jacobi", NULL};
static const char *const forcing_choices[] = {"quadratic", "superlinear", NULL};

#define TR_STR(f) .size = sizeof(((eo_newton_tr_params *)0)->f)
static const eo_param_desc tr_desc[] = {
    {.key = "hessian", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_newton_tr_params, hessian), TR_STR(hessian),
     .def.s = "true", .choices = hessian_choices,
     .help = "model Hessian: true (unprojected) or fix (projection of solver.hessian_fix)"},
    {.key = "precond", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_newton_tr_params, precond), TR_STR(precond),
     .def.s = "none", .choices = precond_choices,
     .help = "CG preconditioner M and trust-region norm sqrt(p'Mp): none (M = I) or jacobi (diag |H_ii|)"},
    {.key = "delta0", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, delta0), .def.d = 0,
     .min = 0, .range = EO_RANGE_MIN,
     .help = "first radius in the trust-region norm (m for precond none); 0 = unconstrained first solve"},
    {.key = "delta_max", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, delta_max), .def.d = 0,
     .min = 0, .range = EO_RANGE_MIN, .help = "largest radius; 0 = none"},
    {.key = "eta", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, eta), .def.d = 1e-4,
     .min = 0, .max = 0.25, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "accept the step when rho = actual/predicted reduction > eta"},
    {.key = "rho_low", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, rho_low), .def.d = 0.25,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "shrink the radius when rho < rho_low"},
    {.key = "rho_high", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, rho_high), .def.d = 0.75,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN,
     .help = "grow the radius when rho > rho_high and the step is on the boundary"},
    {.key = "shrink", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, shrink), .def.d = 0.25,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "radius <- shrink*|p| after a poor step"},
    {.key = "grow", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, grow), .def.d = 2,
     .min = 1, .max = 1e6, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX, .help = "radius <- grow*radius after a good boundary step"},
    {.key = "forcing", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_newton_tr_params, forcing), TR_STR(forcing),
     .def.s = "quadratic", .choices = forcing_choices,
     .help = "CG tolerance eta_k = min(cg_rtol_max, |grad|/|grad0|) (quadratic) or its square root (superlinear)"},
    {.key = "cg_rtol_max", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, cg_rtol_max), .def.d = 0.5,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "largest relative CG residual ||r||/||grad||"},
    {.key = "cg_max_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_newton_tr_params, cg_max_iters), .def.i = 0,
     .min = 0, .max = 100000000, .range = EO_RANGE_CLOSED, .help = "CG iterations per inner solve (0 = n)"},
    {.key = "max_rejects", .kind = EO_PARAM_INT, .offset = offsetof(eo_newton_tr_params, max_rejects), .def.i = 50,
     .min = 1, .max = 100000, .range = EO_RANGE_CLOSED,
     .help = "rejected steps in a row before diverged_linesearch"},
    {.key = "noise", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_newton_tr_params, noise), .def.d = 1e-10,
     .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "where g changes by less than noise*|g| the actual reduction is -(grad+grad_new)'p/2"},
    {0},
};

static void tr_free(tr_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->store);
    memset(st, 0, sizeof *st);
}

static int tr_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    tr_state *st = vst;
    (void)params;
    memset(st, 0, sizeof *st);
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "newton_tr: n = %d < 0", n);
    size_t m = (size_t)(n > 0 ? n : 1);
    st->n = n;
    st->store = eo_calloc(ctx, 9 * m, sizeof(double));
    if (!st->store) return eo_error(ctx, EO_ERR_NOMEM, "newton_tr: out of memory (n = %d)", n);
    double **v[] = {&st->grad, &st->grad_new, &st->x_new, &st->p, &st->r, &st->z, &st->d, &st->hd, &st->minv};
    for (size_t i = 0; i < 9; i++) *v[i] = st->store + i * m;
    return EO_OK;
}

static void tr_destroy(void *vst, eo_ctx *ctx) { tr_free(vst, ctx); }

/* M-norm products (M = diag(1/minv)). */
static double mdot(const eo_vspace *vs, int n, const double *a, const double *b, const double *minv, int pre)
{
    if (pre == PRE_NONE) return eo_vdot(vs, n, a, b);
    double s = 0;
    for (int i = 0; i < n; i++)
        if (!vs || vs->own[i]) s += a[i] * b[i] / minv[i];
    eo_vreduce(vs, &s, 1, EO_REDUCE_SUM);
    return s;
}

/* hd = H d, H a part's matrix on a distributed space: the parts' products summed */
static void hmul(const eo_vspace *vs, const eo_csc *H, const double *d, double *hd)
{
    eo_csc_symv(H, d, hd);
    if (vs && vs->assemble(hd, vs->user) < 0)
        for (int i = 0; i < vs->n; i++) hd[i] = NAN;
}

/* Roots τ₋ ≤ τ₊ of ‖p + τd‖²_M = Δ² (pMp ≤ Δ², so τ₋ ≤ 0 ≤ τ₊). */
static void boundary_roots(double pmp, double pmd, double dmd, double delta, double *tm, double *tp)
{
    double disc = pmd * pmd + dmd * (delta * delta - pmp);
    double s = sqrt(disc > 0 ? disc : 0);
    /* the root without cancellation first, the other from the product c/a */
    double c = pmp - delta * delta; /* ≤ 0 */
    if (pmd >= 0) {
        *tm = (-pmd - s) / dmd;
        *tp = *tm != 0 ? c / (dmd * *tm) : 0;
    } else {
        *tp = (-pmd + s) / dmd;
        *tm = *tp != 0 ? c / (dmd * *tp) : 0;
    }
}

typedef struct cg_out {
    int how;         /* CG_INTERIOR, ... */
    int iters;
    double pred;     /* m(0) − m(p) */
    double pnorm;    /* ‖p‖_M */
    double delta_nc; /* radius proposed when negative curvature is met with Δ = ∞ */
} cg_out;

/* Steihaug–Toint CG for min m(p), ‖p‖_M ≤ delta (delta may be +∞). Writes st->p and
 * leaves r = ∇g + Hp in st->r. Returns EO_OK, or EO_ERR_RANGE for a non-finite κ. */
static int steihaug(tr_state *st, const eo_vspace *vs, const eo_csc *H, const double *grad, double gnorm, double delta, double rtol,
                    int maxit, int pre, cg_out *o)
{
    const int n = st->n;
    double *p = st->p, *r = st->r, *z = st->z, *d = st->d, *hd = st->hd, *minv = st->minv;
    memset(o, 0, sizeof *o);
    o->how = CG_MAXIT;
    o->delta_nc = NAN;
    for (int i = 0; i < n; i++) {
        p[i] = 0;
        r[i] = grad[i];
        z[i] = pre == PRE_NONE ? r[i] : r[i] * minv[i];
        d[i] = -z[i];
    }
    double rz = eo_vdot(vs, n, r, z), pmp = 0, pmd = 0, dmd = rz;
    const double rstop = rtol * gnorm;
    if (gnorm == 0) {
        o->how = CG_INTERIOR;
        return EO_OK;
    }
    for (int j = 0; j < maxit; j++) {
        hmul(vs, H, d, hd);
        double kappa = eo_vdot(vs, n, d, hd);
        if (!isfinite(kappa)) return EO_ERR_RANGE;
        o->iters = j + 1;
        if (kappa <= 0) {
            o->how = CG_NEGCURV;
            double rd = eo_vdot(vs, n, r, d), tau;
            if (!isfinite(delta)) { /* no radius yet: propose one (see the file comment) */
                double tstar = rz / fmax(fabs(kappa), DBL_MIN);
                delta = fmax(2 * sqrt(pmp), tstar * sqrt(dmd));
                o->delta_nc = delta;
            }
            double tm, tp;
            boundary_roots(pmp, pmd, dmd, delta, &tm, &tp);
            /* the root with the smaller model value m(p + τd) − m(p) = τ rᵀd + ½τ²κ */
            double mm = tm * rd + 0.5 * tm * tm * kappa, mp = tp * rd + 0.5 * tp * tp * kappa;
            tau = mm < mp ? tm : tp;
            for (int i = 0; i < n; i++) {
                p[i] += tau * d[i];
                r[i] += tau * hd[i];
            }
            break;
        }
        double alpha = rz / kappa;
        double pmp_new = pmp + 2 * alpha * pmd + alpha * alpha * dmd;
        if (pmp_new >= delta * delta) {
            o->how = CG_BOUNDARY;
            double tm, tp;
            boundary_roots(pmp, pmd, dmd, delta, &tm, &tp);
            for (int i = 0; i < n; i++) {
                p[i] += tp * d[i];
                r[i] += tp * hd[i];
            }
            break;
        }
        for (int i = 0; i < n; i++) {
            p[i] += alpha * d[i];
            r[i] += alpha * hd[i];
        }
        pmp = pmp_new;
        if (eo_vnorm2(vs, n, r) <= rstop) {
            o->how = CG_INTERIOR;
            break;
        }
        for (int i = 0; i < n; i++) z[i] = pre == PRE_NONE ? r[i] : r[i] * minv[i];
        double rz_new = eo_vdot(vs, n, r, z);
        double beta = rz_new / rz;
        for (int i = 0; i < n; i++) d[i] = -z[i] + beta * d[i];
        pmd = beta * (pmd + alpha * dmd);
        dmd = rz_new + beta * beta * dmd;
        rz = rz_new;
    }
    o->pred = -0.5 * (eo_vdot(vs, n, grad, p) + eo_vdot(vs, n, r, p));
    o->pnorm = sqrt(mdot(vs, n, p, p, minv, pre));
    return EO_OK;
}

static int tr_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    tr_state *st = vst;
    eo_newton_tr_params def;
    const eo_newton_tr_params *tp = params;
    if (!tp) {
        eo_params_default(tr_desc, &def);
        tp = &def;
    }
    eo_objective *obj = sc->obj;
    const eo_vspace *vs = obj->space;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    const int hess = strcmp(tp->hessian, "fix") == 0 ? HESS_FIX : HESS_TRUE;
    const int pre = strcmp(tp->precond, "jacobi") == 0 ? PRE_JACOBI : PRE_NONE;
    const int force = strcmp(tp->forcing, "superlinear") == 0 ? FORCE_SUPERLINEAR : FORCE_QUADRATIC;
    const eo_proj proj = hess == HESS_FIX && sc->hessfix ? sc->hessfix->elem_proj : EO_PROJ_NONE;
    const long nall = vs ? vs->nglobal : n;
    const int maxit = tp->cg_max_iters > 0 ? tp->cg_max_iters : (nall > 0 ? (int)nall : 1);
    const double delta_max = tp->delta_max > 0 ? tp->delta_max : INFINITY;
    double *grad = st->grad, *grad_new = st->grad_new;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, last_dec = NAN;
    double delta = tp->delta0 > 0 ? tp->delta0 : INFINITY;
    double gn_sig = INFINITY;
    int rc = EO_OK, reason = 0, k = 0, weak = 0;

    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "newton_tr set up for n = %d, objective has n = %d", st->n, n);
        goto done;
    }
    if ((rc = eo_objective_gradient(obj, x, &g, grad)) < 0) goto done;
    gn = isfinite(g) ? eo_vnorm2(vs, n, grad) : NAN;
    gn0 = gn;
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .ls_evals = 0, .shift = 0, .projected = proj != EO_PROJ_NONE,
                             .inverted = eo_external_inverted(sc, x), .reason = 0, .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .step_norm = step_norm, .x_norm = eo_vnorm2(vs, n, x), .tol = sc->tol};
        if (!isfinite(g) || !isfinite(gn)) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, grad);
        if (!reason && sc->time_budget > 0 && eo_solver_agree(sc, eo_wtime() - t0 > sc->time_budget))
            reason = EO_DIVERGED_TIME_BUDGET;
        eo_csc *H = NULL;
        if (!reason) {
            if ((rc = eo_objective_hessian(obj, x, proj, &H)) < 0) goto done;
            if (!H || H->n != n) {
                rc = eo_error(sc->ctx, EO_ERR_INVALID, "newton_tr: Hessian has n = %d, objective has n = %d",
                              H ? H->n : -1, n);
                goto done;
            }
            eo_csc_diag(H, st->minv);
            if (vs && vs->assemble(st->minv, vs->user) < 0) st->minv[0] = NAN;
            double mean = 0;
            int finite = 1;
            for (int i = 0; i < n; i++) {
                finite &= isfinite(st->minv[i]);
                if (!vs || vs->own[i]) mean += fabs(st->minv[i]);
            }
            double fm[2] = {mean, !finite};
            eo_vreduce(vs, fm, 2, EO_REDUCE_SUM);
            mean = fm[0];
            if (fm[1] != 0) reason = EO_DIVERGED_NONFINITE;
            mean = nall > 0 && mean > 0 ? mean / (double)nall : 1;
            for (int i = 0; i < n; i++) {
                double a = fabs(st->minv[i]);
                st->minv[i] = 1 / (a > 0 ? a : mean);
            }
        }
        double rel = gn0 > 0 ? gn / gn0 : 0;
        double rtol = fmin(tp->cg_rtol_max, force == FORCE_SUPERLINEAR ? sqrt(rel) : rel);
        cg_out co = {0};
        if (!reason) {
            if (steihaug(st, vs, H, grad, gn, delta, rtol, maxit, pre, &co) < 0) {
                reason = EO_DIVERGED_NONFINITE;
            } else {
                res->n_inner += co.iters;
                if (co.how == CG_NEGCURV) res->n_negcurv++;
                if (co.how == CG_INTERIOR || co.how == CG_MAXIT) {
                    info.decrement = last_dec = co.pred;
                    if (sc->stop->needs_direction) {
                        si.decrement = co.pred;
                        reason = eo_solver_stop_check(sc, &si, x, grad);
                    }
                }
            }
        }
        if (!reason && (weak >= TR_WEAK_LIMIT + k / 10)) reason = EO_DIVERGED_STAGNATED;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        /* trial steps from x_k until one is accepted */
        double gnew = NAN;
        int accepted = 0, trials = 0;
        const double xm = sqrt(mdot(vs, n, x, x, st->minv, pre));
        for (;;) {
            if (!isfinite(delta) && co.how == CG_NEGCURV) delta = co.delta_nc;
            for (int i = 0; i < n; i++) st->x_new[i] = x[i] + st->p[i];
            trials++;
            if ((rc = eo_objective_gradient(obj, st->x_new, &gnew, grad_new)) < 0) goto done;
            double rho = -INFINITY;
            if (isfinite(gnew) && co.pred > 0) {
                double actual = g - gnew;
                if (fabs(actual) <= tp->noise * fabs(g)) {
                    double s = 0;
                    for (int i = 0; i < n; i++)
                        if (!vs || vs->own[i]) s += (grad[i] + grad_new[i]) * st->p[i];
                    eo_vreduce(vs, &s, 1, EO_REDUCE_SUM);
                    actual = isfinite(s) ? -0.5 * s : -INFINITY;
                }
                rho = actual / co.pred;
            }
            if (rho < tp->rho_low) delta = tp->shrink * co.pnorm;
            else if (rho > tp->rho_high && co.how != CG_INTERIOR && co.how != CG_MAXIT)
                delta = fmin(tp->grow * fmax(delta, co.pnorm), delta_max);
            if (rho > tp->eta) {
                accepted = 1;
                break;
            }
            if (trials >= tp->max_rejects || !(delta > 1e-15 * fmax(xm, 1))) break;
            if (steihaug(st, vs, H, grad, gn, delta, rtol, maxit, pre, &co) < 0) {
                reason = EO_DIVERGED_NONFINITE;
                break;
            }
            res->n_inner += co.iters;
            if (co.how == CG_NEGCURV) res->n_negcurv++;
        }
        info.ls_evals = trials;
        if (!accepted) {
            info.reason = reason = reason ? reason : EO_DIVERGED_LINESEARCH;
            eo_solver_report(sc, t0, &info);
            break;
        }
        info.alpha = 1;
        if (eo_solver_agree(sc, eo_solver_report(sc, t0, &info) != 0)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        double s2 = 0;
        for (int i = 0; i < n; i++) {
            double s = st->x_new[i] - x[i];
            if (!vs || vs->own[i]) s2 += s * s;
            x[i] = st->x_new[i];
        }
        eo_vreduce(vs, &s2, 1, EO_REDUCE_SUM);
        step_norm = sqrt(s2);
        double *t = grad;
        grad = grad_new;
        grad_new = t;
        g_prev = g;
        g = gnew;
        gn = eo_vnorm2(vs, n, grad);
        last_dec = NAN;
        if (g < g_prev - 1e-15 * fabs(g_prev) || gn < 0.9 * gn_sig) {
            weak = 0;
            if (gn < gn_sig) gn_sig = gn;
        } else {
            weak++;
        }
    }
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    res->decrement = last_dec;
    res->projected = proj != EO_PROJ_NONE;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_newton_tr = {
    .info = {.name = "newton_tr",
             .summary = "trust-region Newton, Steihaug-Toint truncated CG (negative curvature to the "
                        "boundary), optional Jacobi preconditioner",
             .params = tr_desc,
             .params_size = sizeof(eo_newton_tr_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(tr_state),
    .needs_linear = 0,
    .needs_hessian = 1,
    .linesearch = "none",
    .setup = tr_setup,
    .minimize = tr_minimize,
    .destroy = tr_destroy,
};
