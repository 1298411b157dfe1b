/* Hessian fix "shift": Newton factors H + cI (002 Note 4).
 *
 * If H = QΛQᵀ then H + cI = Q(Λ + cI)Qᵀ, positive definite once c > −λ_min. Newton
 * (solvers/optim/newton.c) first tries the shift carried over from the previous
 * iteration (0 at the start); on EO_WARN_NOT_PD or a non-descent direction it retries
 * with c ← max(c_min, shift_grow·c), c_min = shift_init·s, s = mean |H_ii| (1 if 0), and
 * gives up with EO_DIVERGED_NOT_PD above shift_max·s. After a success the next iteration
 * starts at c/shift_shrink (0 when that is below c_min). The element Hessians are not
 * projected (EO_PROJ_NONE). A global shift damps every direction equally; per-element
 * projection (clamp, abs) is usually the stronger fix for elasticity.
 *
 * The parameter table here is shared with clamp and abs, which use the same shift as a
 * safeguard (config solver.shift.*, solver.clamp.*, solver.abs.*). */
#include <stddef.h>

#include "elastopt/solver.h"

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

const eo_hessfix_type eo_hessfix_shift = {
    .info = {.name = "shift",
             .summary = "factor H + cI, growing c until positive definite and descent",
             .params = eo_hessfix_shift_params_desc,
             .params_size = sizeof(eo_hessfix_shift_params)},
    .elem_proj = EO_PROJ_NONE,
    .shifts = 1,
    .safeguard = 0,
};
