/* jacobi — Jacobi iteration  x_{k+1} = x_k + D⁻¹ (b − A x_k),  D = diag(A).
 *
 * Converges iff the spectral radius ρ(I − D⁻¹A) < 1; strict diagonal dominance is
 * sufficient, NOT necessary, and SPD FEM matrices often fail it (ERRATA for 001 §4.1;
 * e.g. A = (1−a) I + a 11ᵀ with a (m−1) > 1 is SPD yet ρ = a (m−1)). Divergence,
 * stagnation and the iteration cap end the solve with EO_WARN_NOT_CONVERGED; see
 * stationary.h for the exact tests. For comparison and teaching, not production.
 *
 * Parameters (solver.jacobi.<key>):
 *   tol         relative residual ‖b − Ax‖/‖b‖ to reach               default 1e-10
 *   max_iters   iteration cap                                         default 10000
 *   warm_start  start from the x passed to solve instead of 0         default false
 */
#include <stddef.h>

#include "stationary.h"

typedef struct jacobi_params {
    double tol;     /* relative residual; default 1e-10 */
    int max_iters;  /* default 10000 */
    int warm_start; /* default false */
} jacobi_params;

static const eo_param_desc jacobi_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(jacobi_params, tol), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(jacobi_params, max_iters),
     .def.i = 10000, .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(jacobi_params, warm_start),
     .def.i = 0, .help = "start from the x passed in (else from 0)"},
    {0},
};

static int jac_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    const jacobi_params *p = params;
    eo_stat *s = st;
    s->o = (eo_stat_opts){.tol = p->tol, .max_iters = p->max_iters, .warm_start = p->warm_start,
                          .omega = 1, .method = EO_STAT_JACOBI, .name = "jacobi"};
    return EO_OK;
}
static int jac_analyze(void *st, const eo_csc *A, eo_ctx *ctx) { return eo_stat_analyze(st, A, ctx); }
static int jac_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    return eo_stat_factor(st, A, stats, ctx);
}
static int jac_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    return eo_stat_solve(st, b, x, stats, ctx);
}
static void jac_destroy(void *st, eo_ctx *ctx) { eo_stat_destroy(st, ctx); }

const eo_linsolve_type eo_linsolve_jacobi = {
    .info = {.name = "jacobi",
             .summary = "Jacobi iteration (diverges on many SPD matrices: reports it)",
             .params = jacobi_desc,
             .params_size = sizeof(jacobi_params)},
    .state_size = sizeof(eo_stat),
    .setup = jac_setup,
    .analyze = jac_analyze,
    .factor = jac_factor,
    .solve = jac_solve,
    .destroy = jac_destroy,
};
