/* Limited-memory BFGS (registry key "lbfgs").
 *
 * Keeps the last m pairs s_i = x_{i+1} − x_i, y_i = ∇g_{i+1} − ∇g_i (ρ_i = 1/y_iᵀs_i) and
 * applies the inverse-Hessian approximation H_k to ∇g by the two-loop recursion
 * (Nocedal & Wright, Numerical Optimization, Alg. 7.4):
 *     q = ∇g;  for i = newest … oldest:  a_i = ρ_i s_iᵀq,  q −= a_i y_i
 *     r = H⁰ q,  H⁰ = γ D⁻¹,  γ = sᵀy / yᵀD⁻¹y of the newest pair
 *                  (D = I: γ = sᵀy/yᵀy; D = the objective's metric, the lumped mass,
 *                   when `scaled` and available)
 *     for i = oldest … newest:  b = ρ_i y_iᵀr,  r += s_i (a_i − b)
 *     p = −r,  line search with first trial α = 1.
 * Without pairs (first iteration, after a reset) p = −D⁻¹∇g·min(1, 1/‖D⁻¹∇g‖_∞).
 * A pair is skipped when sᵀy ≤ 1e-10·‖s‖‖y‖ (keeps H_k positive definite on non-convex
 * g). If p is still not a descent direction (rounding), the memory is cleared and the
 * scaled steepest-descent direction used (counted in res.n_fallback).
 * The reported decrement −∇gᵀp/2 = ∇gᵀH_k∇g/2 is a quasi-Newton estimate of g − g*.
 * All storage (2m vectors of n) is allocated in setup. */
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "lbfgs_memory.h"

typedef struct lbfgs_state {
    eo_descent_ws w;
    int m, n;
    eo_lbfgs_memory mem;
    double *store;      /* the memory's storage, then dinv */
    double *dinv;       /* n */
    eo_ctx *ctx;
} lbfgs_state;

static const eo_param_desc lbfgs_desc[] = {
    {.key = "history", .kind = EO_PARAM_INT, .offset = offsetof(eo_lbfgs_params, history),
     .def.i = 8, .min = 1, .max = 1000, .range = EO_RANGE_CLOSED, .help = "stored (s, y) pairs m"},
    {.key = "scaled", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_lbfgs_params, scaled), .def.i = 1,
     .help = "initial inverse Hessian gamma*D^-1 with D the objective's metric (lumped mass)"},
    {0},
};

static void lbfgs_free(lbfgs_state *st, eo_ctx *ctx)
{
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->store);
    st->store = NULL;
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
    st->store = eo_calloc(ctx, mem + nn, sizeof(double));
    if (!st->store) return eo_error(ctx, EO_ERR_NOMEM, "lbfgs: out of memory (n = %d, m = %zu)", n, m);
    eo_lbfgs_memory_bind(&st->mem, n, (int)m, st->store);
    st->dinv = st->store + mem;
    st->m = (int)m;
    st->n = n;
    return EO_OK;
}

static void lbfgs_destroy(void *vst, eo_ctx *ctx) { lbfgs_free(vst, ctx); }

static int lbfgs_begin(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                       double g, const double *grad, eo_solve_result *res)
{
    lbfgs_state *st = vst;
    const eo_lbfgs_params *pp = params;
    (void)x, (void)g, (void)grad, (void)res;
    if (pp->history != st->m)
        return eo_error(sc->ctx, EO_ERR_INVALID, "lbfgs: set up for history %d, called with %d",
                        st->m, pp->history);
    if (pp->scaled) eo_descent_metric(sc, st->dinv);
    else
        for (int i = 0; i < st->n; i++) st->dinv[i] = 1;
    for (int i = 0; i < st->n; i++) st->dinv[i] = 1 / st->dinv[i];
    eo_lbfgs_memory_clear(&st->mem);
    return EO_OK;
}

static void scaled_gradient(const lbfgs_state *st, const double *grad, double *p)
{
    for (int i = 0; i < st->n; i++) p[i] = -st->dinv[i] * grad[i];
    double m = eo_norm_inf(st->n, p);
    if (m > 1)
        for (int i = 0; i < st->n; i++) p[i] /= m;
}

static int lbfgs_direction(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                           double g, const double *grad, double *p, eo_direction_out *out,
                           eo_solve_result *res)
{
    lbfgs_state *st = vst;
    eo_lbfgs_memory *h = &st->mem;
    const int n = st->n;
    (void)params, (void)sc, (void)x, (void)g;
    out->alpha0 = 1;
    if (h->count == 0) {
        scaled_gradient(st, grad, p);
        return EO_OK;
    }
    double *q = p;
    for (int i = 0; i < n; i++) q[i] = grad[i];
    eo_lbfgs_memory_first_loop(h, q);
    /* H⁰ = γ D⁻¹ with γ = sᵀy / yᵀD⁻¹y of the newest pair */
    const double *y = h->Y + (size_t)eo_lbfgs_memory_slot(h, 0) * n;
    double ydy = 0;
    for (int i = 0; i < n; i++) ydy += y[i] * st->dinv[i] * y[i];
    double gamma = 1 / (h->rho[eo_lbfgs_memory_slot(h, 0)] * ydy);
    for (int i = 0; i < n; i++) q[i] *= gamma * st->dinv[i];
    eo_lbfgs_memory_second_loop(h, q);
    for (int i = 0; i < n; i++) p[i] = -q[i];
    if (!eo_is_descent(n, grad, p)) {
        eo_lbfgs_memory_clear(h);
        res->n_fallback++;
        scaled_gradient(st, grad, p);
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
             .summary = "limited-memory BFGS (two-loop recursion, metric-scaled initial matrix)",
             .params = lbfgs_desc,
             .params_size = sizeof(eo_lbfgs_params)},
    .state_size = sizeof(lbfgs_state),
    .needs_linear = 0,
    .needs_hessian = 0,
    .setup = lbfgs_setup,
    .minimize = lbfgs_minimize,
    .destroy = lbfgs_destroy,
};
