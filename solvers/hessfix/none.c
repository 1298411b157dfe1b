/* Hessian fix "none": the optimizer factors the true Hessian H = ∇²g once per direction.
 *
 * No projection, no shift. When H is not positive definite (the factorization reports
 * EO_WARN_NOT_PD) or the Newton direction is not a descent direction, the direction of
 * that iteration is steepest descent p = −∇g (res.n_fallback counts them), so a
 * non-convex problem still ends with a reason. Useful to observe what the other fixes
 * buy; fine for convex problems. An optimizer that only wants factors to reuse
 * (projective_dynamics, env->want_direction = 0) cannot use −∇g: there the matrix is
 * shifted as by `shift` with its default parameters. With an iterative linear solver
 * (cg/pcg) that meets non-positive curvature pᵀHp ≤ 0 in the solve (out.neg_curvature),
 * that iteration instead uses the clamp-projected matrix (EO_PROJ_CLAMP, shift
 * safeguard): the negative-curvature direction is never used and steepest descent is
 * kept for what a factorization reports. No parameters. */
#include "shift_loop.h"

static int none_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                       eo_hessfix_out *out)
{
    eo_shift_ws *w = vst;
    eo_hessfix_shift_params hp;
    (void)params;
    eo_shift_params_get(NULL, &hp);
    out->projected = 0;
    int ok = eo_shift_assemble_factor(w, &hp, !env->want_direction, env, EO_PROJ_NONE, NULL, p, out);
    if (ok < 0) return ok;
    if (!ok && !out->reason && out->neg_curvature) {
        /* an iterative inner solve met pᵀHp ≤ 0: this iteration uses the clamp-projected
         * matrix, with the shift safeguard; never the negative-curvature direction */
        out->projected = 1;
        ok = eo_shift_assemble_factor(w, &hp, 1, env, EO_PROJ_CLAMP, NULL, p, out);
        if (ok < 0) return ok;
        eo_log(env->ctx, EO_LOG_DEBUG, "hessian fix none: negative curvature in the inner solve, clamp system");
    }
    if (!ok && !out->reason) eo_shift_fallback(w, env, p, out);
    return EO_OK;
}

const eo_hessfix_type eo_hessfix_none = {
    .info = {.name = "none",
             .summary = "true Hessian; steepest descent for iterations where it is not PD",
             .params = NULL,
             .params_size = 0,
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(eo_shift_ws),
    .elem_proj = EO_PROJ_NONE,
    .setup = eo_shift_op_setup,
    .begin = eo_shift_op_begin,
    .factor = none_factor,
    .destroy = eo_shift_op_destroy,
};
