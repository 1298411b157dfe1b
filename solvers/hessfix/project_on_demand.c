/* Hessian fix "project_on_demand": the true Hessian first, the projected one only when
 * it fails (Longva, Löschner, Fernández-Fernández, Larionov, Ascher & Bender, "Pitfalls
 * of Projection: A study of Newton-type solvers for incremental potentials", 2023,
 * arXiv:2311.14526, "Project-on-Demand Newton").
 *
 * Per direction:
 *   1. H = ∇²g(x) unprojected (EO_PROJ_NONE); factor; p = −H⁻¹∇g.
 *   2. If the factorization reports not positive definite, or p is not a descent
 *      direction (∇gᵀp ≥ −descent_eps·‖∇g‖‖p‖), assemble again with every element
 *      Hessian clamped (EO_PROJ_CLAMP, as `clamp`) and use that system, with the c·I
 *      shift loop of shift_loop.c as its safeguard (parameters solver.project_on_demand.
 *      shift_*, same meaning and defaults as solver.shift.*).
 * Near a minimizer where ∇²g is positive definite every direction is a true Newton
 * direction, so the iteration converges quadratically where projected Newton (`clamp`)
 * is only linear; far from it the fix is as robust as `clamp`, at the price of one extra
 * Hessian assembly and factorization on the iterations that need the projection.
 * The fraction projected is 0 or 1 per direction. With want_direction = 0
 * (projective_dynamics) step 2 runs when the factorization fails. */
#include "shift_loop.h"

static int pod_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                      eo_hessfix_out *out)
{
    eo_hessfix_shift_params hp;
    eo_shift_params_get(params, &hp);
    out->projected = 0;
    int ok = eo_shift_assemble_factor(vst, &hp, 0, env, EO_PROJ_NONE, NULL, p, out);
    if (ok < 0) return ok;
    if (ok || out->reason) return EO_OK;
    out->projected = 1;
    ok = eo_shift_assemble_factor(vst, &hp, 1, env, EO_PROJ_CLAMP, NULL, p, out);
    return ok < 0 ? ok : EO_OK;
}

const eo_hessfix_type eo_hessfix_project_on_demand = {
    .info = {.name = "project_on_demand",
             .summary = "true Hessian; clamp-projected only when not PD or not descent (Longva 2023)",
             .params = eo_hessfix_shift_params_desc,
             .params_size = sizeof(eo_hessfix_shift_params)},
    .state_size = sizeof(eo_shift_ws),
    .elem_proj = EO_PROJ_NONE,
    .setup = eo_shift_op_setup,
    .begin = eo_shift_op_begin,
    .factor = pod_factor,
    .destroy = eo_shift_op_destroy,
};
