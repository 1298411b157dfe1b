/* Limited-memory BFGS (registry key "lbfgs").
 *
 * Keeps the last m pairs s_i = x_{i+1} − x_i, y_i = ∇g_{i+1} − ∇g_i (ρ_i = 1/y_iᵀs_i) and
 * applies the inverse-Hessian approximation H_k to ∇g by the two-loop recursion
 * (Nocedal & Wright, Numerical Optimization, Alg. 7.4):
 *     q = ∇g;  for i = newest … oldest:  a_i = ρ_i s_iᵀq,  q −= a_i y_i
 *     r = H⁰ q   (solver.lbfgs.h0; the default `auto` is pd where the objective has a
 *                 constant matrix L — every step problem — and lumped_mass elsewhere):
 *        scaled_identity  H⁰ = γI,    γ = sᵀy / yᵀy of the newest pair (N&W eq. 7.20)
 *        lumped_mass      H⁰ = γD⁻¹,  γ = sᵀy / yᵀD⁻¹y, D = the objective's metric (the
 *                         lumped mass; identity if the objective has none)
 *        pd               H⁰ = L⁻¹, L the objective's constant_hessian (the projective-
 *                         dynamics matrix) factored once (pd_factor.h: the objective's own
 *                         factor with a CHOLMOD solver.linear, else solver.linear;
 *                         ∇²g(x₀) with the Hessian fix's projection if there is none):
 *                         Liu, Bouaziz & Kavan 2017 §5, as projective_dynamics with
 *                         lbfgs_history = m. Not scaled between iterations, as
 *                         in Liu et al.'s code: γ·L⁻¹ with γ = sᵀy/sᵀLs (≤ 1 here, L being
 *                         stiffer than ∇²g in bending) took 3515 instead of 75 iterations
 *                         to relative energy error 1e-6 on the standard suite's
 *                         cantilever-1e9-5k-snh.
 *     for i = oldest … newest:  b = ρ_i y_iᵀr,  r += s_i (a_i − b)
 *     p = −r,  line search with first trial α = 1.
 * Without pairs (first iteration, after a reset) p = −H⁰∇g with H⁰ = D⁻¹ (D = I for
 * scaled_identity) scaled by min(1, 1/‖D⁻¹∇g‖_∞), or p = −L⁻¹∇g for pd.
 * Line search: set solver.linesearch = wolfe (strong Wolfe, c2 = 0.9 by default for this
 * optimizer, and ∇g of the accepted point comes back with it: one value+gradient call
 * per trial and no extra call after acceptance; N&W §7.2 use it with L-BFGS). With
 * backtracking (the solver-wide default, Armijo only) every accepted step costs one
 * more gradient call and sᵀy > 0 is not guaranteed (pairs are skipped instead).
 * A pair is skipped when sᵀy ≤ 1e-10·‖s‖‖y‖ (keeps H_k positive definite on non-convex
 * g). If p is still not a descent direction (rounding), the memory is cleared and the
 * scaled steepest-descent direction used (counted in res.n_fallback).
 * The reported decrement −∇gᵀp/2 = ∇gᵀH_k∇g/2 is a quasi-Newton estimate of g − g*.
 * All storage (2m vectors of n) is allocated in setup. */
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "lbfgs_memory.h"
#include "pd_factor.h"

/// L-BFGS (config `solver.lbfgs.*`).
typedef struct eo_lbfgs_params {
    int history;         ///< stored pairs m (default 8)
    char h0[16];         ///< initial inverse Hessian: "scaled_identity" (γI), "lumped_mass"
                         ///< (γD⁻¹, D = objective metric), "pd" (L⁻¹, L the objective's
                         ///< constant_hessian factored once, pd_factor.h) or "auto" (pd where
                         ///< the objective has constant_hessian, else lumped_mass) (default auto)
} eo_lbfgs_params;

typedef struct lbfgs_state {
    eo_descent_ws w;
    int m, n;
    eo_lbfgs_memory mem;
    double *store;      /* the memory's storage, then dinv */
    double *dinv;       /* n */
    double *q;          /* n: the first loop's vector */
    int pd;             /* h0 = pd */
    eo_pd_factor L;     /* h0 = pd: the factored matrix */
    eo_ctx *ctx;
    const eo_vspace *vs; /* the objective's vector space of this minimization */
} lbfgs_state;

