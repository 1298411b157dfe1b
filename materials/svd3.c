/* 3×3 singular value decomposition with rotations: F = U diag(σ) Vᵀ, U, V ∈ SO(3).
 *
 * Fast path eo_svd3 — one-sided Jacobi (Hestenes) on the columns of F, preconditioned:
 *   A = F V₀, V = V₀ (below); for each column pair (p,q) with α = ‖a_p‖², β = ‖a_q‖²,
 *   γ = a_p·a_q, the plane rotation with t = tan θ = sign(ζ)/(|ζ| + √(1+ζ²)),
 *   ζ = (β−α)/(2γ), makes a_p ⟂ a_q; the same rotation accumulates into V. With
 *   d = β − α, r = √(d² + 4γ²), q = |d| + r it is c = 1/√(1+t²) = q·w, s = c·t =
 *   sign(d)·2γ·w, w = 1/√(2rq) (1 + t² = 2r/q): two square roots and one division per
 *   rotation instead of two and three (the chain of dependent long-latency operations
 *   is most of a rotation's cost). Sweeps stop when every γ² ≤ ε² αβ. Then F V = A has
 *   orthogonal columns whose norms are the singular values. The rotations act on F V₀,
 *   not on FᵀF, so the finish is the plain one-sided Jacobi's, whatever V₀ is.
 * Preconditioner V₀ (precondition): eigenvectors of B = FᵀF in closed form: the two
 *   extreme eigenvalues from the trigonometric solution of the characteristic cubic,
 *   their eigenvectors as the largest cross product of two rows of B − λI (the more
 *   separated one first, the other orthogonalized against it), the third their cross
 *   product. V₀ is orthonormal to rounding whatever its accuracy as eigenvectors, which
 *   only decides how many rotations remain: from F = V₀ = I, Jacobi needs 3–5 sweeps
 *   (9.3 rotations on F = R(I + E), |E_ij| ≤ 0.1, 8.9 on random rotations times
 *   σ ∈ [0.7, 1.4]); after V₀, 1.1–1.8 sweeps and 0.15–1.4 rotations, the common case
 *   one checking sweep. Measured (bench_materials svd, this machine, one thread): 415 →
 *   200 ns per SVD. Where B is a multiple of I to rounding (columns orthogonal already),
 *   where a cross product vanishes (a repeated eigenvalue) or on overflow, V₀ = I.
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

/* Unit eigenvector of the symmetric B (row-major) for its eigenvalue lam: the largest of
 * the three cross products of the rows of B − lam I; 0 if none is positive (rank ≤ 1). */
static int eigvec_cross(const double B[9], double lam, double v[3])
{
    const double r0[3] = {B[0] - lam, B[1], B[2]}, r1[3] = {B[3], B[4] - lam, B[5]}, r2[3] = {B[6], B[7], B[8] - lam};
    double c[3][3];
    cross3(r0, r1, c[0]);
    cross3(r0, r2, c[1]);
    cross3(r1, r2, c[2]);
    const double n0 = dot3(c[0], c[0]), n1 = dot3(c[1], c[1]), n2 = dot3(c[2], c[2]);
    const int best = n0 >= n1 ? (n0 >= n2 ? 0 : 2) : (n1 >= n2 ? 1 : 2);
    const double nb = best == 0 ? n0 : best == 1 ? n1 : n2;
    if (!(nb > 0)) return 0;
    const double s = 1 / sqrt(nb);
    for (int i = 0; i < 3; i++) v[i] = c[best][i] * s;
    return 1;
}

/* A ← A V₀, V ← V₀ with V₀ the eigenvectors of AᵀA (file comment); unchanged where that
 * does not apply. a[c], v[c]: column c. */
static void precondition(double a[3][3], double v[3][3])
{
    double B[9];
    B[0] = dot3(a[0], a[0]), B[4] = dot3(a[1], a[1]), B[8] = dot3(a[2], a[2]);
    B[1] = B[3] = dot3(a[0], a[1]), B[2] = B[6] = dot3(a[0], a[2]), B[5] = B[7] = dot3(a[1], a[2]);
    const double q = (B[0] + B[4] + B[8]) / 3, c0 = B[0] - q, c1 = B[4] - q, c2 = B[8] - q;
    const double off = B[1] * B[1] + B[2] * B[2] + B[5] * B[5];
    const double p2 = (c0 * c0 + c1 * c1 + c2 * c2 + 2 * off) / 6;
    if (!(off > 1e-30 * q * q) || !(p2 > 0)) return; /* orthogonal columns already (or NaN) */
    const double p = sqrt(p2);
    const double det = c0 * (c1 * c2 - B[5] * B[5]) - B[1] * (B[1] * c2 - B[5] * B[2]) + B[2] * (B[1] * B[5] - c1 * B[2]);
    double r = det / (2 * p2 * p); /* cos 3φ of the cubic; NaN on overflow: no V₀ */
    r = r < -1 ? -1 : r > 1 ? 1 : r;
    const double phi = acos(r) / 3;
    const double lhi = q + 2 * p * cos(phi), llo = q + 2 * p * cos(phi + 2.0943951023931954923);
    double w0[3], w1[3], w2[3];
    if (!eigvec_cross(B, r >= 0 ? lhi : llo, w0) || !eigvec_cross(B, r >= 0 ? llo : lhi, w1)) return;
    const double d = dot3(w0, w1);
    for (int i = 0; i < 3; i++) w1[i] -= d * w0[i];
    const double n1 = dot3(w1, w1);
    if (!(n1 > 0.25)) return;
    const double s = 1 / sqrt(n1);
    for (int i = 0; i < 3; i++) w1[i] *= s;
    cross3(w0, w1, w2);
    double a0[3][3];
    memcpy(a0, a, sizeof a0);
    for (int i = 0; i < 3; i++) {
        a[0][i] = a0[0][i] * w0[0] + a0[1][i] * w0[1] + a0[2][i] * w0[2];
        a[1][i] = a0[0][i] * w1[0] + a0[1][i] * w1[1] + a0[2][i] * w1[2];
        a[2][i] = a0[0][i] * w2[0] + a0[1][i] * w2[1] + a0[2][i] * w2[2];
    }
    memcpy(v[0], w0, sizeof w0), memcpy(v[1], w1, sizeof w1), memcpy(v[2], w2, sizeof w2);
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
    precondition(a, v);
    static const int P[3] = {0, 0, 1}, Q[3] = {1, 2, 2};
    for (int sweep = 0; sweep < 40; sweep++) {
        int rotated = 0;
        for (int k = 0; k < 3; k++) {
            int p = P[k], q = Q[k];
            double alpha = dot3(a[p], a[p]), beta = dot3(a[q], a[q]), gamma = dot3(a[p], a[q]);
            if (!(gamma * gamma > (DBL_EPSILON * DBL_EPSILON) * alpha * beta)) continue;
            rotated = 1;
            const double d = beta - alpha, rr = sqrt(d * d + 4 * gamma * gamma), qq = fabs(d) + rr;
            const double w = 1 / sqrt(2 * rr * qq);
            const double cs = qq * w, sn = copysign(2.0, d) * gamma * w;
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
