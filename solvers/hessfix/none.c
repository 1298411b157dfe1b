/* Hessian fix "none": Newton factors the true Hessian H = ∇²g once per iteration.
 *
 * No projection, no shift. When H is not positive definite (the factorization reports
 * EO_WARN_NOT_PD) or the Newton direction is not a descent direction, Newton uses the
 * steepest-descent direction p = −∇g for that iteration (res.n_fallback counts them),
 * so a non-convex problem still ends with a reason. Useful to observe what the other
 * fixes buy; fine for convex problems. No parameters. */
#include "elastopt/solver.h"

const eo_hessfix_type eo_hessfix_none = {
    .info = {.name = "none",
             .summary = "true Hessian; steepest descent for iterations where it is not PD",
             .params = NULL,
             .params_size = 0},
    .elem_proj = EO_PROJ_NONE,
    .shifts = 0,
    .safeguard = 0,
};
