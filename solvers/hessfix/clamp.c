/* Hessian fix "clamp": per-element eigenvalue clamping.
 *
 * Each element Hessian K_e = Q Λ Qᵀ is replaced by Q max(Λ, 0) Qᵀ while assembling
 * (EO_PROJ_CLAMP; for isotropic materials through the closed-form eigensystem of Smith,
 * de Goes & Kim 2019), so H = Σ K_e⁺ + (mass) is positive semi-definite, definite with
 * an inertia term. Objectives whose terms have no per-element form ignore the
 * projection. If the factorization still reports not PD (a static problem with rigid
 * modes, or an objective that ignores the projection), the shift loop of `shift`
 * (shift_loop.c) runs as a safeguard (counted in res.n_shifted); its parameters are
 * solver.clamp.shift_* with the same meaning and defaults as solver.shift.*. */
#include "shift_loop.h"

static int clamp_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                        eo_hessfix_out *out)
{
    eo_hessfix_shift_params hp;
    eo_shift_params_get(params, &hp);
    out->projected = 1;
    int ok = eo_shift_assemble_factor(vst, &hp, 1, env, EO_PROJ_CLAMP, NULL, p, out);
    return ok < 0 ? ok : EO_OK;
}

const eo_hessfix_type eo_hessfix_clamp = {
    .info = {.name = "clamp",
             .summary = "per-element Hessian projection, negative eigenvalues set to 0",
             .params = eo_hessfix_shift_params_desc,
             .params_size = sizeof(eo_hessfix_shift_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(eo_shift_ws),
    .elem_proj = EO_PROJ_CLAMP,
    .setup = eo_shift_op_setup,
    .begin = eo_shift_op_begin,
    .factor = clamp_factor,
    .destroy = eo_shift_op_destroy,
};
