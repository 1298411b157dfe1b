/* Gradient descent, optionally scaled by a diagonal metric (registry key
 * "gradient_descent").
 *
 * Direction     p = −D⁻¹∇g, D = the objective's metric_diag (the lumped mass of the step
 *               objective) when `scaled` and available with every entry finite and > 0,
 *               else D = I (002 §3.2.2: d = −∇g). For g = ½‖x − x̃‖²_M + …, D = M makes
 *               the inertia part perfectly conditioned.
 * Step          x ← x + αp by the configured line search from the first trial α₀:
 *                 k = 0:  α₀ = min(1, 1/‖D⁻¹∇g‖_∞)  (at most a unit move per variable);
 *                 k > 0:  "bb"     α₀ = sᵀDs / sᵀy  (Barzilai–Borwein in the metric D,
 *                                  s = x_k − x_{k−1}, y = ∇g_k − ∇g_{k−1}; it equals 1/c
 *                                  when ∇²g = cD), or 2·α_{k−1} when sᵀy ≤ 0;
 *                         "double" α₀ = 2·α_{k−1}.
 *               α₀ is kept in [1e-30, 1e30].
 * Decrement     reported as −α₀∇gᵀp/2 = α₀∇gᵀD⁻¹∇g/2: the decrease of the quadratic model
 *               with Hessian D/α₀, so newton_decrement with this optimizer is only an
 *               estimate of g − g* (exact only when ∇²g = D/α₀).
 * With the exact line search on ½(x₁² + γx₂²) from (γ, 1), D = I, this reproduces the
 * notes' iterates x₁ᵏ = γ((γ−1)/(γ+1))ᵏ, x₂ᵏ = (−(γ−1)/(γ+1))ᵏ (002 Example 2). */
#include <stddef.h>
#include <string.h>

#include "descent.h"

/// Gradient descent (config `solver.gradient_descent.*`).
typedef struct eo_gradient_descent_params {
    int scaled;          ///< p = −D⁻¹∇g with D = objective metric (lumped mass) (true)
    char alpha0[16];     ///< first trial step after the first iteration: "bb" (Barzilai–
                         ///< Borwein, α₀ = sᵀDs/sᵀy) or "double" (2·α_prev) (default "bb")
} eo_gradient_descent_params;

typedef struct gd_state {
    eo_descent_ws w;
    double *dinv;       /* n: 1/D */
    double alpha_next;  /* first trial of the next iteration, NAN = first iteration */
    eo_ctx *ctx;
} gd_state;

static const char *const alpha0_choices[] = {"bb", "double", NULL};

static const eo_param_desc gd_desc[] = {
    {.key = "scaled", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_gradient_descent_params, scaled),
     .def.i = 1, .help = "scale by the inverse of the objective's diagonal metric (lumped mass)"},
    {.key = "alpha0", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_gradient_descent_params, alpha0),
     .size = sizeof(((eo_gradient_descent_params *)0)->alpha0), .def.s = "bb",
     .choices = alpha0_choices,
     .help = "first trial step: bb (Barzilai-Borwein) or double (2 x previous step)"},
    {0},
};

static int gd_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    gd_state *st = vst;
    (void)params;
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->dinv);
    memset(st, 0, sizeof *st);
    st->ctx = ctx;
    int rc = eo_descent_ws_init(ctx, n, &st->w);
    if (rc < 0) return rc;
    st->dinv = eo_calloc(ctx, (size_t)(n > 0 ? n : 1), sizeof(double));
    if (!st->dinv) return eo_error(ctx, EO_ERR_NOMEM, "gradient_descent: out of memory");
    return EO_OK;
}

static void gd_destroy(void *vst, eo_ctx *ctx)
{
    gd_state *st = vst;
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->dinv);
    st->dinv = NULL;
}

static int gd_begin(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                    double g, const double *grad, eo_solve_result *res)
{
    gd_state *st = vst;
    const eo_gradient_descent_params *pp = params;
    const int n = sc->obj->n;
    (void)x, (void)g, (void)grad, (void)res;
    if (pp->scaled) eo_descent_metric(sc, st->dinv);
    else
        for (int i = 0; i < n; i++) st->dinv[i] = 1;
    for (int i = 0; i < n; i++) st->dinv[i] = 1 / st->dinv[i];
    st->alpha_next = NAN;
    return EO_OK;
}

static double clamp_alpha(double a)
{
    if (!(a >= 1e-30)) return 1e-30;
    return a > 1e30 ? 1e30 : a;
}

static int gd_direction(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                        double g, const double *grad, double *p, eo_direction_out *out,
                        eo_solve_result *res)
{
    gd_state *st = vst;
    const int n = sc->obj->n;
    (void)params, (void)x, (void)g, (void)res;
    for (int i = 0; i < n; i++) p[i] = -st->dinv[i] * grad[i];
    if (isnan(st->alpha_next)) {
        double m = eo_norm_inf(n, p);
        out->alpha0 = m > 1 ? 1 / m : 1;
    } else {
        out->alpha0 = st->alpha_next;
    }
    out->alpha0 = clamp_alpha(out->alpha0);
    return EO_OK;
}

static void gd_accepted(void *vst, const void *params, const double *x, const double *x_new,
                        const double *grad, const double *grad_new, const double *p, double alpha)
{
    gd_state *st = vst;
    const eo_gradient_descent_params *pp = params;
    const int n = st->w.n;
    (void)p;
    double next = 2 * alpha;
    if (strcmp(pp->alpha0, "bb") == 0) {
        double sds = 0, sy = 0;
        for (int i = 0; i < n; i++) {
            double s = x_new[i] - x[i];
            sds += s * s / st->dinv[i];
            sy += s * (grad_new[i] - grad[i]);
        }
        if (sy > 0 && isfinite(sds / sy)) next = sds / sy;
    }
    st->alpha_next = clamp_alpha(next);
}

static const eo_descent_ops gd_ops = {
    .begin = gd_begin,
    .direction = gd_direction,
    .accepted = gd_accepted,
};

static int gd_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                       eo_solve_result *res)
{
    gd_state *st = vst;
    eo_gradient_descent_params def;
    if (!params) {
        eo_params_default(gd_desc, &def);
        params = &def;
    }
    return eo_descent_minimize(&gd_ops, st, params, sc, &st->w, x, res);
}

const eo_optimizer_type eo_optimizer_gradient_descent = {
    .info = {.name = "gradient_descent",
             .summary = "(metric-scaled) gradient descent p = -D^-1 grad, Barzilai-Borwein first trial",
             .params = gd_desc,
             .params_size = sizeof(eo_gradient_descent_params)},
    .state_size = sizeof(gd_state),
    .needs_linear = 0,
    .needs_hessian = 0,
    .setup = gd_setup,
    .minimize = gd_minimize,
    .destroy = gd_destroy,
};
