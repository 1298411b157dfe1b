/* Stopping rule "newton_decrement": converged when λ²/2 ≤ tol.
 *
 * λ² = ∇gᵀ(∇²g)⁻¹∇g = −∇gᵀp for the Newton direction p (ERRATA for 002 Def. 4), and
 * g(x) − g* ≈ λ²/2 near a minimizer, so tol is in the units of g (solver.tol, default
 * 1e-10; for the step objective kg·m²). The rule is affine invariant. It is checked
 * after the direction is computed (needs_direction = 1); the optimizer passes
 * −α₀∇gᵀp/2 of its own direction: with Newton and a shift c > 0 it is the decrement of
 * H + cI; with gradient_descent (p = −D⁻¹∇g, α₀ the first trial) or lbfgs (quasi-Newton
 * p) it is only an estimate of g − g*, as good as D/α₀ or the L-BFGS matrix approximates
 * ∇²g. Also stops with EO_CONVERGED_GRADIENT when ‖∇g‖ is exactly 0. No parameters.
 * Optimizers that can estimate λ²/2 without a new direction (newton: one solve with
 * the factor of the previous iterate's matrix, after a full unshifted step) have the
 * rule tested with that estimate first, before the next Hessian is assembled
 * (descent.c); so the last iterate of a converged Newton run costs no factorization. */
#include <math.h>

#include "elastopt/impl/method.h"

static int dec_check(const void *params, const eo_stop_info *si)
{
    (void)params;
    if (si->grad_norm == 0) return EO_CONVERGED_GRADIENT;
    if (!isnan(si->decrement) && si->decrement <= si->tol) return EO_CONVERGED_DECREMENT;
    return 0;
}

const eo_stop_type eo_stop_newton_decrement = {
    .info = {.name = "newton_decrement",
             .summary = "converged when lambda^2/2 = -grad'p/2 <= tol (estimates g - g*)",
             .params = NULL,
             .params_size = 0,
             .flags = EO_METHOD_DISTRIBUTED},
    .check = dec_check,
    .needs_direction = 1,
};
