/* Internal: zero-fill incomplete Cholesky IC(0) on the pattern of our upper CSC
 * (shared by pcg.c and gmres.c; not a public header).
 *
 *   M = L Lᵀ,  l_jk = (a_jk − Σ_{m<k} l_jm l_km) / l_kk  for (j,k) in the pattern,
 *   l_jj = sqrt(a_jj − Σ_{m<j} l_jm²)     (Meijerink & van der Vorst 1977).
 *
 * The rows of L are the columns of the upper CSC, so L shares A's pattern. IC(0) can
 * break down (l_jj² <= 0) for SPD matrices that are not M-matrices; eo_ic0_factor then
 * recomputes it for A + σ diag(A) with σ = 1e-3, 4e-3, ... (Manteuffel's shift) up to
 * 8 times and returns 0 if every shift failed (the caller falls back to Jacobi). */
#ifndef EO_LINSYS_IC0_H
#define EO_LINSYS_IC0_H

#include <math.h>

#include "elastopt/linsolve.h"

/* IC(0) of A + sigma·diag(A) into L (nnz), w (n) zero scratch. -1 on success, else the
 * failing row (w is then dirty). */
static inline int eo_ic0_try(const eo_csc *A, double sigma, double *L, double *w)
{
    const int *cp = A->colptr, *ri = A->rowind;
    for (int j = 0; j < A->n; j++) {
        int end = cp[j + 1] - 1; /* diagonal position */
        for (int p = cp[j]; p < end; p++) {
            int k = ri[p];
            double v = A->val[p];
            for (int q = cp[k]; q < cp[k + 1] - 1; q++) v -= L[q] * w[ri[q]];
            v /= L[cp[k + 1] - 1];
            L[p] = v;
            w[k] = v;
        }
        double djj = A->val[end] * (1 + sigma);
        for (int p = cp[j]; p < end; p++) {
            djj -= L[p] * L[p];
            w[ri[p]] = 0;
        }
        if (!(djj > 0) || !isfinite(djj)) return j;
        L[end] = sqrt(djj);
    }
    return -1;
}

/* 1 if an IC(0) factor (possibly shifted) was found, 0 if every shift broke down. */
static inline int eo_ic0_factor(const eo_csc *A, double *L, double *w, const char *who, eo_ctx *ctx)
{
    double sigma = 0;
    for (int t = 0; t <= 8; t++) {
        int bad = eo_ic0_try(A, sigma, L, w);
        if (bad < 0) return 1;
        for (int i = 0; i < A->n; i++) w[i] = 0; /* scratch may be dirty at failure */
        eo_log(ctx, EO_LOG_DEBUG, "%s: IC(0) breakdown at row %d with shift %g", who, bad, sigma);
        sigma = sigma == 0 ? 1e-3 : 4 * sigma;
    }
    eo_log(ctx, EO_LOG_INFO, "%s: IC(0) failed with every shift; using Jacobi", who);
    return 0;
}

/* z = (L Lᵀ)⁻¹ r (z must not alias r). */
static inline void eo_ic0_apply(const eo_csc *A, const double *L, const double *r, double *z)
{
    const int n = A->n, *cp = A->colptr, *ri = A->rowind;
    for (int j = 0; j < n; j++) { /* L y = r, rows of L */
        double v = r[j];
        for (int p = cp[j]; p < cp[j + 1] - 1; p++) v -= L[p] * z[ri[p]];
        z[j] = v / L[cp[j + 1] - 1];
    }
    for (int j = n - 1; j >= 0; j--) { /* Lᵀ z = y, columns of Lᵀ = rows of L */
        z[j] /= L[cp[j + 1] - 1];
        double zj = z[j];
        for (int p = cp[j]; p < cp[j + 1] - 1; p++) z[ri[p]] -= L[p] * zj;
    }
}

#endif
