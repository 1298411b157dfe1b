/* cg — conjugate gradients (Hestenes & Stiefel 1952) for symmetric positive definite A.
 *
 *   r₀ = b − A x₀,  p₀ = r₀
 *   α_k = r_kᵀr_k / p_kᵀA p_k
 *   x_{k+1} = x_k + α_k p_k,   r_{k+1} = r_k − α_k A p_k
 *   β_k = r_{k+1}ᵀr_{k+1} / r_kᵀr_k      (ERRATA: the notes' β = rᵀAp/(pᵀAp) with
 *   p_{k+1} = r_{k+1} + β_k p_k            r = Ax − b has the wrong sign/index)
 *
 * Stops when ‖r‖ ≤ tol ‖b‖ (EO_OK), after max_iters (EO_WARN_NOT_CONVERGED), on
 * non-finite values (EO_WARN_NOT_CONVERGED), or when a direction has non-positive
 * curvature p_kᵀA p_k ≤ 0 (EO_WARN_NOT_PD: A is not positive definite). In that case
 * x holds the last iterate, or b itself if it happens at k = 0 (the steepest-descent
 * direction, as truncated Newton–CG does). x₀ = 0 unless warm_start, which uses the x
 * passed in. Workspace is allocated in analyze; solve does not allocate. `factor` only
 * records A (borrowed).
 *
 * Parameters (solver.cg.<key>):
 *   tol         relative residual ‖b − Ax‖/‖b‖ to reach               default 1e-10
 *   max_iters   iteration cap                                         default 10000
 *   warm_start  start from the x passed to solve instead of 0         default false
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "elastopt/linsolve.h"

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

typedef struct cg_state {
    cg_params p;
    int n;
    const eo_csc *A; /* borrowed at factor */
    double *r, *d, *Ad;
} cg_state;

static int cg_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    ((cg_state *)st)->p = *(const cg_params *)params;
    return EO_OK;
}

static void cg_destroy(void *st, eo_ctx *ctx)
{
    cg_state *s = st;
    eo_free(ctx, s->r);
    eo_free(ctx, s->d);
    eo_free(ctx, s->Ad);
    s->r = s->d = s->Ad = NULL;
}

static int cg_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    cg_state *s = st;
    cg_destroy(s, ctx);
    size_t m = (size_t)(A->n ? A->n : 1) * sizeof(double);
    s->n = A->n;
    s->r = eo_malloc(ctx, m);
    s->d = eo_malloc(ctx, m);
    s->Ad = eo_malloc(ctx, m);
    if (!s->r || !s->d || !s->Ad) {
        cg_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "cg: out of memory (n=%d)", A->n);
    }
    return EO_OK;
}

static int cg_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)stats;
    (void)ctx;
    ((cg_state *)st)->A = A;
    return EO_OK;
}

static double dot(int n, const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

static int cg_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    cg_state *s = st;
    const int n = s->n;
    double *r = s->r, *d = s->d, *Ad = s->Ad;
    double bnorm = sqrt(dot(n, b, b));
    if (!s->p.warm_start) memset(x, 0, (size_t)n * sizeof(double));
    stats->iterations = 0;
    stats->residual = 0;
    if (bnorm == 0) {
        memset(x, 0, (size_t)n * sizeof(double));
        return EO_OK;
    }
    if (s->p.warm_start) {
        eo_csc_symv(s->A, x, r);
        for (int i = 0; i < n; i++) r[i] = b[i] - r[i];
    } else {
        memcpy(r, b, (size_t)n * sizeof(double));
    }
    memcpy(d, r, (size_t)n * sizeof(double));
    double rr = dot(n, r, r), stop = s->p.tol * bnorm;
    int k = 0;
    while (sqrt(rr) > stop) {
        if (k >= s->p.max_iters || !isfinite(rr)) {
            stats->iterations = k;
            stats->residual = sqrt(rr) / bnorm;
            return eo_error(ctx, EO_WARN_NOT_CONVERGED,
                            "cg: %s after %d iterations, relative residual %.3g (tol %.3g)",
                            isfinite(rr) ? "not converged" : "non-finite residual", k,
                            stats->residual, s->p.tol);
        }
        eo_csc_symv(s->A, d, Ad);
        double dAd = dot(n, d, Ad);
        if (!(dAd > 0)) {
            if (k == 0 && !s->p.warm_start) memcpy(x, b, (size_t)n * sizeof(double));
            stats->iterations = k;
            stats->residual = sqrt(rr) / bnorm;
            return eo_error(ctx, EO_WARN_NOT_PD,
                            "cg: non-positive curvature p'Ap = %.3g at iteration %d: matrix not "
                            "positive definite", dAd, k);
        }
        double alpha = rr / dAd;
        for (int i = 0; i < n; i++) {
            x[i] += alpha * d[i];
            r[i] -= alpha * Ad[i];
        }
        double rr_new = dot(n, r, r);
        double beta = rr_new / rr; /* r_{k+1}ᵀr_{k+1} / r_kᵀr_k */
        for (int i = 0; i < n; i++) d[i] = r[i] + beta * d[i];
        rr = rr_new;
        k++;
    }
    stats->iterations = k;
    stats->residual = sqrt(rr) / bnorm;
    return EO_OK;
}

const eo_linsolve_type eo_linsolve_cg = {
    .info = {.name = "cg",
             .summary = "conjugate gradients (unpreconditioned; detects non-positive curvature)",
             .params = cg_desc,
             .params_size = sizeof(cg_params)},
    .state_size = sizeof(cg_state),
    .setup = cg_setup,
    .analyze = cg_analyze,
    .factor = cg_factor,
    .solve = cg_solve,
    .destroy = cg_destroy,
};
