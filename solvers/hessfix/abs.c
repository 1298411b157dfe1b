/* Hessian fix "abs": per-element absolute eigenvalues.
 *
 * Each element Hessian K_e = Q Λ Qᵀ is replaced by Q |Λ| Qᵀ while assembling
 * (EO_PROJ_ABS): negative curvature becomes positive curvature of the same size, which
 * keeps steps shorter than clamping in strongly compressed/inverted elements. H is
 * positive semi-definite; if the factorization still reports not PD, Newton applies the
 * shift logic of `shift` as a safeguard (counted in res.n_shifted; parameters
 * solver.abs.shift_*, same meaning and defaults as solver.shift.*). */
#include "elastopt/solver.h"

const eo_hessfix_type eo_hessfix_abs = {
    .info = {.name = "abs",
             .summary = "per-element Hessian projection, eigenvalues replaced by |lambda|",
             .params = eo_hessfix_shift_params_desc,
             .params_size = sizeof(eo_hessfix_shift_params)},
    .elem_proj = EO_PROJ_ABS,
    .shifts = 0,
    .safeguard = 1,
};
