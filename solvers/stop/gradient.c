/* Stopping rule "gradient": converged when ‖∇g(x)‖₂ ≤ tol·max(‖∇g(x₀)‖₂, floor).
 *
 * The scale is the gradient norm at the start point x₀ of this minimization (each time
 * step starts a new one), so tol (solver.tol) is a relative reduction, independent of
 * the units of g. `floor` (units of ∇g, default 1e-300, i.e. purely relative) bounds
 * the scale from below: set it to the gradient size you consider negligible so that a
 * minimization starting at (or numerically at) a minimizer stops at once instead of
 * chasing rounding noise; the absolute threshold is then tol·floor. Also stops when
 * ‖∇g‖ is exactly 0. Needs no direction, so it is checked right after the gradient. */
#include <math.h>
#include <stddef.h>

#include "elastopt/impl/method.h"

/// Gradient stopping rule (config `solver.gradient.*`).
typedef struct eo_stop_gradient_params {
    double floor;        ///< lower bound of the scale ‖∇g(x₀)‖, units of ∇g (1e-300)
} eo_stop_gradient_params;

static const eo_param_desc grad_desc[] = {
    {.key = "floor", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_stop_gradient_params, floor),
     .def.d = 1e-300, .min = 0, .range = EO_RANGE_MIN,
     .help = "lower bound of the scale |grad g(x0)| (units of grad g)"},
    {0},
};

static int grad_check(const void *params, const eo_stop_info *si)
{
    const eo_stop_gradient_params *gp = params;
    double floor = gp ? gp->floor : 1e-300;
    if (si->grad_norm == 0) return EO_CONVERGED_GRADIENT;
    double scale = si->grad_norm0 > floor ? si->grad_norm0 : floor;
    if (si->grad_norm <= si->tol * scale) return EO_CONVERGED_GRADIENT;
    return 0;
}

const eo_stop_type eo_stop_gradient = {
    .info = {.name = "gradient",
             .summary = "converged when |grad g| <= tol * max(|grad g(x0)|, floor)",
             .params = grad_desc,
             .params_size = sizeof(eo_stop_gradient_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .check = grad_check,
    .needs_direction = 0,
};
