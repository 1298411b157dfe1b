/* Internal: the conjugate-gradient iteration shared by cg.c (M = I) and pcg.c (Jacobi or
 * IC(0)), not a public header. Each method file owns its params struct and descriptor
 * table and copies the common fields into eo_cg_opts; plain CG is PCG with the identity
 * preconditioner, run without the copy z = r and without the second dot product.
 *
 *   r₀ = b − A x₀,  z₀ = M⁻¹ r₀,  p₀ = z₀
 *   α_k = r_kᵀz_k / p_kᵀA p_k,   x_{k+1} = x_k + α_k p_k,   r_{k+1} = r_k − α_k A p_k
 *   z_{k+1} = M⁻¹ r_{k+1},   β_k = r_{k+1}ᵀz_{k+1} / r_kᵀz_k,   p_{k+1} = z_{k+1} + β_k p_k
 *
 * (ERRATA: the notes' β = rᵀAp/(pᵀAp) with r = Ax − b has the wrong sign/index.)
 * Stops when ‖r‖ ≤ tol ‖b‖ (EO_OK), after max_iters (EO_WARN_NOT_CONVERGED), once the
 * average contraction (‖r_k‖/‖r₀‖)^(1/k) projects more than project_max iterations (k ≥ 2,
 * project_max > 0; EO_WARN_NOT_CONVERGED), on
 * non-finite values (EO_WARN_NOT_CONVERGED), or when a direction has non-positive
 * curvature p_kᵀA p_k ≤ 0 (EO_WARN_NOT_PD: A is not positive definite). In that case
 * x holds the last iterate, or z₀ = M⁻¹ b if it happens at k = 0 without warm start
 * (the preconditioned steepest-descent direction, as truncated Newton–CG does); the
 * negative-curvature direction itself is never added to x, and its curvature pᵀAp is
 * returned in stats->curvature so the caller can fall back to the projected system.
 * x₀ = 0 unless warm_start, which uses the x passed in. Workspace is allocated in
 * eo_cg_analyze; eo_cg_solve does not allocate. A is borrowed from factor on.
 */
#ifndef EO_LINSYS_CG_ITER_H
#define EO_LINSYS_CG_ITER_H

#include <math.h>
#include <string.h>

#include "elastopt/linsolve.h"

typedef struct eo_cg_opts {
    double tol;       /* relative residual ‖b − Ax‖/‖b‖ to reach */
    int max_iters;    /* iteration cap */
    int warm_start;   /* start from the x passed to solve */
    const char *name; /* registry key, prefixes every message */
} eo_cg_opts;

/* z = M⁻¹ r for the preconditioner data `pc` (z never aliases r). */
typedef void (*eo_cg_precond_fn)(const void *pc, const double *r, double *z);

typedef struct eo_cg {
    eo_cg_opts o;
    int n;
    const eo_csc *A; /* borrowed at factor */
    double rtol;     /* eo_linsolve_set_rtol: > 0 overrides o.tol */
    int project_max; /* > 0: give up (EO_WARN_NOT_CONVERGED) from iteration 2 on once the
                        average contraction so far projects more iterations than this */
    double *r, *d, *Ad;
    double *z;       /* M⁻¹ r; NULL without preconditioner (then z is r itself) */
} eo_cg;

static inline void eo_cg_destroy(eo_cg *s, eo_ctx *ctx)
{
    eo_free(ctx, s->r);
    eo_free(ctx, s->d);
    eo_free(ctx, s->Ad);
    eo_free(ctx, s->z);
    s->r = s->d = s->Ad = s->z = NULL;
}

/* Workspace for n = A->n; z only when a preconditioner will be used. */
static inline int eo_cg_analyze(eo_cg *s, const eo_csc *A, int preconditioned, eo_ctx *ctx)
{
    eo_cg_destroy(s, ctx);
    size_t m = (size_t)(A->n ? A->n : 1) * sizeof(double);
    s->n = A->n;
    s->r = eo_malloc(ctx, m);
    s->d = eo_malloc(ctx, m);
    s->Ad = eo_malloc(ctx, m);
    if (preconditioned) s->z = eo_malloc(ctx, m);
    if (!s->r || !s->d || !s->Ad || (preconditioned && !s->z)) {
        eo_cg_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "%s: out of memory (n=%d)", s->o.name, A->n);
    }
    return EO_OK;
}

