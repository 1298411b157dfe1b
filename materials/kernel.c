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
 * Fast path (F_psi_grad): for EO_EVAL_ENERGY / EO_EVAL_GRAD a model that has it gives ψ
 *   and P straight from F and J (no SVD); the SVD path above stays for EO_EVAL_HESS and
 *   eo_material_evaluate_svd, the reference the tests compare against.
 * Inversion (one rule, material.h): J = eo_det3(F) computed once per evaluation;
 *   barrier models get ψ = +∞ iff eo_tet_is_inverted(J), decided here before any model
 *   code runs. Where J > 0 but the SVD's signed σ3 ≤ 0 (|J| at rounding level, the two
 *   signs computed differently), σ3 is replaced by J/(σ1σ2) > 0, a change of F at the
 *   rounding level, so that the SVD path agrees with the rule.
 * Tet element (notes §4.2–4.3, ERRATA): Ds = [x0−x3, x1−x3, x2−x3], F = Ds Dm⁻¹,
 *   vec(F) = (Dm⁻ᵀ S ⊗ I3) x. The adjoint map B: 3×3 Q ↦ 12-vector ∂(F:Q)/∂x is
 *   vertex c ∈ {0,1,2}: column c of Q Dm⁻ᵀ; vertex 3: minus their sum.
 *   energy = w ψ, grad = w B(P), Hessian = w Σ_k λ_k B(Q_k) B(Q_k)ᵀ (nine rank-1
 *   updates of 12×12; for F-space models w Bᵀ ∂P/∂F B applied column- then row-wise).
 *   No allocation. */
#include <math.h>
#include <string.h>

#include "elastopt/material.h"

static double det3(const double M[9]) { return eo_det3(M); }

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

/* Shared front half of both evaluations, after the SVD F = U diag(s) Vᵀ: σ-space model
 * and P. J > 0 for barrier models (checked by the caller). Returns ψ. */
static double iso_eval(const eo_material_type *mt, const eo_material_coef *c, const double F[9],
                       double J, eo_eval_what what, double U[9], double s[3], double V[9], eo_sigma_eval *se,
                       double P[9])
{ /* P == NULL: not wanted (eo_tet_hessian) */
    (void)F;
    if ((mt->flags & EO_MATERIAL_BARRIER) && !(s[2] > 0)) { /* caller checked J > 0 */
        double d = s[0] * s[1];
        s[2] = d > 0 ? J / d : 0;
    }
    memset(se, 0, sizeof *se);
    mt->sigma_eval(c, s, what, se);
    if (!(se->psi < INFINITY)) {
        se->psi = INFINITY;
        return INFINITY;
    }
    if (what >= EO_EVAL_GRAD && P)
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                P[3 * a + b] = U[3 * a + 0] * se->g[0] * V[3 * b + 0] + U[3 * a + 1] * se->g[1] * V[3 * b + 1] +
                               U[3 * a + 2] * se->g[2] * V[3 * b + 2];
    return se->psi;
}

