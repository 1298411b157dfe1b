/* Backtracking line search with the Armijo condition (registry key "backtracking").
 *
 * φ(α) = g(x + αp), φ(0) = g0, φ'(0) = ∇gᵀp = dg0 < 0. Trials α = α₀, shrink·α₀,
 * shrink²·α₀, … until the sufficient-decrease (Armijo) condition
 *     φ(α) ≤ φ(0) + c1·α·φ'(0)
 * holds with φ(α) finite — or, at rounding level (when the predicted decrease
 * α|φ'(0)| is below 100·ε_g, ε_g = 4·ε_mach·|φ(0)|), φ(α) ≤ φ(0) + ε_g: there the
 * Armijo test would compare rounding noise and fail near every minimizer whose g* ≠ 0
 * (as in Hager & Zhang's approximate Wolfe conditions).
 *
 * Directional-derivative test at rounding level (when the caller passes extra, as the
 * descent loop does): in that regime the trial is evaluated with its gradient and also
 * accepted when
 *     φ'(α) ≤ (1 − 2·c1)·|φ'(0)|   and   φ(α) ≤ φ(0) + 100·ε_g,
 * Hager & Zhang's approximate Armijo condition (2005, eq. 4.1 with δ = c1): on a
 * quadratic φ it is equivalent to the Armijo test, but it is computed from ∇g without
 * the cancellation of φ(α) − φ(0). The gradient is handed back (extra->have_grad), so
 * the trial costs the loop nothing extra. Measured on the static cantilever (E = 1e7,
 * stable neo-Hookean, relative_decrement to 1e-10): the value-only test rejected the
 * full Newton step in 33 of 47 iterations once λ²/2 < ε|g| (α down to 1e-7 on steps the
 * derivative shows are right; g there wanders by ±5ε|g| with every evaluation, more than
 * ε_g); with the derivative test 17, every step after the first a full one (12–13
 * with no line search: there the first full step, which raises g from 4.9 to 10.8 — a
 * real increase, rejected by any monotone search — lands nearer the solution). A trial where g is +∞ (outside the domain of a barrier
 * material, an inverted element) or NaN is rejected like a too-long step. When the caller
 * expects the first trial to be accepted (extra->grad_first), that trial is evaluated
 * with its gradient, handed back if accepted (one gradient call instead of a value call
 * and a gradient call; measured on the 115k-tet bunny re-mesh, bench_newton: the
 * energy pass was 1.4% of a factorization per Newton iteration). After
 * max_evals rejected trials the search returns x itself (α = 0) and
 * EO_WARN_NOT_CONVERGED (Nocedal & Wright, Numerical Optimization, Alg. 3.1). */
#include "elastopt/impl/params.h"
#include <float.h>
#include <math.h>
#include <stddef.h>

#include "trial.h"

static const eo_param_desc bt_desc[] = {
    {.key = "c1", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_backtracking_params, c1),
     .def.d = 1e-4, .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "Armijo constant: accept g(x+ap) <= g + c1*a*grad'p"},
    {.key = "shrink", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_backtracking_params, shrink),
     .def.d = 0.5, .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "step factor after a rejected trial"},
    {.key = "max_evals", .kind = EO_PARAM_INT, .offset = offsetof(eo_backtracking_params, max_evals),
     .def.i = 60, .min = 1, .max = 10000, .range = EO_RANGE_CLOSED, .help = "trials before giving up"},
    {0},
};

static int bt_search(const void *params, eo_objective *obj, const double *x, const double *p,
                     double g0, double dg0, double alpha0, double *xnew, double *gnew,
                     double *alpha, int *nevals, double *work, eo_ctx *ctx,
                     eo_ls_extra *extra)
{
    eo_backtracking_params def;
    const eo_backtracking_params *bp = params;
    (void)work, (void)ctx;
    if (extra) extra->have_grad = 0; /* values only */
    if (!bp) {
        eo_params_default(bt_desc, &def);
        bp = &def;
    }
    double a = eo_ls_first_step(alpha0);
    const double noise = 4 * DBL_EPSILON * fabs(g0);
    double *g1 = eo_ls_first_grad(extra); /* the first trial with its gradient (file comment) */
    *nevals = 0;
    for (int k = 0; k < bp->max_evals; k++) {
        double f;
        const int tiny = -a * dg0 <= 100 * noise; /* g cannot resolve the predicted decrease */
        int rc;
        if (tiny && extra && extra->grad_new) {
            eo_ls_point(obj->n, x, p, a, xnew);
            ++*nevals;
            rc = eo_objective_gradient(obj, xnew, &f, extra->grad_new);
            if (rc < 0) return rc;
            double d = 0;
            d = eo_vdot(obj->space, obj->n, extra->grad_new, p);
            if (isfinite(f) && isfinite(d) &&
                (f <= g0 + noise || (d <= (1 - 2 * bp->c1) * -dg0 && f <= g0 + 100 * noise))) {
                extra->have_grad = 1;
                *gnew = f;
                *alpha = a;
                return EO_OK;
            }
            a *= bp->shrink;
            continue;
        }
        rc = eo_ls_eval(obj, x, p, a, xnew, &f, nevals, k == 0 ? g1 : NULL);
        if (rc < 0) return rc;
        if (isfinite(f) && (f <= g0 + bp->c1 * a * dg0 ||
                            (-a * dg0 <= 100 * noise && f <= g0 + noise))) {
            if (k == 0 && g1) extra->have_grad = 1;
            *gnew = f;
            *alpha = a;
            return EO_OK;
        }
        a *= bp->shrink;
    }
    return eo_ls_give_up(obj->n, x, g0, xnew, gnew, alpha);
}

const eo_linesearch_type eo_linesearch_backtracking = {
    .info = {.name = "backtracking",
             .summary = "Armijo backtracking: shrink until g(x+ap) <= g + c1*a*grad'p",
             .params = bt_desc,
             .params_size = sizeof(eo_backtracking_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .search = bt_search,
};