static const char *const h0_choices[] = {"auto", "scaled_identity", "lumped_mass", "pd", NULL};

static const eo_param_desc lbfgs_desc[] = {
    {.key = "history", .kind = EO_PARAM_INT, .offset = offsetof(eo_lbfgs_params, history),
     .def.i = 8, .min = 1, .max = 1000, .range = EO_RANGE_CLOSED, .help = "stored (s, y) pairs m"},
    {.key = "h0", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_lbfgs_params, h0),
     .size = sizeof(((eo_lbfgs_params *)0)->h0), .def.s = "auto", .choices = h0_choices,
     .help = "initial inverse Hessian: auto (pd if the objective has a constant PD matrix, as every step "
             "problem, else lumped_mass), scaled_identity (gamma*I), lumped_mass (gamma*D^-1), pd (L^-1, the PD "
             "matrix factored once)"},
    {0},
};

static void lbfgs_free(lbfgs_state *st, eo_ctx *ctx)
{
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->store);
    st->store = NULL;
    eo_pd_factor_deinit(ctx, &st->L);
}

static int lbfgs_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    lbfgs_state *st = vst;
    eo_lbfgs_params def;
    const eo_lbfgs_params *pp = params;
    if (!pp) {
        eo_params_default(lbfgs_desc, &def);
        pp = &def;
    }
    lbfgs_free(st, ctx);
    memset(st, 0, sizeof *st);
    st->ctx = ctx;
    int rc = eo_descent_ws_init(ctx, n, &st->w);
    if (rc < 0) return rc;
    size_t m = (size_t)pp->history, nn = (size_t)(n > 0 ? n : 1);
    size_t mem = eo_lbfgs_memory_size(n, (int)m);
    st->store = eo_calloc(ctx, mem + 2 * nn, sizeof(double));
    if (!st->store) return eo_error(ctx, EO_ERR_NOMEM, "lbfgs: out of memory (n = %d, m = %zu)", n, m);
    eo_lbfgs_memory_bind(&st->mem, n, (int)m, st->store);
    st->dinv = st->store + mem;
    st->q = st->dinv + nn;
    st->m = (int)m;
    st->n = n;
    return eo_pd_factor_init(ctx, n, "lbfgs", &st->L);
}

static void lbfgs_destroy(void *vst, eo_ctx *ctx) { lbfgs_free(vst, ctx); }

static int lbfgs_begin(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                       double g, const double *grad, eo_solve_result *res)
{
    lbfgs_state *st = vst;
    const eo_lbfgs_params *pp = params;
    (void)g, (void)grad;
    if (pp->history != st->m)
        return eo_error(sc->ctx, EO_ERR_INVALID, "lbfgs: set up for history %d, called with %d",
                        st->m, pp->history);
    const int autom = strcmp(pp->h0, "auto") == 0;
    st->pd = strcmp(pp->h0, "pd") == 0 || (autom && sc->obj->ops->constant_hessian);
    if (strcmp(pp->h0, "lumped_mass") == 0 || (autom && !st->pd)) eo_descent_metric(sc, st->dinv);
    else
        for (int i = 0; i < st->n; i++) st->dinv[i] = 1;
    for (int i = 0; i < st->n; i++) st->dinv[i] = 1 / st->dinv[i];
    eo_lbfgs_memory_clear(&st->mem);
    st->mem.vs = st->vs = sc->obj->space;
    return st->pd ? eo_pd_factor_prepare(&st->L, sc, x, res) : EO_OK;
}

static void scaled_gradient(const lbfgs_state *st, const double *grad, double *p)
{
    for (int i = 0; i < st->n; i++) p[i] = -st->dinv[i] * grad[i];
    double m = eo_vnorm_inf(st->vs, st->n, p);
    if (m > 1)
        for (int i = 0; i < st->n; i++) p[i] /= m;
}

