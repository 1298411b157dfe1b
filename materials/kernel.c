/* Shared material kernel: ψ, P, ∂P/∂F (analytic eigensystem) and the tet element.
 *
 * Isotropic models (sigma_eval): with F = U Σ Vᵀ (eo_svd3, U, V ∈ SO(3), signed σ3),
 *     P = U diag(ψ_1, ψ_2, ψ_3) Vᵀ,
 *     ∂P/∂F = Σ_k λ_k vec(Q_k) vec(Q_k)ᵀ   (vec row-major: index 3a+b), where
 *   scaling  Q_m = U diag(w_m) Vᵀ,  λ_m = ν_m,  (ν_m, w_m) eigenpairs of ∂²ψ/∂σ² (3×3
 *            cyclic Jacobi — the only numeric eigensolve, on a 3×3);
 *   pair (i,j) ∈ {(0,1),(0,2),(1,2)}:
 *            Q = (u_i v_jᵀ + u_j v_iᵀ)/√2,  λ = twist_ij = (ψ_i − ψ_j)/(σ_i − σ_j),
 *            Q = (u_i v_jᵀ − u_j v_iᵀ)/√2,  λ = flip_ij  = (ψ_i + ψ_j)/(σ_i + σ_j).
 *   Derivation (Teran et al. 2005; Smith, de Goes & Kim 2019): write dF = U A Vᵀ, dU =
 *   U Ω_U, dV = V Ω_V (skew). Then A = Ω_U Σ + dΣ − Σ Ω_V and Uᵀ dP V = Ω_U Ψ + dΨ − Ψ Ω_V.
 *   A diagonal: dΨ = (∂²ψ/∂σ²) dΣ. A = e_i e_jᵀ + e_j e_iᵀ: Ω_U = Ω_V = K/(σ_j − σ_i),
 *   K = e_i e_jᵀ − e_j e_iᵀ, so Uᵀ dP V = twist_ij A. A = K: Ω_U = −Ω_V = K/(σ_i + σ_j),
 *   so Uᵀ dP V = flip_ij A. The nine Q_k are orthonormal in the Frobenius product.
 *   Projection: λ_k → max(λ_k, 0) (EO_PROJ_CLAMP) or |λ_k| (EO_PROJ_ABS).
 * F-space models (F_eval, `linear`): ψ, P, ∂P/∂F as given; the Hessian is constant and
 *   PSD, so the projection is the identity.
 *
 * Tet element (notes §4.2–4.3, ERRATA): Ds = [x0−x3, x1−x3, x2−x3], F = Ds Dm⁻¹,
 *   vec(F) = (Dm⁻ᵀ S ⊗ I3) x. The adjoint map B: 3×3 Q ↦ 12-vector ∂(F:Q)/∂x is
 *   vertex c ∈ {0,1,2}: column c of Q Dm⁻ᵀ; vertex 3: minus their sum.
 *   energy = w ψ, grad = w B(P), Hessian = w Σ_k λ_k B(Q_k) B(Q_k)ᵀ (nine rank-1
 *   updates of 12×12; for F-space models w Bᵀ ∂P/∂F B applied column- then row-wise).
 *   No allocation. */
#include <math.h>
#include <string.h>

#include "elastopt/material.h"

static double det3(const double M[9])
{
    return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
           M[2] * (M[3] * M[7] - M[4] * M[6]);
}

/* Symmetric 3×3 eigen-decomposition, cyclic Jacobi. A row-major (destroyed copy taken),
 * d eigenvalues, W row-major with eigenvectors in columns. */
