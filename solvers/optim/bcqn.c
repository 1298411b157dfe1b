/* Blended cured quasi-Newton, BCQN (registry key "bcqn").
 *
 * Zhu, Bridson & Kaufman 2018, "Blended Cured Quasi-Newton for Distortion Optimization",
 * ACM TOG 37(4) (arXiv 1705.00039); the authors' code github.com/mike323zyf/BCQN
 * (code/3D/lib/solver/mlbfgs_lcp_split_solver.m). Three parts, three registered pieces:
 *   1. this optimizer: L-BFGS (two-loop recursion, lbfgs_memory.h) whose initial inverse
 *      Hessian is the Sobolev proxy H⁰ = L⁻¹ (the objective's constant SPD matrix, the
 *      step objective's M + w·Σₜ Vₜ(λ+2μ)GₜᵀGₜ — the paper's Laplacian with the material
 *      and inertia folded in — factored once, pd_factor.h), and whose stored secant pairs
 *      are BLENDED toward that proxy (the paper's eq. 13):
 *          ŷ_k = (1 − β_k) y_k + β_k L s_k,
 *          β_k = clamp( ‖L‖₂ · y_kᵀ L s_k / B , 0, 1 ),   B = |Ω|^{4/3}  (3-D),
 *      s_k = x_{k+1} − x_k, y_k = ∇g_{k+1} − ∇g_k, ‖L‖₂ by power iteration once per L.
 *      β = 1 makes (s, L s) a pair L⁻¹ already satisfies: the direction tends to the
 *      Sobolev (preconditioned) gradient −L⁻¹∇g, strong far from the solution and on
 *      large distortions; β = 0 is plain L-BFGS with H⁰ = L⁻¹ (lbfgs h0 = pd), fast near
 *      the solution. Blending also "cures" the pairs: sᵀŷ = (1 − β)sᵀy + β sᵀLs > 0
 *      whenever sᵀLs dominates a negative-curvature secant.
 *   2. the line search `barrier_filter` (solvers/linesearch/barrier_filter.c, the default
 *      for bcqn): first trial min(1, safety·α_max), α_max the step at which the first
 *      element inverts, then Armijo.
 *   3. the stopping rule `characteristic_gradient` (solvers/stop/): ‖∇g‖ ≤ tol·g_c.
 * Units. The paper's quantities are those of a unit-modulus distortion energy over a
 * mesh measured in its own units (L the Laplacian, y a gradient of ∫ψ). Here g carries a
 * stiffness k = w·(mean ‖∂²ψ/∂σ²(I)‖) (objective.h, characteristic: L ≈ k·L̂, y ≈ k·ŷ),
 * so the paper's β is taken of L/k and y/k:  β = blend_scale·‖L‖·yᵀLs / (k³·|Ω|^{4/3}).
 * Like the paper's, that β is not dimensionless (it scales with the mesh's length unit:
 * the paper's meshes are of unit size); blend_scale adjusts it, and blend = sobolev,
 * lbfgs or fixed pins it. Objectives without characteristic scales: k = |Ω| = 1.
 * Parameters (solver.bcqn.*): history m = 5 (the paper's), blend, beta, blend_scale.
 * Differences from the paper: (a) pairs with sᵀŷ ≤ 1e-10‖s‖‖ŷ‖ are skipped (lbfgs_memory.h)
 * where the authors' code clamps |sᵀy| below at 1e-8; (b) the "curing" of the DIRECTION
 * in the authors' code (lcp_solve: a few projected-Jacobi sweeps on the LCP that keeps the
 * linearized per-element volumes non-negative, p ← p + Jλ when still a descent direction)
 * is not implemented: the filter alone guards the iterates; (c) L is the step objective's
 * PD matrix (mass + material-weighted Laplacian), not the bare cotangent Laplacian; where
 * the objective has none, ∇²g(x₀) with the Hessian fix's projection (pd_factor.h), and
 * L s uses that matrix; (d) the paper's other stopping tests (‖Δx‖, |Δg| for 5
 * iterations) are not used; convergence is solver.stop (eo_solver_stop_check, the metric
 * gradient measure by default).
 * If p is not a descent direction (rounding), the memory is cleared and p = −L⁻¹∇g
 * (res.n_fallback). All storage is allocated in setup. */
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "lbfgs_memory.h"
#include "pd_factor.h"