/* p = −H⁰v (v and p distinct for pd). Returns a negative reason or 0. */
static int apply_h0(lbfgs_state *st, const eo_solver_ctx *sc, const double *v, double *p,
                    eo_solve_result *res)
{
    if (st->pd) {
        int reason = eo_pd_factor_solve(&st->L, sc, v, p, res);
        if (reason) return reason;
        for (int i = 0; i < st->n; i++) p[i] = -p[i];
        return 0;
    }
    scaled_gradient(st, v, p);
    return 0;
}

static int lbfgs_direction(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                           double g, const double *grad, double *p, eo_direction_out *out,
                           eo_solve_result *res)
{
    lbfgs_state *st = vst;
    eo_lbfgs_memory *h = &st->mem;
    const int n = st->n;
    (void)params, (void)x, (void)g;
    out->alpha0 = 1;
    if (st->pd) {
        out->shift = st->L.shift;
        if (!st->L.factored) {
            out->reason = st->L.fail_reason ? st->L.fail_reason : EO_DIVERGED_LINSOLVE;
            return EO_OK;
        }
    }
    if (h->count == 0) {
        out->reason = apply_h0(st, sc, grad, p, res);
        return EO_OK;
    }
    double *q = st->q;
    for (int i = 0; i < n; i++) q[i] = grad[i];
    eo_lbfgs_memory_first_loop(h, q);
    if (st->pd) {
        int reason = eo_pd_factor_solve(&st->L, sc, q, p, res); /* r = L⁻¹ q */
        if (reason) {
            out->reason = reason;
            return EO_OK;
        }
    } else {
        /* H⁰ = γ D⁻¹ with γ = sᵀy / yᵀD⁻¹y of the newest pair */
        const double *y = h->Y + (size_t)eo_lbfgs_memory_slot(h, 0) * n;
        double ydy = 0;
        for (int i = 0; i < n; i++)
            if (!st->vs || st->vs->own[i]) ydy += y[i] * st->dinv[i] * y[i];
        eo_vreduce(st->vs, &ydy, 1, EO_REDUCE_SUM);
        double gamma = 1 / (h->rho[eo_lbfgs_memory_slot(h, 0)] * ydy);
        for (int i = 0; i < n; i++) p[i] = q[i] * gamma * st->dinv[i];
    }
    eo_lbfgs_memory_second_loop(h, p);
    for (int i = 0; i < n; i++) p[i] = -p[i];
    if (!eo_is_descent(st->vs, n, grad, p)) {
        eo_lbfgs_memory_clear(h);
        res->n_fallback++;
        out->reason = apply_h0(st, sc, grad, p, res);
    }
    return EO_OK;
}

static void lbfgs_accepted(void *vst, const void *params, const double *x, const double *x_new,
                           const double *grad, const double *grad_new, const double *p, double alpha)
{
    lbfgs_state *st = vst;
    (void)params, (void)p, (void)alpha;
    eo_lbfgs_memory_push(&st->mem, x, x_new, grad, grad_new);
}
static const eo_descent_ops lbfgs_ops = {
    .begin = lbfgs_begin,
    .direction = lbfgs_direction,
    .accepted = lbfgs_accepted,
    .ls_c2 = 0.9,
};

static int lbfgs_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                          eo_solve_result *res)
{
    lbfgs_state *st = vst;
    eo_lbfgs_params def;
    if (!params) {
        eo_params_default(lbfgs_desc, &def);
        params = &def;
    }
    return eo_descent_minimize(&lbfgs_ops, st, params, sc, &st->w, x, res);
}

const eo_optimizer_type eo_optimizer_lbfgs = {
    .info = {.name = "lbfgs",
             .summary = "limited-memory BFGS (two-loop recursion; initial matrix scaled identity, "
                        "lumped mass or the PD matrix); use with linesearch wolfe",
             .params = lbfgs_desc,
             .params_size = sizeof(eo_lbfgs_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(lbfgs_state),
    .needs_linear = 1, /* only with h0 = pd */
    .needs_hessian = 0,
    .linesearch = "wolfe",
    .setup = lbfgs_setup,
    .minimize = lbfgs_minimize,
    .destroy = lbfgs_destroy,
};