static void eig_sym3(const double Ain[9], double d[3], double W[9])
{
    double A[9];
    memcpy(A, Ain, sizeof A);
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(W, I3, sizeof I3);
    static const int P[3] = {0, 0, 1}, Q[3] = {1, 2, 2};
    for (int sweep = 0; sweep < 30; sweep++) {
        double off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
        double diag = A[0] * A[0] + A[4] * A[4] + A[8] * A[8];
        if (!(off > 1e-36 * diag)) break;
        for (int k = 0; k < 3; k++) {
            int p = P[k], q = Q[k];
            double apq = A[3 * p + q];
            if (apq == 0) continue;
            double theta = (A[3 * q + q] - A[3 * p + p]) / (2 * apq);
            double t = fabs(theta) > 1e150 ? 0.5 / theta
                                           : copysign(1.0, theta) / (fabs(theta) + sqrt(theta * theta + 1));
            double c = 1 / sqrt(t * t + 1), s = t * c;
            /* A ← Jᵀ A J, J = rotation in (p,q): J_pp = J_qq = c, J_pq = s, J_qp = −s */
            for (int r = 0; r < 3; r++) { /* columns */
                double arp = A[3 * r + p], arq = A[3 * r + q];
                A[3 * r + p] = c * arp - s * arq;
                A[3 * r + q] = s * arp + c * arq;
            }
            for (int r = 0; r < 3; r++) { /* rows */
                double apr = A[3 * p + r], aqr = A[3 * q + r];
                A[3 * p + r] = c * apr - s * aqr;
                A[3 * q + r] = s * apr + c * aqr;
            }
            A[3 * p + q] = A[3 * q + p] = 0;
            for (int r = 0; r < 3; r++) {
                double wrp = W[3 * r + p], wrq = W[3 * r + q];
                W[3 * r + p] = c * wrp - s * wrq;
                W[3 * r + q] = s * wrp + c * wrq;
            }
        }
    }
    d[0] = A[0], d[1] = A[4], d[2] = A[8];
}

/* The nine modes: eigenvalues lam (unprojected) and orthonormal vec(Q_k). */
typedef struct modes {
    double lam[9];
    double q[9][9];
} modes;

static void build_modes(const eo_sigma_eval *se, const double U[9], const double V[9], modes *m)
{
    double d[3], W[9];
    eig_sym3(se->H, d, W);
    for (int k = 0; k < 3; k++) {
        m->lam[k] = d[k];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                m->q[k][3 * a + b] = U[3 * a + 0] * W[0 + k] * V[3 * b + 0] +
                                     U[3 * a + 1] * W[3 + k] * V[3 * b + 1] +
                                     U[3 * a + 2] * W[6 + k] * V[3 * b + 2];
    }
    static const int PI[3] = {0, 0, 1}, PJ[3] = {1, 2, 2};
    const double r2 = 0.70710678118654752440;
    for (int p = 0; p < 3; p++) {
        int i = PI[p], j = PJ[p];
        m->lam[3 + p] = se->twist[p];
        m->lam[6 + p] = se->flip[p];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double x = U[3 * a + i] * V[3 * b + j], y = U[3 * a + j] * V[3 * b + i];
                m->q[3 + p][3 * a + b] = r2 * (x + y);
                m->q[6 + p][3 * a + b] = r2 * (x - y);
            }
    }
}

static double project(double l, eo_proj proj)
{
    switch (proj) {
    case EO_PROJ_CLAMP: return l > 0 ? l : 0;
    case EO_PROJ_ABS: return fabs(l);
    case EO_PROJ_NONE: break;
    }
    return l;
}

/* Shared front half of both evaluations: SVD, σ-space model, P. Returns ψ. */
static double iso_eval(const eo_material_type *mt, const eo_material_coef *c, const double F[9],
                       eo_eval_what what, double U[9], double s[3], double V[9], eo_sigma_eval *se,
                       double P[9])
{
    eo_svd3(F, U, s, V);
    memset(se, 0, sizeof *se);
    mt->sigma_eval(c, s, what, se);
    if (!(se->psi < INFINITY)) {
        se->psi = INFINITY;
        return INFINITY;
    }
    if (what >= EO_EVAL_GRAD)
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                P[3 * a + b] = U[3 * a + 0] * se->g[0] * V[3 * b + 0] + U[3 * a + 1] * se->g[1] * V[3 * b + 1] +
                               U[3 * a + 2] * se->g[2] * V[3 * b + 2];
    return se->psi;
}