/// Blended cured quasi-Newton, BCQN (config `solver.bcqn.*`; Zhu, Bridson & Kaufman 2018;
/// solvers/optim/bcqn.c has the algorithm): L-BFGS with H⁰ = L⁻¹ (the objective's
/// constant matrix, the Sobolev proxy) and each stored y blended toward L s.
typedef struct eo_bcqn_params {
    int history;         ///< stored (s, y) pairs m (default 5, the paper's)
    char blend[16];      ///< "adaptive" (the paper's β, eq. 13), "sobolev" (β = 1: the
                         ///< preconditioned gradient p = −L⁻¹∇g), "lbfgs" (β = 0: L-BFGS with
                         ///< H⁰ = L⁻¹) or "fixed" (β = beta) (default adaptive)
    double beta;         ///< fixed: the blend weight β ∈ [0, 1] (default 0.5)
    double blend_scale;  ///< adaptive: factor on the paper's β before the clamp (default 1)
} eo_bcqn_params;

typedef struct bcqn_state {
    eo_descent_ws w;
    int m, n;
    eo_lbfgs_memory mem;
    double *store;      /* the memory's storage, then s, ls, q, t */
    double *s, *ls;     /* n each: the step and L s (then ŷ) */
    double *q, *t;      /* n each: the first loop's vector; power-iteration scratch */
    eo_pd_factor L;     /* L⁻¹ */
    const eo_csc *Lmat; /* L for L s (borrowed for the minimization) */
    const eo_csc *norm_of; /* matrix and version ‖L‖ was computed for */
    unsigned long norm_ver;
    double Lnorm;       /* ‖L‖₂ */
    double bscale;      /* 1 / (k³ |Ω|^{4/3}) · blend_scale */
    int mode;           /* 0 adaptive, 1 sobolev, 2 lbfgs, 3 fixed */
    double beta_sum;    /* Σ β over the pairs of this minimization (eo_bcqn_beta_mean) */
    long beta_n;
} bcqn_state;

static const char *const blend_choices[] = {"adaptive", "sobolev", "lbfgs", "fixed", NULL};

static const eo_param_desc bcqn_desc[] = {
    {.key = "history", .kind = EO_PARAM_INT, .offset = offsetof(eo_bcqn_params, history), .def.i = 5, .min = 1,
     .max = 1000, .range = EO_RANGE_CLOSED, .help = "stored (s, y) pairs m (the paper: 5)"},
    {.key = "blend", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_bcqn_params, blend),
     .size = sizeof(((eo_bcqn_params *)0)->blend), .def.s = "adaptive", .choices = blend_choices,
     .help = "blend weight of y toward L s: adaptive (the paper's beta = clamp(|L| y'Ls / (k^3 |Omega|^(4/3)))), "
             "sobolev (beta = 1: p = -L^-1 grad), lbfgs (beta = 0: L-BFGS with H0 = L^-1), fixed (beta)"},
    {.key = "beta", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_bcqn_params, beta), .def.d = 0.5, .min = 0,
     .max = 1, .range = EO_RANGE_CLOSED, .help = "blend = fixed: the weight beta"},
    {.key = "blend_scale", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_bcqn_params, blend_scale), .def.d = 1,
     .min = 0, .range = EO_RANGE_MIN, .help = "blend = adaptive: factor on the paper's beta before the clamp"},
    {0},
};

static void bcqn_free(bcqn_state *st, eo_ctx *ctx)
{
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->store);
    st->store = NULL;
    eo_pd_factor_deinit(ctx, &st->L);
}

