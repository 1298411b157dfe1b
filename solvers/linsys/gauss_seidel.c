/* gauss_seidel — Gauss–Seidel iteration, forward sweep:
 *
 *   x_i ← (b_i − Σ_{j<i} a_ij x_j^{new} − Σ_{j>i} a_ij x_j^{old}) / a_ii,  i = 1..n
 *
 * i.e. (D + L) x_{k+1} = b − U x_k. Converges for every SPD A (the error decreases in
 * the A-norm each sweep), possibly very slowly; the iteration cap and the stagnation
 * test (stationary.h) end it with EO_WARN_NOT_CONVERGED. Rows of the full symmetric
 * matrix are built once in analyze.
 *
 * Parameters (solver.gauss_seidel.<key>):
 *   tol         relative residual ‖b − Ax‖/‖b‖ to reach               default 1e-10
 *   max_iters   iteration cap                                         default 10000
 *   warm_start  start from the x passed to solve instead of 0         default false
 */
#include <stddef.h>

#include "stationary.h"

typedef struct gs_params {
    double tol;     /* relative residual; default 1e-10 */
    int max_iters;  /* default 10000 */
    int warm_start; /* default false */
} gs_params;

static const eo_param_desc gs_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(gs_params, tol), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(gs_params, max_iters),
     .def.i = 10000, .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(gs_params, warm_start),
     .def.i = 0, .help = "start from the x passed in (else from 0)"},
    {0},
};

static int gs_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    const gs_params *p = params;
    eo_stat *s = st;
    s->o = (eo_stat_opts){.tol = p->tol, .max_iters = p->max_iters, .warm_start = p->warm_start,
                          .omega = 1, .method = EO_STAT_SOR, .name = "gauss_seidel"};
    return EO_OK;
}
static int gs_analyze(void *st, const eo_csc *A, eo_ctx *ctx) { return eo_stat_analyze(st, A, ctx); }
static int gs_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    return eo_stat_factor(st, A, stats, ctx);
}
static int gs_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    return eo_stat_solve(st, b, x, stats, ctx);
}
static void gs_destroy(void *st, eo_ctx *ctx) { eo_stat_destroy(st, ctx); }

const eo_linsolve_type eo_linsolve_gauss_seidel = {
    .info = {.name = "gauss_seidel",
             .summary = "Gauss-Seidel forward sweeps (converges for SPD, slowly)",
             .params = gs_desc,
             .params_size = sizeof(gs_params)},
    .state_size = sizeof(eo_stat),
    .setup = gs_setup,
    .analyze = gs_analyze,
    .factor = gs_factor,
    .solve = gs_solve,
    .destroy = gs_destroy,
};