int eo_material_evaluate(const eo_material_type *mt, const eo_material_coef *c,
                         const double F[9], eo_eval_what what, eo_proj proj,
                         eo_material_eval *out)
{
    memset(out, 0, sizeof *out);
    out->J = det3(F);
    if (mt->flags & EO_MATERIAL_EDGE) {
        eo_svd3(F, out->U, out->sigma, out->V);
        return EO_ERR_UNSUPPORTED;
    }
    if (mt->F_eval) {
        eo_svd3(F, out->U, out->sigma, out->V);
        out->psi = mt->F_eval(c, F, what, what >= EO_EVAL_GRAD ? out->P : NULL,
                              what >= EO_EVAL_HESS ? out->dPdF : NULL);
        if (what >= EO_EVAL_HESS) {
            /* linear: ∂P/∂F = μ(I + T) + λ vec(I)vec(I)ᵀ, eigenvalues 2μ+3λ, 2μ (×5), 0 (×3) */
            double mu = c->mu, la = c->lambda;
            double e[9] = {2 * mu + 3 * la, 2 * mu, 2 * mu, 2 * mu, 2 * mu, 2 * mu, 0, 0, 0};
            memcpy(out->eig, e, sizeof e);
        }
        return EO_OK;
    }
    eo_sigma_eval se;
    out->psi = iso_eval(mt, c, F, what, out->U, out->sigma, out->V, &se, out->P);
    if (!(out->psi < INFINITY) || what < EO_EVAL_HESS) return EO_OK;
    modes m;
    build_modes(&se, out->U, out->V, &m);
    memcpy(out->eig, m.lam, sizeof m.lam);
    for (int k = 0; k < 9; k++) {
        double l = project(m.lam[k], proj);
        if (l == 0) continue;
        const double *q = m.q[k];
        for (int r = 0; r < 9; r++) {
            double lq = l * q[r];
            for (int t = r; t < 9; t++) out->dPdF[9 * r + t] += lq * q[t];
        }
    }
    for (int r = 0; r < 9; r++)
        for (int t = 0; t < r; t++) out->dPdF[9 * r + t] = out->dPdF[9 * t + r];
    return EO_OK;
}

/* B: 3×3 Q (row-major) ↦ 12-vector ∂(F:Q)/∂x. */
static void adjoint_map(const double Dminv[9], const double Q[9], double g[12])
{
    for (int a = 0; a < 3; a++) {
        double s = 0;
        for (int cidx = 0; cidx < 3; cidx++) {
            double v = Q[3 * a + 0] * Dminv[3 * cidx + 0] + Q[3 * a + 1] * Dminv[3 * cidx + 1] +
                       Q[3 * a + 2] * Dminv[3 * cidx + 2];
            g[3 * cidx + a] = v;
            s += v;
        }
        g[9 + a] = -s;
    }
}