static int material_eval(const eo_material_type *mt, const eo_material_coef *c, const double F[9],
                         eo_eval_what what, eo_proj proj, int fast, eo_material_eval *out)
{
    memset(out, 0, sizeof *out);
    out->J = det3(F);
    eo_svd3(F, out->U, out->sigma, out->V);
    if (mt->flags & EO_MATERIAL_EDGE) return EO_ERR_UNSUPPORTED;
    if ((mt->flags & EO_MATERIAL_BARRIER) && eo_tet_is_inverted(out->J)) {
        out->psi = INFINITY;
        return EO_OK;
    }
    if (fast && what < EO_EVAL_HESS && mt->F_psi_grad) {
        out->psi = mt->F_psi_grad(c, F, out->J, what >= EO_EVAL_GRAD ? out->P : NULL);
        return EO_OK;
    }
    if (mt->F_eval) {
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
    double s[3];
    memcpy(s, out->sigma, sizeof s);
    out->psi = iso_eval(mt, c, F, out->J, what, out->U, s, out->V, &se, out->P);
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

int eo_material_evaluate(const eo_material_type *mt, const eo_material_coef *c, const double F[9],
                         eo_eval_what what, eo_proj proj, eo_material_eval *out)
{
    return material_eval(mt, c, F, what, proj, 1, out);
}

int eo_material_evaluate_svd(const eo_material_type *mt, const eo_material_coef *c, const double F[9],
                             eo_eval_what what, eo_proj proj, eo_material_eval *out)
{
    return material_eval(mt, c, F, what, proj, 0, out);
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

void eo_tet_F(const double Dminv[9], const double x[12], double F[9])
{
    for (int a = 0; a < 3; a++) {
        double ds0 = x[a] - x[9 + a], ds1 = x[3 + a] - x[9 + a], ds2 = x[6 + a] - x[9 + a];
        for (int b = 0; b < 3; b++) F[3 * a + b] = ds0 * Dminv[b] + ds1 * Dminv[3 + b] + ds2 * Dminv[6 + b];
    }
}

double eo_tet_J(const double Dminv[9], const double x[12])
{
    double F[9];
    eo_tet_F(Dminv, x, F);
    return eo_det3(F);
}

/* Unit eigenvector of the symmetric B (row-major) for its eigenvalue lam: the largest of
 * the three cross products of the rows of B − lam I; 0 if B − lam I has rank ≤ 1. */
static int eigvec_cross(const double B[9], double lam, double v[3])
{
    double r0[3] = {B[0] - lam, B[1], B[2]}, r1[3] = {B[3], B[4] - lam, B[5]}, r2[3] = {B[6], B[7], B[8] - lam};
    double c[3][3];
    c[0][0] = r0[1] * r1[2] - r0[2] * r1[1], c[0][1] = r0[2] * r1[0] - r0[0] * r1[2], c[0][2] = r0[0] * r1[1] - r0[1] * r1[0];
    c[1][0] = r0[1] * r2[2] - r0[2] * r2[1], c[1][1] = r0[2] * r2[0] - r0[0] * r2[2], c[1][2] = r0[0] * r2[1] - r0[1] * r2[0];
    c[2][0] = r1[1] * r2[2] - r1[2] * r2[1], c[2][1] = r1[2] * r2[0] - r1[0] * r2[2], c[2][2] = r1[0] * r2[1] - r1[1] * r2[0];
    int best = 0;
    double nb = 0;
    for (int k = 0; k < 3; k++) {
        double n = c[k][0] * c[k][0] + c[k][1] * c[k][1] + c[k][2] * c[k][2];
        if (n > nb) nb = n, best = k;
    }
    if (!(nb > 0)) return 0;
    double s = 1 / sqrt(nb);
    for (int i = 0; i < 3; i++) v[i] = c[best][i] * s;
    return 1;
}

/* Symmetric 3×3 eigen-decomposition in closed form (no iteration): eigenvalues from the
 * trigonometric solution of the characteristic cubic (A scaled by its largest entry);
 * the eigenvector of the most separated eigenvalue (the largest when det(A − qI) ≥ 0,
 * else the smallest) from cross products of the rows of A − λI; the other two from the
 * 2×2 restriction of A to the orthogonal complement, diagonalized by one exact plane
 * rotation, which stays accurate for a repeated pair. d eigenvalues, W row-major with
 * the eigenvectors in its columns (orthonormal). */
static void eig_sym3_closed(const double Ain[9], double d[3], double W[9])
{
    double m = 0;
    for (int i = 0; i < 9; i++) m = fmax(m, fabs(Ain[i]));
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (!(m > 0)) {
        d[0] = d[1] = d[2] = 0;
        memcpy(W, I3, sizeof I3);
        return;
    }
    double A[9];
    for (int i = 0; i < 9; i++) A[i] = Ain[i] / m;
    double q = (A[0] + A[4] + A[8]) / 3;
    double b00 = A[0] - q, b11 = A[4] - q, b22 = A[8] - q;
    double p2 = (b00 * b00 + b11 * b11 + b22 * b22 + 2 * (A[1] * A[1] + A[2] * A[2] + A[5] * A[5])) / 6;
    if (!(p2 > 1e-36)) { /* A = q I to working precision */
        d[0] = A[0] * m, d[1] = A[4] * m, d[2] = A[8] * m;
        memcpy(W, I3, sizeof I3);
        return;
    }
    double p = sqrt(p2);
    double r = (b00 * (b11 * b22 - A[5] * A[5]) - A[1] * (A[1] * b22 - A[5] * A[2]) + A[2] * (A[1] * A[5] - b11 * A[2])) /
               (2 * p2 * p);
    r = r < -1 ? -1 : r > 1 ? 1 : r;
    double phi = acos(r) / 3;
    double lam = r >= 0 ? q + 2 * p * cos(phi) : q + 2 * p * cos(phi + 2.0943951023931954923);
    double v0[3];
    if (!eigvec_cross(A, lam, v0)) v0[0] = 1, v0[1] = 0, v0[2] = 0;
    /* orthonormal e1, e2 ⟂ v0 */
    double e1[3], e2[3];
    if (fabs(v0[0]) > fabs(v0[1])) {
        double s = 1 / sqrt(v0[0] * v0[0] + v0[2] * v0[2]);
        e1[0] = -v0[2] * s, e1[1] = 0, e1[2] = v0[0] * s;
    } else {
        double s = 1 / sqrt(v0[1] * v0[1] + v0[2] * v0[2]);
        e1[0] = 0, e1[1] = v0[2] * s, e1[2] = -v0[1] * s;
    }
    e2[0] = v0[1] * e1[2] - v0[2] * e1[1], e2[1] = v0[2] * e1[0] - v0[0] * e1[2], e2[2] = v0[0] * e1[1] - v0[1] * e1[0];
    double Ae1[3], Ae2[3], Av0[3];
    for (int i = 0; i < 3; i++) {
        Ae1[i] = A[3 * i] * e1[0] + A[3 * i + 1] * e1[1] + A[3 * i + 2] * e1[2];
        Ae2[i] = A[3 * i] * e2[0] + A[3 * i + 1] * e2[1] + A[3 * i + 2] * e2[2];
        Av0[i] = A[3 * i] * v0[0] + A[3 * i + 1] * v0[1] + A[3 * i + 2] * v0[2];
    }
    double m11 = e1[0] * Ae1[0] + e1[1] * Ae1[1] + e1[2] * Ae1[2];
    double m22 = e2[0] * Ae2[0] + e2[1] * Ae2[1] + e2[2] * Ae2[2];
    double m12 = e1[0] * Ae2[0] + e1[1] * Ae2[1] + e1[2] * Ae2[2];
    double l0 = v0[0] * Av0[0] + v0[1] * Av0[1] + v0[2] * Av0[2]; /* Rayleigh quotient */
    double c = 1, s = 0;
    if (m12 != 0) { /* Jacobi rotation zeroing m12 */
        double theta = (m22 - m11) / (2 * m12);
        double t = fabs(theta) > 1e150 ? 0.5 / theta : copysign(1.0, theta) / (fabs(theta) + sqrt(theta * theta + 1));
        c = 1 / sqrt(t * t + 1), s = t * c;
    }
    double l1 = c * c * m11 - 2 * s * c * m12 + s * s * m22, l2 = s * s * m11 + 2 * s * c * m12 + c * c * m22;
    double w1[3], w2[3];
    for (int i = 0; i < 3; i++) w1[i] = c * e1[i] - s * e2[i], w2[i] = s * e1[i] + c * e2[i];
    d[0] = l0 * m, d[1] = l1 * m, d[2] = l2 * m;
    for (int i = 0; i < 3; i++) W[3 * i] = v0[i], W[3 * i + 1] = w1[i], W[3 * i + 2] = w2[i];
}

/* The projected scaling block Hs⁺ = W proj(Λ) Wᵀ of ∂²ψ/∂σ². A positive definite Hs
 * (all leading minors > 0, the common case) is its own clamp and abs projection and
 * needs no eigensolve. */
static void scaling_block(const double Hs[9], eo_proj proj, double out[9])
{
    double m2 = Hs[0] * Hs[4] - Hs[1] * Hs[3];
    if (proj == EO_PROJ_NONE || (Hs[0] > 0 && m2 > 0 && det3(Hs) > 0)) {
        memcpy(out, Hs, 9 * sizeof(double));
        return;
    }
    double d[3], W[9];
    eig_sym3_closed(Hs, d, W);
    for (int k = 0; k < 3; k++) d[k] = project(d[k], proj);
    for (int i = 0; i < 3; i++)
        for (int j = i; j < 3; j++)
            out[3 * i + j] = out[3 * j + i] = W[3 * i] * d[0] * W[3 * j] + W[3 * i + 1] * d[1] * W[3 * j + 1] +
                                             W[3 * i + 2] * d[2] * W[3 * j + 2];
}

/* 12×12 element Hessian w (∂F/∂x)ᵀ ∂P/∂F (∂F/∂x) of an isotropic model, projected,
 * without forming the nine modes. In the rotated frame A = Uᵀ dF V the (projected)
 * ∂P/∂F acts as A'_aa = Σ_c Hs⁺_ac A_cc (Hs⁺ the projected 3×3 scaling block) and, per
 * pair (i,j), A'_ij = α A_ij + β A_ji, α = (t⁺ + f⁺)/2, β = (t⁺ − f⁺)/2 (t, f the twist
 * and flip eigenvalues, projected). With ∂F_ij/∂x_vk = δ_ik G_vj (G_vj = Dm⁻¹_vj for
 * v < 3, G_3 = −Σ G_v) and GV = G V:
 *     H_(v,i),(u,l) = w Σ_bd GV_vb GV_ud T_bd[i][l],   T_bd = U L_bd Uᵀ,
 *     T_bb = Hs⁺_bb u_b u_bᵀ + Σ_(a≠b) α_ab u_a u_aᵀ,   T_bd = Hs⁺_bd u_b u_dᵀ + β_bd u_d u_bᵀ,
 * (u_a the columns of U), contracted as Y_ub = Σ_d GV_ud T_bd, block(v,u) = Σ_b GV_vb Y_ub
 * for v ≤ u < 3; the blocks of vertex 3 are minus the sums of the others (translation
 * invariance, exact in G). */
/* T_bd of the comment above (the projected ∂P/∂F in the U frame) */
static void iso_T(const eo_sigma_eval *se, const double U[9], eo_proj proj, double T[3][3][9])
{
    double Hs[9];
    scaling_block(se->H, proj, Hs);
    double al[3][3] = {{0}}, be[3][3] = {{0}};
    static const int PI[3] = {0, 0, 1}, PJ[3] = {1, 2, 2};
    for (int p = 0; p < 3; p++) {
        double t = project(se->twist[p], proj), f = project(se->flip[p], proj);
        int i = PI[p], j = PJ[p];
        al[i][j] = al[j][i] = 0.5 * (t + f);
        be[i][j] = be[j][i] = 0.5 * (t - f);
    }
    for (int b = 0; b < 3; b++) {
        double l[3];
        for (int a = 0; a < 3; a++) l[a] = a == b ? Hs[4 * b] : al[a][b];
        for (int i = 0; i < 3; i++)
            for (int k = i; k < 3; k++)
                T[b][b][3 * i + k] = T[b][b][3 * k + i] = l[0] * U[3 * i] * U[3 * k] + l[1] * U[3 * i + 1] * U[3 * k + 1] +
                                                          l[2] * U[3 * i + 2] * U[3 * k + 2];
        for (int dd = b + 1; dd < 3; dd++) {
            double h = Hs[3 * b + dd], bb = be[b][dd];
            for (int i = 0; i < 3; i++)
                for (int k = 0; k < 3; k++) {
                    double v = h * U[3 * i + b] * U[3 * k + dd] + bb * U[3 * i + dd] * U[3 * k + b];
                    T[b][dd][3 * i + k] = v;
                    T[dd][b][3 * k + i] = v;
                }
        }
    }
}

static void hess_iso(const eo_sigma_eval *se, const double U[9], const double V[9], const double Dminv[9],
                     double w, eo_proj proj, double *H)
{
    double T[3][3][9];
    iso_T(se, U, proj, T);
    double GV[3][3];
    for (int v = 0; v < 3; v++)
        for (int b = 0; b < 3; b++)
            GV[v][b] = Dminv[3 * v] * V[b] + Dminv[3 * v + 1] * V[3 + b] + Dminv[3 * v + 2] * V[6 + b];
    double Y[3][3][9];
    for (int u = 0; u < 3; u++)
        for (int b = 0; b < 3; b++)
            for (int q = 0; q < 9; q++) Y[u][b][q] = GV[u][0] * T[b][0][q] + GV[u][1] * T[b][1][q] + GV[u][2] * T[b][2][q];
    double Bk[3][3][9];
    for (int v = 0; v < 3; v++)
        for (int u = v; u < 3; u++)
            for (int q = 0; q < 9; q++) Bk[v][u][q] = GV[v][0] * Y[u][0][q] + GV[v][1] * Y[u][1][q] + GV[v][2] * Y[u][2][q];
    for (int v = 0; v < 3; v++)
        for (int u = v; u < 3; u++)
            for (int q = 0; q < 9; q++) Bk[v][u][q] *= w;
    double S3[3][9]; /* block(3,u) = −Σ_v block(v,u) */
    for (int u = 0; u < 3; u++)
        for (int i = 0; i < 3; i++)
            for (int l = 0; l < 3; l++) {
                double s = 0;
                for (int v = 0; v < 3; v++) s += v <= u ? Bk[v][u][3 * i + l] : Bk[u][v][3 * l + i];
                S3[u][3 * i + l] = -s;
            }
    for (int v = 0; v < 3; v++)
        for (int u = v; u < 3; u++)
            for (int i = 0; i < 3; i++)
                for (int l = 0; l < 3; l++) {
                    double x = Bk[v][u][3 * i + l];
                    H[12 * (3 * v + i) + 3 * u + l] = x;
                    H[12 * (3 * u + l) + 3 * v + i] = x;
                }
    for (int u = 0; u < 3; u++)
        for (int i = 0; i < 3; i++)
            for (int l = 0; l < 3; l++) {
                double x = S3[u][3 * i + l];
                H[12 * (9 + i) + 3 * u + l] = x;
                H[12 * (3 * u + l) + 9 + i] = x;
            }
    for (int i = 0; i < 3; i++)
        for (int l = 0; l < 3; l++)
            H[12 * (9 + i) + 9 + l] = -(S3[0][3 * l + i] + S3[1][3 * l + i] + S3[2][3 * l + i]);
}

/* eo_tet_evaluate and eo_tet_hessian: want_grad = 0 skips P and the gradient (only with
 * what = EO_EVAL_HESS); every other output is computed by the same operations. */
static int tet_eval(const eo_material_type *mt, const eo_material_coef *c, const double Dminv[9], double w,
                    const double x[12], eo_eval_what what, eo_proj proj, int want_grad, eo_tet_out *out)
{
    if (mt->flags & EO_MATERIAL_EDGE) return EO_ERR_UNSUPPORTED;
    double F[9];
    eo_tet_F(Dminv, x, F);
    const double J = det3(F);
    out->J = J;
    if ((mt->flags & EO_MATERIAL_BARRIER) && eo_tet_is_inverted(J)) {
        out->psi = out->energy = INFINITY;
        if (what >= EO_EVAL_GRAD && want_grad) memset(out->grad, 0, sizeof out->grad);
        if (what >= EO_EVAL_HESS) memset(out->hess, 0, sizeof out->hess);
        return EO_OK;
    }
    double P[9];
    if (what < EO_EVAL_HESS && mt->F_psi_grad) {
        out->psi = mt->F_psi_grad(c, F, J, what >= EO_EVAL_GRAD ? P : NULL);
        out->energy = w * out->psi;
        if (what >= EO_EVAL_GRAD) {
            for (int i = 0; i < 9; i++) P[i] *= w;
            adjoint_map(Dminv, P, out->grad);
        }
        return EO_OK;
    }
    if (mt->F_eval) {
        double dPdF[81];
        out->psi = mt->F_eval(c, F, what, what >= EO_EVAL_GRAD ? P : NULL, what >= EO_EVAL_HESS ? dPdF : NULL);
        out->energy = w * out->psi;
        if (what >= EO_EVAL_GRAD && want_grad) {
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
    eo_svd3(F, U, s, V);
    out->psi = iso_eval(mt, c, F, J, what, U, s, V, &se, want_grad ? P : NULL);
    if (!(out->psi < INFINITY)) {
        out->energy = INFINITY;
        if (what >= EO_EVAL_GRAD && want_grad) memset(out->grad, 0, sizeof out->grad);
        if (what >= EO_EVAL_HESS) memset(out->hess, 0, sizeof out->hess);
        return EO_OK;
    }
    out->energy = w * out->psi;
    if (what >= EO_EVAL_GRAD && want_grad) {
        adjoint_map(Dminv, P, out->grad);
        for (int i = 0; i < 12; i++) out->grad[i] *= w;
    }
    if (what >= EO_EVAL_HESS) hess_iso(&se, U, V, Dminv, w, proj, out->hess);
    return EO_OK;
}

int eo_tet_evaluate(const eo_material_type *mt, const eo_material_coef *c,
                    const double Dminv[9], double w, const double x[12], eo_eval_what what,
                    eo_proj proj, eo_tet_out *out)
{
    return tet_eval(mt, c, Dminv, w, x, what, proj, 1, out);
}

int eo_tet_hessian(const eo_material_type *mt, const eo_material_coef *c, const double Dminv[9], double w,
                   const double x[12], eo_proj proj, eo_tet_out *out)
{
    return tet_eval(mt, c, Dminv, w, x, EO_EVAL_HESS, proj, 0, out);
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

int eo_material_hessian_nodes(const eo_material_type *mt, const eo_material_coef *c, const double F[9], int n,
                              const double *G, double w, eo_proj proj, double *H, double *psi, double *J)
{
    if (!mt->sigma_eval || (mt->flags & EO_MATERIAL_EDGE) || n < 1 || n > 10) return EO_ERR_UNSUPPORTED;
    *J = det3(F);
    if ((mt->flags & EO_MATERIAL_BARRIER) && eo_tet_is_inverted(*J)) {
        *psi = INFINITY;
        return EO_OK;
    }
    double U[9], s[3], V[9];
    eo_svd3(F, U, s, V);
    eo_sigma_eval se;
    *psi = iso_eval(mt, c, F, *J, EO_EVAL_HESS, U, s, V, &se, NULL);
    if (!(*psi < INFINITY)) return EO_OK;
    double T[3][3][9], GV[10][3], Y[10][3][9];
    iso_T(&se, U, proj, T);
    for (int a = 0; a < n; a++)
        for (int b = 0; b < 3; b++)
            GV[a][b] = G[3 * a] * V[b] + G[3 * a + 1] * V[3 + b] + G[3 * a + 2] * V[6 + b];
    for (int u = 0; u < n; u++)
        for (int b = 0; b < 3; b++)
            for (int q = 0; q < 9; q++) Y[u][b][q] = GV[u][0] * T[b][0][q] + GV[u][1] * T[b][1][q] + GV[u][2] * T[b][2][q];
    const int n3 = 3 * n;
    for (int v = 0; v < n; v++) {
        const double g0 = w * GV[v][0], g1 = w * GV[v][1], g2 = w * GV[v][2];
        for (int u = v; u < n; u++) {
            double blk[9];
            for (int q = 0; q < 9; q++) blk[q] = g0 * Y[u][0][q] + g1 * Y[u][1][q] + g2 * Y[u][2][q];
            for (int i = 0; i < 3; i++)
                for (int l = 0; l < 3; l++) H[(size_t)(3 * v + i) * n3 + 3 * u + l] += blk[3 * i + l];
        }
    }
    return EO_OK;
}
