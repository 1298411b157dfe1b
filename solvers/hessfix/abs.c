/* Hessian fix "abs": per-element absolute eigenvalues.
 *
 * Each element Hessian K_e = Q Λ Qᵀ is replaced by Q |Λ| Qᵀ while assembling
 * (EO_PROJ_ABS): negative curvature becomes positive curvature of the same size, which
 * keeps steps shorter than clamping in strongly compressed/inverted elements. H is
 * positive semi-definite; if the factorization still reports not PD, the shift loop of
 * `shift` (shift_loop.c) runs as a safeguard (counted in res.n_shifted; parameters
 * solver.abs.shift_*, same meaning and defaults as solver.shift.*). */
#include "shift_loop.h"

static int abs_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                        eo_hessfix_out *out)
{
    eo_hessfix_shift_params hp;
    eo_shift_params_get(params, &hp);
    out->projected = 1;
    int ok = eo_shift_assemble_factor(vst, &hp, 1, env, EO_PROJ_ABS, NULL, p, out);
    return ok < 0 ? ok : EO_OK;
}

const eo_hessfix_type eo_hessfix_abs = {
    .info = {.name = "abs",
             .summary = "per-element Hessian projection, eigenvalues replaced by |lambda|",
             .params = eo_hessfix_shift_params_desc,
             .params_size = sizeof(eo_hessfix_shift_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(eo_shift_ws),
    .elem_proj = EO_PROJ_ABS,
    .setup = eo_shift_op_setup,
    .begin = eo_shift_op_begin,
    .factor = abs_factor,
    .destroy = eo_shift_op_destroy,
};