int eo_tet_evaluate(const eo_material_type *mt, const eo_material_coef *c,
                    const double Dminv[9], double w, const double x[12], eo_eval_what what,
                    eo_proj proj, eo_tet_out *out)
{
    if (mt->flags & EO_MATERIAL_EDGE) return EO_ERR_UNSUPPORTED;
    double F[9];
    for (int a = 0; a < 3; a++) {
        double ds0 = x[a] - x[9 + a], ds1 = x[3 + a] - x[9 + a], ds2 = x[6 + a] - x[9 + a];
        for (int b = 0; b < 3; b++) F[3 * a + b] = ds0 * Dminv[b] + ds1 * Dminv[3 + b] + ds2 * Dminv[6 + b];
    }
    out->J = det3(F);
    double P[9];
    if (mt->F_eval) {
        double dPdF[81];
        out->psi = mt->F_eval(c, F, what, what >= EO_EVAL_GRAD ? P : NULL, what >= EO_EVAL_HESS ? dPdF : NULL);
        out->energy = w * out->psi;
        if (what >= EO_EVAL_GRAD) {
            adjoint_map(Dminv, P, out->grad);
            for (int i = 0; i < 12; i++) out->grad[i] *= w;
        }
        if (what >= EO_EVAL_HESS) {
            double Y[12][9]; /* Y = Bᵀ dPdF (dPdF symmetric: map its rows) */
            double row[12];
            for (int r = 0; r < 9; r++) {
                adjoint_map(Dminv, dPdF + 9 * r, row);
                for (int i = 0; i < 12; i++) Y[i][r] = row[i];
            }
            for (int i = 0; i < 12; i++) {
                adjoint_map(Dminv, Y[i], row);
                for (int j = 0; j < 12; j++) out->hess[12 * i + j] = w * row[j];
            }
        }
        return EO_OK;
    }
    double U[9], s[3], V[9];
    eo_sigma_eval se;
    out->psi = iso_eval(mt, c, F, what, U, s, V, &se, P);
    if (!(out->psi < INFINITY)) {
        out->energy = INFINITY;
        if (what >= EO_EVAL_GRAD) memset(out->grad, 0, sizeof out->grad);
        if (what >= EO_EVAL_HESS) memset(out->hess, 0, sizeof out->hess);
        return EO_OK;
    }
    out->energy = w * out->psi;
    if (what >= EO_EVAL_GRAD) {
        adjoint_map(Dminv, P, out->grad);
        for (int i = 0; i < 12; i++) out->grad[i] *= w;
    }
    if (what >= EO_EVAL_HESS) {
        modes m;
        build_modes(&se, U, V, &m);
        double *H = out->hess;
        memset(H, 0, sizeof out->hess);
        for (int k = 0; k < 9; k++) {
            double l = w * project(m.lam[k], proj);
            if (l == 0) continue;
            double g[12];
            adjoint_map(Dminv, m.q[k], g);
            for (int i = 0; i < 12; i++) {
                double lg = l * g[i];
                for (int j = i; j < 12; j++) H[12 * i + j] += lg * g[j];
            }
        }
        for (int i = 0; i < 12; i++)
            for (int j = 0; j < i; j++) H[12 * i + j] = H[12 * j + i];
    }
    return EO_OK;
}

int eo_tet_rest(const double X[12], double Dminv[9], double *w)
{
    double Dm[9];
    for (int a = 0; a < 3; a++)
        for (int cidx = 0; cidx < 3; cidx++) Dm[3 * a + cidx] = X[3 * cidx + a] - X[9 + a];
    double len = 0;
    for (int cidx = 0; cidx < 3; cidx++) {
        double l = sqrt(Dm[cidx] * Dm[cidx] + Dm[3 + cidx] * Dm[3 + cidx] + Dm[6 + cidx] * Dm[6 + cidx]);
        if (l > len) len = l;
    }
    double d = det3(Dm);
    /* F = Ds Dm⁻¹ does not depend on the orientation; only degenerate tets are refused. */
    if (!(fabs(d) > 1e-12 * len * len * len) || !isfinite(d)) return EO_ERR_MESH;
    double inv = 1 / d;
    Dminv[0] = (Dm[4] * Dm[8] - Dm[5] * Dm[7]) * inv;
    Dminv[1] = (Dm[2] * Dm[7] - Dm[1] * Dm[8]) * inv;
    Dminv[2] = (Dm[1] * Dm[5] - Dm[2] * Dm[4]) * inv;
    Dminv[3] = (Dm[5] * Dm[6] - Dm[3] * Dm[8]) * inv;
    Dminv[4] = (Dm[0] * Dm[8] - Dm[2] * Dm[6]) * inv;
    Dminv[5] = (Dm[2] * Dm[3] - Dm[0] * Dm[5]) * inv;
    Dminv[6] = (Dm[3] * Dm[7] - Dm[4] * Dm[6]) * inv;
    Dminv[7] = (Dm[1] * Dm[6] - Dm[0] * Dm[7]) * inv;
    Dminv[8] = (Dm[0] * Dm[4] - Dm[1] * Dm[3]) * inv;
    *w = fabs(d) / 6;
    return EO_OK;
}
