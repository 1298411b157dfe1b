/* Hessian fix "clamp": per-element eigenvalue clamping.
 *
 * Each element Hessian K_e = Q Λ Qᵀ is replaced by Q max(Λ, 0) Qᵀ while assembling
 * (EO_PROJ_CLAMP; for isotropic materials through the closed-form eigensystem of Smith,
 * de Goes & Kim 2019), so H = Σ K_e⁺ + (mass) is positive semi-definite, definite with
 * an inertia term. Objectives whose terms have no per-element form ignore the
 * projection. If the factorization still reports not PD (a static problem with rigid
 * modes, or an objective that ignores the projection), Newton applies the shift logic
 * of `shift` as a safeguard (counted in res.n_shifted); its parameters are
 * solver.clamp.shift_* with the same meaning and defaults as solver.shift.*. */
#include "elastopt/solver.h"

const eo_hessfix_type eo_hessfix_clamp = {
    .info = {.name = "clamp",
             .summary = "per-element Hessian projection, negative eigenvalues set to 0",
             .params = eo_hessfix_shift_params_desc,
             .params_size = sizeof(eo_hessfix_shift_params)},
    .elem_proj = EO_PROJ_CLAMP,
    .shifts = 0,
    .safeguard = 1,
};
