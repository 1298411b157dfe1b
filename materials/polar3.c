/* Rotation of the polar decomposition consistent with the signed SVD.
 *
 * For F = U diag(σ) Vᵀ with U, V ∈ SO(3) and signed σ (σ1 ≥ σ2 ≥ |σ3|, σ3 < 0 when
 * det F < 0), R = U Vᵀ is the maximizer of f(R) = tr(RᵀF) over SO(3) (max f = σ1+σ2+σ3;
 * the other critical points U D Vᵀ, D = diag(±1) with det D = 1, are saddles or the
 * minimum). It is unique where σ2 + σ3 > 0.
 * Iteration: with M = RᵀF, S = sym(M), t = tr M and R(w) = R exp([w]×),
 *     f(R(w)) = t + w·g − ½ wᵀ H w + O(|w|³),
 *     g = (M₂₁ − M₁₂, M₀₂ − M₂₀, M₁₀ − M₀₁),   H = t I − S,
 * exactly (exp = I + K + ½K² + …, K² = wwᵀ − |w|² I). The direction is Newton's
 * d = H⁻¹ g where H is positive definite (near the maximum its eigenvalues are
 * σ_j + σ_k), else the gradient g, else (g ≈ 0 at a saddle) an eigenvector of H with
 * negative eigenvalue. Along a unit axis d̂ the objective is a sinusoid,
 *     f(θ) = t + b sin θ − c (1 − cos θ),   b = d̂·g,   c = d̂ᵀ H d̂,
 * maximized at θ = atan2(b, c): sin θ = b/ρ, cos θ = c/ρ, ρ = √(b² + c²), so each step
 * is the exact line maximum and needs no trigonometric call; Rodrigues' formula
 * Δ = I + sin θ K + (1 − cos θ) K² updates R ← R Δ, M ← Δᵀ M. Monotone ascent and
 * Newton's quadratic rate near the maximum: 2–5 iterations from the start below.
 * Start: Gram–Schmidt of the columns of F taken in order of decreasing norm, the last
 * axis completed by a cross product with the sign that makes det R = +1 (for a diagonal
 * F this is already the answer). F beyond 2^±200 is scaled by a power of two. */
#include <float.h>
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

/* A unit eigenvector of the smallest eigenvalue of the symmetric 3×3 H (row-major), by
 * the cross products of the rows of H − λ_min I (λ_min from the trigonometric formula). */
static void min_eigvec(const double H[9], double d[3])
{
    double q = (H[0] + H[4] + H[8]) / 3;
    double b00 = H[0] - q, b11 = H[4] - q, b22 = H[8] - q;
    double p2 = (b00 * b00 + b11 * b11 + b22 * b22 + 2 * (H[1] * H[1] + H[2] * H[2] + H[5] * H[5])) / 6;
    double p = sqrt(p2), lam = q;
    if (p > 0) {
        double r = (b00 * (b11 * b22 - H[5] * H[5]) - H[1] * (H[1] * b22 - H[5] * H[2]) +
                    H[2] * (H[1] * H[5] - b11 * H[2])) / (2 * p2 * p);
        r = r < -1 ? -1 : r > 1 ? 1 : r;
        lam = q + 2 * p * cos(acos(r) / 3 + 2.0943951023931954923);
    }
    double r0[3] = {H[0] - lam, H[1], H[2]}, r1[3] = {H[3], H[4] - lam, H[5]}, r2[3] = {H[6], H[7], H[8] - lam};
    double c[3][3];
    cross3(r0, r1, c[0]), cross3(r0, r2, c[1]), cross3(r1, r2, c[2]);
    int best = 0;
    double nb = dot3(c[0], c[0]);
    for (int k = 1; k < 3; k++)
        if (dot3(c[k], c[k]) > nb) nb = dot3(c[k], c[k]), best = k;
    if (!(nb > 0)) { /* H − λI of rank ≤ 1: any axis of least curvature */
        int k = H[0] <= H[4] && H[0] <= H[8] ? 0 : H[4] <= H[8] ? 1 : 2;
        d[0] = d[1] = d[2] = 0, d[k] = 1;
        return;
    }
    double s = 1 / sqrt(nb);
    for (int i = 0; i < 3; i++) d[i] = c[best][i] * s;
}

