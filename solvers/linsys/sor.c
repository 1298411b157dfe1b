/* sor — successive over-relaxation (Young 1950), forward sweep:
 *
 *   x_i ← (1 − ω) x_i + ω (b_i − Σ_{j<i} a_ij x_j^{new} − Σ_{j>i} a_ij x_j^{old}) / a_ii
 *
 * i.e. (D + ωL) x_{k+1} = ω b − (ωU + (ω − 1) D) x_k. For SPD A it converges iff
 * 0 < ω < 2 (Ostrowski–Reich); ω = 1 is Gauss–Seidel. Divergence, stagnation and the
 * iteration cap end the solve with EO_WARN_NOT_CONVERGED (stationary.h).
 *
 * Parameters (solver.sor.<key>):
 *   omega       relaxation factor, in (0, 2)                          default 1.5
 *   tol         relative residual ‖b − Ax‖/‖b‖ to reach               default 1e-10
 *   max_iters   iteration cap                                         default 10000
 *   warm_start  start from the x passed to solve instead of 0         default false
 */
#include <stddef.h>

#include "stationary.h"

typedef struct sor_params {
    double omega;   /* relaxation in (0,2); default 1.5 */
    double tol;     /* relative residual; default 1e-10 */
    int max_iters;  /* default 10000 */
    int warm_start; /* default false */
} sor_params;

static const eo_param_desc sor_desc[] = {
    {.key = "omega", .kind = EO_PARAM_DOUBLE, .offset = offsetof(sor_params, omega), .def.d = 1.5,
     .min = 0, .max = 2, .range = EO_RANGE_OPEN, .help = "relaxation factor (1 = Gauss-Seidel)"},
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(sor_params, tol), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(sor_params, max_iters),
     .def.i = 10000, .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(sor_params, warm_start),
     .def.i = 0, .help = "start from the x passed in (else from 0)"},
    {0},
};

static int sor_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    const sor_params *p = params;
    eo_stat *s = st;
    s->o = (eo_stat_opts){.tol = p->tol, .max_iters = p->max_iters, .warm_start = p->warm_start,
                          .omega = p->omega, .method = EO_STAT_SOR, .name = "sor"};
    return EO_OK;
}
static int sor_analyze(void *st, const eo_csc *A, eo_ctx *ctx) { return eo_stat_analyze(st, A, ctx); }
static int sor_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    return eo_stat_factor(st, A, stats, ctx);
}
static int sor_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    return eo_stat_solve(st, b, x, stats, ctx);
}
static void sor_destroy(void *st, eo_ctx *ctx) { eo_stat_destroy(st, ctx); }

const eo_linsolve_type eo_linsolve_sor = {
    .info = {.name = "sor",
             .summary = "successive over-relaxation (omega in (0,2))",
             .params = sor_desc,
             .params_size = sizeof(sor_params)},
    .state_size = sizeof(eo_stat),
    .setup = sor_setup,
    .analyze = sor_analyze,
    .factor = sor_factor,
    .solve = sor_solve,
    .destroy = sor_destroy,
};