static int bcqn_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    bcqn_state *st = vst;
    eo_bcqn_params def;
    const eo_bcqn_params *pp = params;
    if (!pp) {
        eo_params_default(bcqn_desc, &def);
        pp = &def;
    }
    bcqn_free(st, ctx);
    memset(st, 0, sizeof *st);
    int rc = eo_descent_ws_init(ctx, n, &st->w);
    if (rc < 0) return rc;
    const size_t nn = (size_t)(n > 0 ? n : 1), mem = eo_lbfgs_memory_size(n, pp->history);
    st->store = eo_calloc(ctx, mem + 4 * nn, sizeof(double));
    if (!st->store) return eo_error(ctx, EO_ERR_NOMEM, "bcqn: out of memory (n = %d, m = %d)", n, pp->history);
    eo_lbfgs_memory_bind(&st->mem, n, pp->history, st->store);
    st->s = st->store + mem;
    st->ls = st->s + nn;
    st->q = st->ls + nn;
    st->t = st->q + nn;
    st->m = pp->history;
    st->n = n;
    return eo_pd_factor_init(ctx, n, "bcqn", &st->L);
}

static void bcqn_destroy(void *vst, eo_ctx *ctx) { bcqn_free(vst, ctx); }

/* ‖A‖₂ of a symmetric (upper-triangle CSC) A by power iteration (to ~1e-3, at most 30
 * products: the authors' code takes MATLAB's normest, tolerance 1e-6); v, t scratch (n) */
static double sym_norm(const eo_csc *A, double *v, double *t)
{
    const int n = A->n;
    for (int i = 0; i < n; i++) v[i] = 1 + 0.1 * (i % 7);
    double lam = 0;
    for (int it = 0; it < 30; it++) { /* a few digits are plenty for β */
        double vn = eo_norm2(n, v);
        if (!(vn > 0)) return 0;
        for (int i = 0; i < n; i++) v[i] /= vn;
        eo_csc_symv(A, v, t);
        const double l = eo_norm2(n, t);
        memcpy(v, t, (size_t)n * sizeof(double));
        if (fabs(l - lam) <= 1e-3 * l) return l;
        lam = l;
    }
    return lam;
}

static int bcqn_begin(void *vst, const void *params, const eo_solver_ctx *sc, const double *x, double g,
                      const double *grad, eo_solve_result *res)
{
    bcqn_state *st = vst;
    const eo_bcqn_params *pp = params;
    (void)g, (void)grad;
    if (pp->history != st->m)
        return eo_error(sc->ctx, EO_ERR_INVALID, "bcqn: set up for history %d, called with %d", st->m, pp->history);
    st->mode = strcmp(pp->blend, "sobolev") == 0 ? 1 : strcmp(pp->blend, "lbfgs") == 0 ? 2
             : strcmp(pp->blend, "fixed") == 0   ? 3
                                                 : 0;
    st->beta_sum = 0;
    st->beta_n = 0;
    eo_lbfgs_memory_clear(&st->mem);
    int rc = eo_pd_factor_prepare(&st->L, sc, x, res);
    if (rc < 0) return rc;
    /* L for the products L s: the objective's constant matrix, else the own copy (∇²g(x₀)) */
    eo_csc *L = NULL;
    unsigned long ver = 0;
    rc = eo_objective_constant_hessian(sc->obj, &L, &ver);
    if (rc < 0 && rc != EO_ERR_UNSUPPORTED) return rc;
    if (rc < 0) {
        L = st->L.A;
        ver = 0;
        st->norm_of = NULL; /* a new matrix at each minimization */
    }
    st->Lmat = L && L->n == st->n ? L : NULL;
    if (st->Lmat && (st->norm_of != st->Lmat || st->norm_ver != ver)) {
        st->Lnorm = sym_norm(st->Lmat, st->q, st->t);
        st->norm_of = st->Lmat;
        st->norm_ver = ver;
    }
    eo_objective_characteristic ch;
    double k = 1, vol = 1;
    if (eo_objective_characteristic_get(sc->obj, &ch) >= 0 && ch.stiffness > 0 && ch.volume > 0 &&
        isfinite(ch.stiffness) && isfinite(ch.volume)) {
        k = ch.stiffness;
        vol = ch.volume;
    }
    st->bscale = pp->blend_scale / (k * k * k * pow(vol, 4.0 / 3.0));
    return EO_OK;
}