static inline double eo_cg_dot(int n, const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

static inline void eo_cg_set_rtol(eo_cg *s, double rtol) { s->rtol = rtol > 0 ? rtol : 0; }

/* Solve A x = b; M == NULL: no preconditioner (pc unused). */
static inline int eo_cg_solve(eo_cg *s, eo_cg_precond_fn M, const void *pc, const double *b,
                              double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    const int n = s->n;
    double *r = s->r, *d = s->d, *Ad = s->Ad, *z = M ? s->z : s->r;
    double bnorm = sqrt(eo_cg_dot(n, b, b));
    stats->iterations = 0;
    stats->residual = 0;
    stats->curvature = 0;
    if (!s->o.warm_start || bnorm == 0) memset(x, 0, (size_t)n * sizeof(double));
    if (bnorm == 0) return EO_OK;
    if (s->o.warm_start) {
        eo_csc_symv(s->A, x, r);
        for (int i = 0; i < n; i++) r[i] = b[i] - r[i];
    } else {
        memcpy(r, b, (size_t)n * sizeof(double));
    }
    if (M) M(pc, r, z);
    memcpy(d, z, (size_t)n * sizeof(double));
    double rz = eo_cg_dot(n, r, z);
    double rnorm = M ? sqrt(eo_cg_dot(n, r, r)) : sqrt(rz);
    const double tol = s->rtol > 0 ? s->rtol : s->o.tol;
    const double stop = tol * bnorm, rnorm0 = rnorm;
    int k = 0;
    while (rnorm > stop) {
        int hopeless = 0;
        if (s->project_max > 0 && k >= 2 && rnorm < rnorm0) {
            double rate = pow(rnorm / rnorm0, 1.0 / k);
            hopeless = k + log(stop / rnorm) / log(rate) > s->project_max;
        }
        if (hopeless || k >= s->o.max_iters || !isfinite(rnorm) || !isfinite(rz)) {
            stats->iterations = k;
            stats->residual = rnorm / bnorm;
            return eo_error(ctx, EO_WARN_NOT_CONVERGED,
                            "%s: %s after %d iterations, relative residual %.3g (tol %.3g)",
                            s->o.name,
                            !isfinite(rnorm) ? "non-finite residual" : hopeless ? "given up (contraction too slow)"
                                                                              : "not converged",
                            k,
                            stats->residual, tol);
        }
        eo_csc_symv(s->A, d, Ad);
        double dAd = eo_cg_dot(n, d, Ad);
        if (!(dAd > 0)) {
            if (k == 0 && !s->o.warm_start) memcpy(x, z, (size_t)n * sizeof(double));
            stats->iterations = k;
            stats->residual = rnorm / bnorm;
            stats->curvature = dAd;
            return eo_error(ctx, EO_WARN_NOT_PD,
                            "%s: non-positive curvature p'Ap = %.3g at iteration %d: matrix not "
                            "positive definite",
                            s->o.name, dAd, k);
        }
        double alpha = rz / dAd;
        for (int i = 0; i < n; i++) {
            x[i] += alpha * d[i];
            r[i] -= alpha * Ad[i];
        }
        if (M) M(pc, r, z);
        double rz_new = eo_cg_dot(n, r, z);
        double beta = rz_new / rz; /* r_{k+1}ᵀz_{k+1} / r_kᵀz_k */
        for (int i = 0; i < n; i++) d[i] = z[i] + beta * d[i];
        rz = rz_new;
        rnorm = M ? sqrt(eo_cg_dot(n, r, r)) : sqrt(rz);
        k++;
    }
    stats->iterations = k;
    stats->residual = rnorm / bnorm;
    return EO_OK;
}

#endif
