/* Hessian fix "shift": factor H + cI (002 Note 4).
 *
 * If H = QΛQᵀ then H + cI = Q(Λ + cI)Qᵀ, positive definite once c > −λ_min. The shift
 * loop (shift_loop.c) first tries the shift carried over from the previous
 * direction (0 at the start); on EO_WARN_NOT_PD or a non-descent direction it retries
 * with c ← max(c_min, shift_grow·c), c_min = shift_init·s, s = mean |H_ii| (1 if 0), and
 * gives up with EO_DIVERGED_NOT_PD above shift_max·s. After a success the next iteration
 * starts at c/shift_shrink (0 when that is below c_min). The element Hessians are not
 * projected (EO_PROJ_NONE). A global shift damps every direction equally; per-element
 * projection (clamp, abs) is usually the stronger fix for elasticity.
 *
 * The parameter table here is shared with clamp and abs, which use the same shift as a
 * safeguard (config solver.shift.*, solver.clamp.*, solver.abs.*). */
#include <stddef.h>

#include "shift_loop.h"

const eo_param_desc eo_hessfix_shift_params_desc[] = {
    {.key = "shift_init", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_shift_params, shift_init), .def.d = 1e-8, .min = 0,
     .range = EO_RANGE_POSITIVE, .help = "first non-zero shift, relative to mean |H_ii|"},
    {.key = "shift_grow", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_shift_params, shift_grow), .def.d = 10, .min = 1,
     .range = EO_RANGE_MIN_OPEN, .help = "shift growth factor per retry"},
    {.key = "shift_shrink", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_shift_params, shift_shrink), .def.d = 10, .min = 1,
     .range = EO_RANGE_MIN, .help = "next iteration starts at c/shift_shrink (0 below the minimum)"},
    {.key = "shift_max", .kind = EO_PARAM_DOUBLE,
     .offset = offsetof(eo_hessfix_shift_params, shift_max), .def.d = 1e12, .min = 0,
     .range = EO_RANGE_POSITIVE, .help = "largest shift, relative to mean |H_ii|; beyond: not PD"},
    {0},
};

static int shift_factor(void *vst, const void *params, const eo_hessfix_env *env, double *p,
                        eo_hessfix_out *out)
{
    eo_hessfix_shift_params hp;
    eo_shift_params_get(params, &hp);
    out->projected = 0;
    int ok = eo_shift_assemble_factor(vst, &hp, 1, env, EO_PROJ_NONE, NULL, p, out);
    return ok < 0 ? ok : EO_OK;
}

const eo_hessfix_type eo_hessfix_shift = {
    .info = {.name = "shift",
             .summary = "factor H + cI, growing c until positive definite and descent",
             .params = eo_hessfix_shift_params_desc,
             .params_size = sizeof(eo_hessfix_shift_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .state_size = sizeof(eo_shift_ws),
    .elem_proj = EO_PROJ_NONE,
    .setup = eo_shift_op_setup,
    .begin = eo_shift_op_begin,
    .factor = shift_factor,
    .destroy = eo_shift_op_destroy,
};
