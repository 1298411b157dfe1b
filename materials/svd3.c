/* 3×3 singular value decomposition with rotations: F = U diag(σ) Vᵀ, U, V ∈ SO(3).
 *
 * Fast path eo_svd3 — one-sided Jacobi (Hestenes) on the columns of F:
 *   A = F, V = I; for each column pair (p,q) with α = ‖a_p‖², β = ‖a_q‖², γ = a_p·a_q,
 *   a plane rotation with ζ = (β−α)/(2γ), t = sign(ζ)/(|ζ| + √(1+ζ²)), c = 1/√(1+t²),
 *   s = c t makes a_p ⟂ a_q; the same rotation accumulates into V. Sweeps stop when
 *   every γ² ≤ ε² αβ (quadratic convergence, typically 3–5 sweeps). Then F V = A has
 *   orthogonal columns whose norms are the singular values. Because the rotations act
 *   on F itself (not on FᵀF), small σ keep their relative accuracy.
 * Finishing:
 *   - columns sorted by norm, descending; if det V < 0 the last columns of V and A are
 *     negated (F = A Vᵀ still holds), so V ∈ SO(3);
 *   - u1 = a1/‖a1‖ (U = I, σ = 0 if F = 0); u2 = a2 Gram–Schmidt'ed against u1, or any
 *     unit vector ⟂ u1 when a2 vanishes (rank 1); u3 = u1 × u2 always, so U ∈ SO(3)
 *     without dividing by a small σ3;
 *   - σ_i = u_iᵀ a_i; σ3 is signed and carries the sign of det F (inverted elements).
 * F with entries beyond 2^±200 is scaled by an exact power of two first.
 * Reference eo_svd3_lapack — LAPACKE_dgesvd, then the same sign convention: if
 * det U < 0 negate u3 and σ3; if det V < 0 negate v3 and σ3. */
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <string.h>

#include "elastopt/material.h"

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double det_cols(double m[3][3])
{
    double c[3];
    cross3(m[1], m[2], c);
    return dot3(m[0], c);
}

static void swap_cols(double a[3][3], double v[3][3], double n[3], int i, int j)
{
    double t[3];
    memcpy(t, a[i], sizeof t), memcpy(a[i], a[j], sizeof t), memcpy(a[j], t, sizeof t);
    memcpy(t, v[i], sizeof t), memcpy(v[i], v[j], sizeof t), memcpy(v[j], t, sizeof t);
    double s = n[i];
    n[i] = n[j], n[j] = s;
}

void eo_svd3(const double F[9], double U[9], double s[3], double V[9])
{
    /* a[c] = column c of F, v[c] = column c of V */
    double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double mx = 0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) a[c][r] = F[3 * r + c], mx = fmax(mx, fabs(F[3 * r + c]));
    /* Exact power-of-two scaling keeps γ² and αβ below overflow / above underflow. */
    int ex = 0;
    if (mx > 0x1p200 || (mx < 0x1p-200 && mx > 0)) {
        frexp(mx, &ex);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) a[c][r] = ldexp(a[c][r], -ex);
    }
    static const int P[3] = {0, 0, 1}, Q[3] = {1, 2, 2};
    for (int sweep = 0; sweep < 40; sweep++) {
        int rotated = 0;
        for (int k = 0; k < 3; k++) {
            int p = P[k], q = Q[k];
            double alpha = dot3(a[p], a[p]), beta = dot3(a[q], a[q]), gamma = dot3(a[p], a[q]);
            if (!(gamma * gamma > (DBL_EPSILON * DBL_EPSILON) * alpha * beta)) continue;
            rotated = 1;
            double zeta = (beta - alpha) / (2 * gamma);
            double t = fabs(zeta) > 1e150 ? 0.5 / zeta
                                          : copysign(1.0, zeta) / (fabs(zeta) + sqrt(1 + zeta * zeta));
            double cs = 1 / sqrt(1 + t * t), sn = cs * t;
            for (int r = 0; r < 3; r++) {
                double ap = a[p][r], aq = a[q][r];
                a[p][r] = cs * ap - sn * aq;
                a[q][r] = sn * ap + cs * aq;
                double vp = v[p][r], vq = v[q][r];
                v[p][r] = cs * vp - sn * vq;
                v[q][r] = sn * vp + cs * vq;
            }
        }
        if (!rotated) break;
    }
    double n[3] = {dot3(a[0], a[0]), dot3(a[1], a[1]), dot3(a[2], a[2])};
    if (n[0] < n[1]) swap_cols(a, v, n, 0, 1);
    if (n[0] < n[2]) swap_cols(a, v, n, 0, 2);
    if (n[1] < n[2]) swap_cols(a, v, n, 1, 2);
    if (det_cols(v) < 0)
        for (int r = 0; r < 3; r++) v[2][r] = -v[2][r], a[2][r] = -a[2][r];

    double u[3][3];
    double n0 = sqrt(n[0]);
    if (!(n0 > 0)) { /* F = 0 */
        memset(u, 0, sizeof u);
        u[0][0] = u[1][1] = u[2][2] = 1;
    } else {
        for (int r = 0; r < 3; r++) u[0][r] = a[0][r] / n0;
        double d = dot3(u[0], a[1]), w[3];
        for (int r = 0; r < 3; r++) w[r] = a[1][r] - d * u[0][r];
        double nw = sqrt(dot3(w, w));
        if (!(nw > 1e-300)) { /* rank 1: any unit vector orthogonal to u1 */
            int m = 0;
            for (int r = 1; r < 3; r++)
                if (fabs(u[0][r]) < fabs(u[0][m])) m = r;
            double e[3] = {0, 0, 0};
            e[m] = 1;
            d = u[0][m];
            for (int r = 0; r < 3; r++) w[r] = e[r] - d * u[0][r];
            nw = sqrt(dot3(w, w));
        }
        for (int r = 0; r < 3; r++) u[1][r] = w[r] / nw;
        cross3(u[0], u[1], u[2]);
    }
    s[0] = dot3(u[0], a[0]);
    s[1] = dot3(u[1], a[1]);
    s[2] = dot3(u[2], a[2]);
    if (ex)
        for (int k = 0; k < 3; k++) s[k] = ldexp(s[k], ex);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            U[3 * r + c] = u[c][r];
            V[3 * r + c] = v[c][r];
        }
}

static double det_rm(const double M[9])
{
    return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
           M[2] * (M[3] * M[7] - M[4] * M[6]);
}

int eo_svd3_lapack(const double F[9], double U[9], double s[3], double V[9])
{
    double A[9], VT[9], superb[2];
    memcpy(A, F, sizeof A);
    lapack_int info = LAPACKE_dgesvd(LAPACK_ROW_MAJOR, 'A', 'A', 3, 3, A, 3, s, U, 3, VT, 3, superb);
    if (info != 0) return EO_ERR_INTERNAL;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) V[3 * r + c] = VT[3 * c + r];
    if (det_rm(U) < 0) {
        for (int r = 0; r < 3; r++) U[3 * r + 2] = -U[3 * r + 2];
        s[2] = -s[2];
    }
    if (det_rm(V) < 0) {
        for (int r = 0; r < 3; r++) V[3 * r + 2] = -V[3 * r + 2];
        s[2] = -s[2];
    }
    return EO_OK;
}
