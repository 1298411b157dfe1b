/* Internal: the shared engine of the stationary iterations jacobi.c, gauss_seidel.c and
 * sor.c (not a public header). Each method file owns its params struct and descriptor
 * table and copies the common fields into eo_stat_opts.
 *
 * Splitting A = D + L + U (D diagonal, L/U strictly lower/upper):
 *   Jacobi        x_{k+1} = x_k + D⁻¹ (b − A x_k)
 *   Gauss–Seidel  (D + L) x_{k+1} = b − U x_k        (forward sweep, new values used)
 *   SOR           (D + ωL) x_{k+1} = ω b − (ωU + (ω−1)D) x_k,   0 < ω < 2
 * Gauss–Seidel and SOR converge for every SPD A; Jacobi only when the spectral radius
 * of I − D⁻¹A is < 1 (e.g. strict diagonal dominance) — SPD FEM matrices need not
 * qualify (ERRATA), so every solve checks, after each sweep, the true residual
 * r = b − A x and stops with EO_WARN_NOT_CONVERGED (stats.residual set) when
 *   ‖r‖ > 1e6 ‖r₀‖ or non-finite         (diverged)
 *   ‖r‖ did not drop below 0.99 × its best value within 1000 iterations  (stagnated)
 *   max_iters reached
 * and with EO_OK when ‖r‖ ≤ tol ‖b‖. Rows of the full symmetric matrix are needed for
 * the sweeps: built once in analyze (eo_csc_full), values gathered in factor. A
 * diagonal entry ≤ 0 proves A not SPD: factor returns EO_WARN_NOT_PD with the column.
 */
#ifndef EO_LINSYS_STATIONARY_H
#define EO_LINSYS_STATIONARY_H

#include <math.h>
#include <string.h>

#include "elastopt/linsolve.h"

enum { EO_STAT_JACOBI, EO_STAT_SOR };

#define EO_STAT_DIVERGE 1e6
#define EO_STAT_STALL_WINDOW 1000
#define EO_STAT_STALL_FACTOR 0.99

typedef struct eo_stat_opts {
    double tol;
    int max_iters;
    int warm_start;
    double omega; /* SOR relaxation (1 = Gauss–Seidel) */
    int method;   /* EO_STAT_JACOBI or EO_STAT_SOR */
    const char *name;
} eo_stat_opts;

typedef struct eo_stat {
    eo_stat_opts o;
    int n;
    eo_csc_full *F;
    double *r, *dinv;
} eo_stat;

static inline void eo_stat_destroy(eo_stat *s, eo_ctx *ctx)
{
    eo_csc_full_destroy(&s->F);
    eo_free(ctx, s->r);
    eo_free(ctx, s->dinv);
    s->r = s->dinv = NULL;
}

static inline int eo_stat_analyze(eo_stat *s, const eo_csc *A, eo_ctx *ctx)
{
    eo_stat_destroy(s, ctx);
    s->n = A->n;
    size_t m = (size_t)(A->n ? A->n : 1) * sizeof(double);
    int rc = eo_csc_full_create(ctx, A, &s->F);
    if (rc < 0) return rc;
    s->r = eo_malloc(ctx, m);
    s->dinv = eo_malloc(ctx, m);
    if (!s->r || !s->dinv) {
        eo_stat_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "%s: out of memory (n=%d)", s->o.name, A->n);
    }
    return EO_OK;
}

static inline int eo_stat_factor(eo_stat *s, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    eo_csc_full_fill(s->F, A);
    for (int j = 0; j < s->n; j++) {
        double a = s->F->val[s->F->diag[j]];
        if (!(a > 0)) {
            stats->not_pd_column = j;
            return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", j),
                               "%s: diagonal entry %.3g <= 0: matrix not positive definite",
                               s->o.name, a);
        }
        s->dinv[j] = 1 / a;
    }
    return EO_OK;
}

/* r = b − A x with the full rows; returns ‖r‖. */
static inline double eo_stat_residual(const eo_stat *s, const double *b, const double *x, double *r)
{
    const eo_csc_full *F = s->F;
    double rr = 0;
    for (int i = 0; i < s->n; i++) {
        double v = b[i];
        for (int q = F->colptr[i]; q < F->colptr[i + 1]; q++) v -= F->val[q] * x[F->rowind[q]];
        r[i] = v;
        rr += v * v;
    }
    return sqrt(rr);
}

static inline int eo_stat_solve(eo_stat *s, const double *b, double *x, eo_linsolve_stats *stats,
                                eo_ctx *ctx)
{
    const int n = s->n;
    const eo_csc_full *F = s->F;
    const double w = s->o.omega;
    double bnorm = 0;
    for (int i = 0; i < n; i++) bnorm += b[i] * b[i];
    bnorm = sqrt(bnorm);
    if (!s->o.warm_start) memset(x, 0, (size_t)n * sizeof(double));
    stats->iterations = 0;
    stats->residual = 0;
    if (bnorm == 0) {
        memset(x, 0, (size_t)n * sizeof(double));
        return EO_OK;
    }
    double rnorm = eo_stat_residual(s, b, x, s->r), r0 = rnorm, best = rnorm;
    const double stop = s->o.tol * bnorm;
    int k = 0, best_at = 0;
    const char *why = NULL;
    while (rnorm > stop) {
        if (!isfinite(rnorm) || rnorm > EO_STAT_DIVERGE * r0) why = "diverged";
        else if (k - best_at >= EO_STAT_STALL_WINDOW) why = "stagnated";
        else if (k >= s->o.max_iters) why = "reached max_iters";
        if (why) break;
        if (s->o.method == EO_STAT_JACOBI) {
            for (int i = 0; i < n; i++) x[i] += s->r[i] * s->dinv[i];
        } else {
            for (int i = 0; i < n; i++) {
                double sigma = 0;
                for (int q = F->colptr[i]; q < F->colptr[i + 1]; q++) sigma += F->val[q] * x[F->rowind[q]];
                /* sigma includes a_ii x_i: x_i + ω (b_i − Σ_j a_ij x_j) / a_ii */
                x[i] += w * (b[i] - sigma) * s->dinv[i];
            }
        }
        k++;
        rnorm = eo_stat_residual(s, b, x, s->r);
        if (rnorm < EO_STAT_STALL_FACTOR * best) {
            best = rnorm;
            best_at = k;
        }
    }
    stats->iterations = k;
    stats->residual = rnorm / bnorm;
    if (why)
        return eo_error(ctx, EO_WARN_NOT_CONVERGED,
                        "%s: %s after %d iterations, relative residual %.3g (tol %.3g)", s->o.name,
                        why, k, stats->residual, s->o.tol);
    return EO_OK;
}

#endif
