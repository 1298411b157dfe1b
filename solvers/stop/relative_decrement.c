/* Stopping rule "relative_decrement" (the default): converged when the Newton decrement
 * has fallen by the factor tol from the first one of this minimization,
 *
 *     λ_k ≤ tol · λ_0,        λ² = −∇gᵀp = ‖p‖²_H   (p the Newton step, H its matrix),
 *
 * or, at the rounding floor, when the decrement has stopped falling at a level that g
 * cannot resolve:  λ_k²/2 ≤ plateau·|g(x_k)|  and  λ_k² > λ_{k−1}²/4.
 *
 * Why: λ_k = ‖p_k‖_H estimates ‖x_k − x*‖_H, and λ_0 estimates ‖x_0 − x*‖_H, the
 * distance the step problem has to move. The rule therefore asks for the iterate to be
 * within a relative distance tol of the minimizer, measured in the Hessian norm against
 * the step's own motion: it is scale-aware (the units and magnitude of g, E, ρ, h and the
 * mesh cancel) and affine invariant, unlike `newton_decrement` (λ²/2 ≤ tol in units of
 * g), whose absolute 1e-10 left the tip of the static StVK cantilever 2.2e-6 relative
 * from the converged answer and the dynamic cantilever 6e-2 after 50 steps (one Newton
 * iteration per step). With the default tol = 1e-10 both are within 1e-8
 * (tests/test_stop.c: 3.7e-11 and 5.9e-10).
 *
 * The plateau: λ² = −∇gᵀp comes from a gradient with rounding error, so it stops falling
 * at a noise level δᵀH⁻¹δ (δ the rounding of ∇g) that depends on the forces, not on tol.
 * Measured plateaus of λ²/2: 1.5e-26·|g| (static cantilever), 4e-27·|g| (dynamic
 * cantilever), 1.6e-21·|g| (a linear cube relaxing to rest, g → 0). Where tol·λ_0 lies
 * below that, the plateau test ends the minimization as converged, instead of iterating
 * to EO_DIVERGED_STAGNATED: it needs both a decrement below what g resolves (plateau =
 * 1e-16, about ε/2: g − g* ≈ λ²/2 is then below the rounding of g) and no progress (a
 * quadratically or fast linearly converging Newton divides λ² by far more than 4 per
 * iteration; clamp on the static cantilever by 23). A slowly converging method
 * (projective dynamics, first-order methods) may stop there by the plateau test: at
 * that point g cannot tell it is still making progress.
 *
 * λ_0 is the decrement of the first direction of the minimization (eo_stop_info
 * decrement0). That measure is used only for optimizers whose direction is a Newton
 * direction (si->measure = EO_MEASURE_DECREMENT, eo_optimizer_type.newton_decrement):
 * every other optimizer is measured by the metric gradient norm, ‖∇g_k‖_{D⁻¹} ≤
 * tol·‖∇g_0‖_{D⁻¹} (the same acceptance set whichever optimizer produced x_k), and so is
 * a caller that reports no first decrement (never the absolute λ²/2 ≤ tol it once fell
 * back to: fixed_point and newton_tr were declared converged at a distance). Both
 * measures also stop at the rounding floor of the step's start (si->floor_dec,
 * floor_grad from eo_solver_stop_check), so a step that starts at its minimizer
 * converges at once; the plateau is scaled by max(|g(x₀)|, |g(x_k)|), not by the final
 * |g| alone (a step whose g falls from 50 to 0.02 reached 9e-16 and was declared
 * stagnated). Also converged when ‖∇g‖ is exactly 0. Checked after the direction is
 * computed (needs_direction = 1), like newton_decrement, and with
 * the same caveats for non-Newton directions (λ is then only an estimate). */
#include <math.h>
#include <stddef.h>

#include "elastopt/impl/method.h"

/// Relative decrement stopping rule, the default (config `solver.relative_decrement.*`):
/// converged when λ_k ≤ tol·λ_0 (λ² = −∇gᵀp, λ_0 of the first direction), or at the
/// rounding floor: λ_k²/2 ≤ plateau·|g| and λ_k² > λ_{k−1}²/4.
typedef struct eo_stop_relative_decrement_params {
    double plateau;      ///< level of λ²/2, relative to |g|, below which a decrement that
                         ///< stopped falling counts as converged (1e-16)
} eo_stop_relative_decrement_params;

static const eo_param_desc reldec_desc[] = {
    {.key = "plateau", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_stop_relative_decrement_params, plateau),
     .def.d = 1e-16, .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "also converged when lambda^2/2 <= plateau*|g| and lambda^2 fell by less than 4x since the previous "
             "iteration (the decrement's rounding floor)"},
    {0},
};

/* Progress by the metric gradient norm: ‖∇g_k‖_{D⁻¹} ≤ tol·‖∇g_0‖_{D⁻¹} (the Euclidean
 * norms for a caller that does not fill the metric ones). */
static int gradient_measure(const eo_stop_info *si)
{
    if (si->floor_grad > 0 && isfinite(si->grad_metric) &&
        si->grad_metric * si->grad_metric / 2 <= si->floor_grad)
        return EO_CONVERGED_GRADIENT;
    double r = si->grad_metric / si->grad_metric0;
    if (!(si->measure == EO_MEASURE_GRADIENT && isfinite(r))) r = si->grad_norm / si->grad_norm0;
    return r <= si->tol ? EO_CONVERGED_GRADIENT : 0;
}

static int reldec_check(const void *params, const eo_stop_info *si)
{
    eo_stop_relative_decrement_params def;
    const eo_stop_relative_decrement_params *p = params;
    if (!p) {
        eo_params_default(reldec_desc, &def);
        p = &def;
    }
    if (si->grad_norm == 0) return EO_CONVERGED_GRADIENT;
    if (si->measure == EO_MEASURE_GRADIENT) return gradient_measure(si);
    if (isnan(si->decrement)) return 0;
    /* at the rounding floor of the step's start: a step that starts at (or reaches) its
     * minimizer */
    if (si->floor_dec > 0 && si->decrement <= si->floor_dec) return EO_CONVERGED_DECREMENT;
    /* no first decrement measured: progress by the gradient, never an absolute test */
    if (!(si->decrement0 > 0) || !isfinite(si->decrement0)) return gradient_measure(si);
    if (si->decrement <= si->tol * si->tol * si->decrement0) return EO_CONVERGED_DECREMENT;
    /* the plateau: below what g resolves, at the scale of g at the start or now, or of
     * the terms g is summed from (the objective's rounding scale: g itself may be a
     * small difference of large terms, e.g. a body at rest) */
    double gs = fabs(si->g);
    if (isfinite(si->g0) && fabs(si->g0) > gs) gs = fabs(si->g0);
    if (si->g_scale > gs) gs = si->g_scale;
    if (si->decrement <= p->plateau * gs && si->decrement > si->decrement_prev / 4) return EO_CONVERGED_DECREMENT;
    return 0;
}

const eo_stop_type eo_stop_relative_decrement = {
    .info = {.name = "relative_decrement",
             .summary = "converged when lambda <= tol*lambda_0 (within tol of x*, relative to the step's motion, H-norm)",
             .params = reldec_desc,
             .params_size = sizeof(eo_stop_relative_decrement_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .check = reldec_check,
    .needs_direction = 1,
};
