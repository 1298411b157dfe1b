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
 * (projective_dynamics) step 2 runs when the factorization fails.
 *
 * projection = abs (solver.project_on_demand.projection): step 2 assembles with the
 * absolute eigenvalues (EO_PROJ_ABS, as `abs`) instead of clamping them. Where many
 * elements are inverted or strongly compressed, clamping zeroes their negative curvature
 * and the direction is long in those modes (the line search then cuts it to α ~ 1e-3);
 * |λ| keeps the curvature's size and the steps short and full (Chen et al. 2024, the
 * `abs` branch of trust_region_filter). Near a minimizer the true Hessian is used, so
 * the end game is Newton's, where `abs` alone converges only linearly (measured on the
 * inverted real bunny, docs/defaults.md). */
#include <stddef.h>
#include <string.h>

#include "shift_loop.h"

/// project_on_demand (config `solver.project_on_demand.*`).
typedef struct eo_hessfix_pod_params {
    eo_hessfix_shift_params shift; ///< safeguard of the projected retry (as solver.shift.*)
    char projection[8];            ///< the retry's projection: "clamp" (default) or "abs"
} eo_hessfix_pod_params;

static const char *const pod_projections[] = {"clamp", "abs", NULL};

static const eo_param_desc pod_desc[] = {
    {.key = "shift_init", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_hessfix_pod_params, shift.shift_init),
     .def.d = 1e-8, .min = 0, .range = EO_RANGE_POSITIVE, .help = "first non-zero shift, relative to mean |H_ii|"},
    {.key = "shift_grow", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_hessfix_pod_params, shift.shift_grow),
     .def.d = 10, .min = 1, .range = EO_RANGE_MIN_OPEN, .help = "shift growth factor per retry"},
    {.key = "shift_shrink", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_hessfix_pod_params, shift.shift_shrink),
     .def.d = 10, .min = 1, .range = EO_RANGE_MIN, .help = "next iteration starts at c/shift_shrink (0 below the minimum)"},
    {.key = "shift_max", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_hessfix_pod_params, shift.shift_max),
     .def.d = 1e12, .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "largest shift, relative to mean |H_ii|; beyond: not PD"},
    {.key = "projection", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_hessfix_pod_params, projection),
     .size = sizeof(((eo_hessfix_pod_params *)0)->projection), .def.s = "clamp", .choices = pod_projections,
     .help = "element projection of the retry when the true Hessian is not PD: clamp (negative eigenvalues to 0) "
             "or abs (to their absolute values: shorter steps through inverted elements)"},
    {0},
};

static int pod_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                      eo_hessfix_out *out)
{
    eo_hessfix_pod_params def;
    const eo_hessfix_pod_params *pp = params;
    if (!pp) {
        eo_params_default(pod_desc, &def);
        pp = &def;
    }
    out->projected = 0;
    int ok = eo_shift_assemble_factor(vst, &pp->shift, 0, env, EO_PROJ_NONE, NULL, p, out);
    if (ok < 0) return ok;
    if (ok || out->reason) return EO_OK;
    out->projected = 1;
    const eo_proj proj = strcmp(pp->projection, "abs") == 0 ? EO_PROJ_ABS : EO_PROJ_CLAMP;
    ok = eo_shift_assemble_factor(vst, &pp->shift, 1, env, proj, NULL, p, out);
    return ok < 0 ? ok : EO_OK;
}

const eo_hessfix_type eo_hessfix_project_on_demand = {
    .info = {.name = "project_on_demand",
             .summary = "true Hessian; clamp-projected only when not PD or not descent (Longva 2023)",
             .params = pod_desc,
             .params_size = sizeof(eo_hessfix_pod_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(eo_shift_ws),
    .elem_proj = EO_PROJ_NONE,
    .setup = eo_shift_op_setup,
    .begin = eo_shift_op_begin,
    .factor = pod_factor,
    .destroy = eo_shift_op_destroy,
};
