/* Stopping rule "characteristic_gradient": converged when
 *
 *     ‖∇g(x)‖₂ ≤ tol · scale · g_c,
 *
 * g_c the objective's characteristic gradient norm (objective.h, characteristic; filled
 * into eo_stop_info.grad_char by eo_solver_stop_check at x₀). Zhu, Bridson & Kaufman 2018,
 * "Blended Cured Quasi-Newton for Distortion Optimization" §7: a relative test against
 * ‖∇g(x₀)‖ depends on how far the start is from the solution, and tests on the change of
 * g or x stop wrongly when a method slows down for a while; instead ‖∇g‖ is compared with
 * the gradient a unit distortion of this mesh and energy would produce: the per-vertex
 * "perimeter" a_v (sum of the rest areas of the faces opposite v in its tets) times the
 * norm of the energy's Hessian in the singular values at rest, g_c = ‖a‖₂·‖∂²ψ/∂σ²(I)‖₂
 * (the authors' code, get_precomputed_split_info.m / stop_check.m, stops at
 * ‖∇E‖ < 1e-3·g_c; that is solver.tol = 1e-3). In a step problem g = ½‖x − x̃‖²_M + w E
 * the elastic weight w multiplies g_c, and materials may differ per tet (a_v sums
 * A_{t,v}·h_t). The test is absolute (in units of ∇g), so a step that starts at its
 * minimizer converges at once, and so does one that starts within tol·g_c of it.
 * Differences: the authors' code also stops when ‖Δx‖ or |Δg| stay below 1e-10 / 1e-6
 * (relative) for 5 iterations; those tests are not part of this rule (the descent loop
 * reports stagnation on its own). Also converged at the rounding floor of ‖∇g‖_{D⁻¹}
 * (eo_stop_info.floor_grad) and when ‖∇g‖ is exactly 0. Objectives without g_c
 * (grad_char = 0): the test is relative to ‖∇g(x₀)‖₂, as the `gradient` rule.
 * Needs no direction: checked right after the gradient. */
#include <math.h>
#include <stddef.h>

#include "elastopt/impl/method.h"

/// Characteristic gradient stopping rule (config `solver.characteristic_gradient.*`):
/// ‖∇g‖₂ ≤ tol·g_c (BCQN §7).
typedef struct eo_stop_characteristic_gradient_params {
    double scale;        ///< factor on g_c (default 1)
} eo_stop_characteristic_gradient_params;

static const eo_param_desc cg_desc[] = {
    {.key = "scale", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_stop_characteristic_gradient_params, scale),
     .def.d = 1, .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "factor on the characteristic gradient norm g_c: converged when |grad g| <= tol*scale*g_c"},
    {0},
};

static int cg_check(const void *params, const eo_stop_info *si)
{
    const eo_stop_characteristic_gradient_params *cp = params;
    const double scale = cp ? cp->scale : 1;
    if (si->grad_norm == 0) return EO_CONVERGED_GRADIENT;
    if (si->floor_grad > 0 && isfinite(si->grad_metric) && si->grad_metric * si->grad_metric / 2 <= si->floor_grad)
        return EO_CONVERGED_GRADIENT;
    const double gc = si->grad_char > 0 && isfinite(si->grad_char) ? scale * si->grad_char : si->grad_norm0;
    return si->grad_norm <= si->tol * gc ? EO_CONVERGED_GRADIENT : 0;
}

const eo_stop_type eo_stop_characteristic_gradient = {
    .info = {.name = "characteristic_gradient",
             .summary = "converged when |grad g| <= tol * g_c, g_c the characteristic gradient norm of the mesh and "
                        "energy (BCQN; tol = 1e-3 in the paper)",
             .params = cg_desc,
             .params_size = sizeof(eo_stop_characteristic_gradient_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .check = cg_check,
    .needs_direction = 0,
};