/* p = −L⁻¹ v (v, p distinct). Returns a negative reason or 0. */
static int sobolev(bcqn_state *st, const eo_solver_ctx *sc, const double *v, double *p, eo_solve_result *res)
{
    int reason = eo_pd_factor_solve(&st->L, sc, v, p, res);
    if (reason) return reason;
    for (int i = 0; i < st->n; i++) p[i] = -p[i];
    return 0;
}

static int bcqn_direction(void *vst, const void *params, const eo_solver_ctx *sc, const double *x, double g,
                          const double *grad, double *p, eo_direction_out *out, eo_solve_result *res)
{
    bcqn_state *st = vst;
    eo_lbfgs_memory *h = &st->mem;
    const int n = st->n;
    (void)params, (void)x, (void)g;
    out->alpha0 = 1;
    out->shift = st->L.shift;
    if (!st->L.factored) {
        out->reason = st->L.fail_reason ? st->L.fail_reason : EO_DIVERGED_LINSOLVE;
        return EO_OK;
    }
    if (h->count == 0) {
        out->reason = sobolev(st, sc, grad, p, res);
        return EO_OK;
    }
    double *q = st->q;
    memcpy(q, grad, (size_t)n * sizeof(double));
    eo_lbfgs_memory_first_loop(h, q);
    int reason = eo_pd_factor_solve(&st->L, sc, q, p, res); /* r = L⁻¹ q */
    if (reason) {
        out->reason = reason;
        return EO_OK;
    }
    eo_lbfgs_memory_second_loop(h, p);
    for (int i = 0; i < n; i++) p[i] = -p[i];
    if (!eo_is_descent(NULL, n, grad, p)) {
        eo_lbfgs_memory_clear(h);
        res->n_fallback++;
        out->reason = sobolev(st, sc, grad, p, res);
    }
    return EO_OK;
}

static void bcqn_accepted(void *vst, const void *params, const double *x, const double *x_new, const double *grad,
                          const double *grad_new, const double *p, double alpha)
{
    bcqn_state *st = vst;
    const eo_bcqn_params *pp = params;
    const int n = st->n;
    (void)p, (void)alpha;
    double *s = st->s, *y = st->q, *ls = st->ls;
    for (int i = 0; i < n; i++) {
        s[i] = x_new[i] - x[i];
        y[i] = grad_new[i] - grad[i];
    }
    double beta = 0;
    if (st->mode == 1) beta = 1;
    else if (st->mode == 3) beta = pp->beta;
    if (st->Lmat && beta != 0) eo_csc_symv(st->Lmat, s, ls);
    if (st->mode == 0 && st->Lmat) {
        eo_csc_symv(st->Lmat, s, ls);
        const double b = st->Lnorm * eo_dot(n, y, ls) * st->bscale;
        beta = isfinite(b) ? (b < 0 ? 0 : b > 1 ? 1 : b) : 0;
    }
    if (!st->Lmat) beta = 0;
    st->beta_sum += beta;
    st->beta_n++;
    if (beta > 0)
        for (int i = 0; i < n; i++) y[i] = (1 - beta) * y[i] + beta * ls[i];
    eo_lbfgs_memory_push_pair(&st->mem, s, y);
}

static const eo_descent_ops bcqn_ops = {
    .begin = bcqn_begin,
    .direction = bcqn_direction,
    .accepted = bcqn_accepted,
    .ls_c2 = 0.9,
};

static int bcqn_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    bcqn_state *st = vst;
    eo_bcqn_params def;
    if (!params) {
        eo_params_default(bcqn_desc, &def);
        params = &def;
    }
    return eo_descent_minimize(&bcqn_ops, st, params, sc, &st->w, x, res);
}

const eo_optimizer_type eo_optimizer_bcqn = {
    .info = {.name = "bcqn",
             .summary = "blended cured quasi-Newton (Zhu, Bridson & Kaufman 2018): L-BFGS with H0 = L^-1 and secants "
                        "blended toward L s; barrier_filter line search",
             .params = bcqn_desc,
             .params_size = sizeof(eo_bcqn_params)},
    .state_size = sizeof(bcqn_state),
    .needs_linear = 1,
    .needs_hessian = 0,
    .linesearch = "barrier_filter",
    .setup = bcqn_setup,
    .minimize = bcqn_minimize,
    .destroy = bcqn_destroy,
};