int eo_polar3(const double F[9], double R[9])
{
    double A[9], mx = 0;
    for (int i = 0; i < 9; i++) mx = fmax(mx, fabs(F[i]));
    memcpy(A, F, sizeof A);
    if (mx > 0x1p200 || (mx < 0x1p-200 && mx > 0)) {
        int ex;
        frexp(mx, &ex);
        for (int i = 0; i < 9; i++) A[i] = ldexp(A[i], -ex);
    }
    /* start: columns by decreasing norm, Gram–Schmidt, completed to SO(3) */
    double col[3][3], n[3];
    for (int c = 0; c < 3; c++) {
        for (int r = 0; r < 3; r++) col[c][r] = A[3 * r + c];
        n[c] = dot3(col[c], col[c]);
    }
    int p0 = 0, p1 = 1, p2 = 2, t;
    if (n[p0] < n[p1]) t = p0, p0 = p1, p1 = t;
    if (n[p0] < n[p2]) t = p0, p0 = p2, p2 = t;
    if (n[p1] < n[p2]) t = p1, p1 = p2, p2 = t;
    double q[3][3] = {{0}};
    if (!(n[p0] > 0)) { /* F = 0 */
        static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        memcpy(R, I3, sizeof I3);
        return 0;
    }
    double s0 = 1 / sqrt(n[p0]);
    for (int r = 0; r < 3; r++) q[p0][r] = col[p0][r] * s0;
    double dd = dot3(q[p0], col[p1]), w[3];
    for (int r = 0; r < 3; r++) w[r] = col[p1][r] - dd * q[p0][r];
    double nw = dot3(w, w);
    if (!(nw > 1e-30 * n[p0])) { /* rank 1: any unit vector orthogonal to q[p0] */
        int m = 0;
        for (int r = 1; r < 3; r++)
            if (fabs(q[p0][r]) < fabs(q[p0][m])) m = r;
        double e[3] = {0, 0, 0};
        e[m] = 1;
        dd = q[p0][m];
        for (int r = 0; r < 3; r++) w[r] = e[r] - dd * q[p0][r];
        nw = dot3(w, w);
    }
    double s1 = 1 / sqrt(nw);
    for (int r = 0; r < 3; r++) q[p1][r] = w[r] * s1;
    cross3(q[p0], q[p1], q[p2]);
    /* (p0,p1,p2) odd permutation of (0,1,2): the cross product must be negated */
    int even = (p0 == 0 && p1 == 1) || (p0 == 1 && p1 == 2) || (p0 == 2 && p1 == 0);
    if (!even)
        for (int r = 0; r < 3; r++) q[p2][r] = -q[p2][r];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) R[3 * r + c] = q[c][r];

    double M[9]; /* M = Rᵀ A */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) M[3 * i + j] = R[i] * A[j] + R[3 + i] * A[3 + j] + R[6 + i] * A[6 + j];
    double scale = 0;
    for (int i = 0; i < 9; i++) scale += A[i] * A[i];
    scale = sqrt(scale);
    int it;
    for (it = 0; it < 40; it++) {
        double g[3] = {M[7] - M[5], M[2] - M[6], M[3] - M[1]};
        double tr = M[0] + M[4] + M[8];
        double H[9] = {tr - M[0], -0.5 * (M[1] + M[3]), -0.5 * (M[2] + M[6]), 0, tr - M[4], -0.5 * (M[5] + M[7]),
                       0, 0, tr - M[8]};
        H[3] = H[1], H[6] = H[2], H[7] = H[5];
        double gg = dot3(g, g), gtol = 4 * DBL_EPSILON * scale;
        /* positive definite: leading minors; adjugate solve */
        double m2 = H[0] * H[4] - H[1] * H[1];
        double a0 = H[4] * H[8] - H[5] * H[5], a1 = H[2] * H[5] - H[1] * H[8], a2 = H[1] * H[5] - H[2] * H[4];
        double det = H[0] * a0 + H[1] * a1 + H[2] * a2;
        int pd = H[0] > 0 && m2 > 0 && det > 0;
        double d[3];
        if (pd) {
            if (gg <= gtol * gtol) break;
            double a4 = H[0] * H[8] - H[2] * H[2], a5 = H[1] * H[2] - H[0] * H[5];
            d[0] = a0 * g[0] + a1 * g[1] + a2 * g[2];
            d[1] = a1 * g[0] + a4 * g[1] + a5 * g[2];
            d[2] = a2 * g[0] + a5 * g[1] + m2 * g[2];
        } else if (gg > gtol * gtol) {
            memcpy(d, g, sizeof d);
        } else {
            /* stationary but not a maximum: escape along negative curvature, if any */
            min_eigvec(H, d);
            double c = d[0] * (H[0] * d[0] + H[1] * d[1] + H[2] * d[2]) +
                       d[1] * (H[3] * d[0] + H[4] * d[1] + H[5] * d[2]) +
                       d[2] * (H[6] * d[0] + H[7] * d[1] + H[8] * d[2]);
            if (!(c < -1e-12 * scale)) break; /* σ2 + σ3 ≈ 0: R not unique, keep it */
            if (dot3(d, g) < 0) d[0] = -d[0], d[1] = -d[1], d[2] = -d[2];
        }
        double nd = sqrt(dot3(d, d));
        if (!(nd > 0)) break;
        for (int k = 0; k < 3; k++) d[k] /= nd;
        double b = dot3(d, g);
        double c = d[0] * (H[0] * d[0] + H[1] * d[1] + H[2] * d[2]) + d[1] * (H[3] * d[0] + H[4] * d[1] + H[5] * d[2]) +
                   d[2] * (H[6] * d[0] + H[7] * d[1] + H[8] * d[2]);
        double rho = sqrt(b * b + c * c);
        if (!(rho > 0)) break;
        double sn = b / rho, omc = c > 0 ? b * b / (rho * (rho + c)) : (rho - c) / rho; /* 1 − cos θ */
        /* Δ = I + sn K + omc K², K = [d]× */
        double K2[9] = {d[0] * d[0] - 1, d[0] * d[1], d[0] * d[2], d[1] * d[0], d[1] * d[1] - 1, d[1] * d[2],
                        d[2] * d[0], d[2] * d[1], d[2] * d[2] - 1};
        double D[9] = {1 + omc * K2[0], -sn * d[2] + omc * K2[1], sn * d[1] + omc * K2[2],
                       sn * d[2] + omc * K2[3], 1 + omc * K2[4], -sn * d[0] + omc * K2[5],
                       -sn * d[1] + omc * K2[6], sn * d[0] + omc * K2[7], 1 + omc * K2[8]};
        double T[9];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) T[3 * i + j] = R[3 * i] * D[j] + R[3 * i + 1] * D[3 + j] + R[3 * i + 2] * D[6 + j];
        memcpy(R, T, sizeof T);
        for (int i = 0; i < 3; i++) /* Δᵀ M */
            for (int j = 0; j < 3; j++) T[3 * i + j] = D[i] * M[j] + D[3 + i] * M[3 + j] + D[6 + i] * M[6 + j];
        memcpy(M, T, sizeof T);
        if (pd && fabs(sn) < 1e-9) {
            it++;
            break;
        }
    }
    return it;
}
