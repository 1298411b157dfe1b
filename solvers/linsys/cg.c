/* cg — conjugate gradients (Hestenes & Stiefel 1952) for symmetric positive definite A.
 *
 *   r₀ = b − A x₀,  p₀ = r₀
 *   α_k = r_kᵀr_k / p_kᵀA p_k
 *   x_{k+1} = x_k + α_k p_k,   r_{k+1} = r_k − α_k A p_k
 *   β_k = r_{k+1}ᵀr_{k+1} / r_kᵀr_k      (ERRATA: the notes' β = rᵀAp/(pᵀAp) with
 *   p_{k+1} = r_{k+1} + β_k p_k            r = Ax − b has the wrong sign/index)
 *
 * The iteration is pcg's with M = I (cg_iter.h, shared with pcg.c). Stops when
 * ‖r‖ ≤ tol ‖b‖ (EO_OK), after max_iters (EO_WARN_NOT_CONVERGED), on non-finite values
 * (EO_WARN_NOT_CONVERGED), or when a direction has non-positive curvature p_kᵀA p_k ≤ 0
 * (EO_WARN_NOT_PD: A is not positive definite). In that case x holds the last iterate,
 * or b itself if it happens at k = 0 (the steepest-descent direction, as truncated
 * Newton–CG does). x₀ = 0 unless warm_start, which uses the x passed in. Workspace is
 * allocated in analyze; solve does not allocate. `factor` only records A (borrowed).
 *
 * Parameters (solver.cg.<key>):
 *   tol         relative residual ‖b − Ax‖/‖b‖ to reach               default 1e-10
 *   max_iters   iteration cap                                         default 10000
 *   warm_start  start from the x passed to solve instead of 0         default false
 */
#include <stddef.h>

#include "cg_iter.h"

typedef struct cg_params {
    double tol;     /* relative residual; default 1e-10 */
    int max_iters;  /* default 10000 */
    int warm_start; /* default false */
} cg_params;

static const eo_param_desc cg_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(cg_params, tol), .def.d = 1e-10,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "relative residual |b - Ax|/|b| to reach"},
    {.key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(cg_params, max_iters),
     .def.i = 10000, .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap"},
    {.key = "warm_start", .kind = EO_PARAM_BOOL, .offset = offsetof(cg_params, warm_start),
     .def.i = 0, .help = "start from the x passed in (else from 0)"},
    {0},
};

static int cg_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    const cg_params *p = params;
    ((eo_cg *)st)->o = (eo_cg_opts){
        .tol = p->tol, .max_iters = p->max_iters, .warm_start = p->warm_start, .name = "cg"};
    return EO_OK;
}

static void cg_destroy(void *st, eo_ctx *ctx) { eo_cg_destroy(st, ctx); }

static int cg_analyze(void *st, const eo_csc *A, eo_ctx *ctx) { return eo_cg_analyze(st, A, 0, ctx); }

static int cg_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)stats;
    (void)ctx;
    ((eo_cg *)st)->A = A;
    return EO_OK;
}

static int cg_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    return eo_cg_solve(st, NULL, NULL, b, x, stats, ctx);
}

static void cg_set_rtol(void *st, double rtol) { eo_cg_set_rtol(st, rtol); }

const eo_linsolve_type eo_linsolve_cg = {
    .info = {.name = "cg",
             .summary = "conjugate gradients (unpreconditioned; detects non-positive curvature)",
             .params = cg_desc,
             .params_size = sizeof(cg_params)},
    .state_size = sizeof(eo_cg),
    .setup = cg_setup,
    .analyze = cg_analyze,
    .factor = cg_factor,
    .solve = cg_solve,
    .destroy = cg_destroy,
    .set_rtol = cg_set_rtol,
};
