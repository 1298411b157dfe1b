/* stable_neo_hookean — Smith, de Goes & Kim 2018, "Stable Neo-Hookean Flesh Simulation".
 *
 *   ψ = μ'/2 (I_C − 3) + λ'/2 (J − α)² − μ'/2 log(I_C + 1) − ψ₀,
 *   μ' = 4μ/3,  λ' = λ + 5μ/6,  α = 1 + 3μ'/(4λ')   (rest-stable: P(I) = 0, and the
 *   small-strain limit is linear elasticity with μ, λ). The constant ψ₀ = λ'/2 (1−α)²
 *   − μ'/2 log 4 of the paper's form is removed, so ψ(I) = 0: written as
 *   ψ = μ'/2 (I_C − 3 − log1p((I_C − 3)/4)) + λ'/2 (J − 1)(J − 1 + 2(1 − α)), with I_C − 3
 *   and J − 1 formed without cancellation, energies near rest carry no rounding of a
 *   large constant (with E = 1e7 it was ~5e-10 J/m³ per tet, far above the line search's
 *   noise allowance 4ε|g|). Same P and Hessian. Smooth through inversion (J ≤ 0 finite).
 * With I_C = Σσ_i², J = σ1σ2σ3, r = 1/(I_C + 1), (i,j,k) a permutation:
 *   ψ_i = μ'σ_i(1 − r) + λ'(J − α) σ_jσ_k,
 *   ∂²ψ/∂σ_i² = μ'(1 − r) + 2μ'σ_i² r² + λ'(σ_jσ_k)²,
 *   ∂²ψ/∂σ_i∂σ_j = 2μ'σ_iσ_j r² + λ'σ_k(2J − α),
 *   twist_ij = μ'(1 − r) − λ'(J − α)σ_k,
 *   flip_ij  = μ'(1 − r) + λ'(J − α)σ_k.
 * Fast path from F (no SVD), H = F − I: I_C − 3 = 2 tr H + ‖H‖², J − 1 = tr H + Σ
 * principal 2×2 minors of H + det H (both without cancellation at small strain),
 *   ψ as above,  P = μ'(1 − r) F + λ'(J − α) cof(F),   cof(F) = ∂J/∂F = J F⁻ᵀ. */
#include <math.h>

#include "elastopt/material.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    double mu = 4.0 / 3.0 * c->mu, la = c->lambda + 5.0 / 6.0 * c->mu;
    double alpha = 1 + 0.75 * mu / la;
    double J = s[0] * s[1] * s[2], oma = -0.75 * mu / la; /* 1 − α */
    double Ic3 = (s[0] - 1) * (s[0] + 1) + (s[1] - 1) * (s[1] + 1) + (s[2] - 1) * (s[2] + 1);
    double Ic = Ic3 + 3, r = 1 / (Ic + 1);
    double d0 = s[0] - 1, d1 = s[1] - 1, d2 = s[2] - 1;
    double Jm1 = d0 + d1 + d2 + d0 * d1 + d0 * d2 + d1 * d2 + d0 * d1 * d2; /* J − 1, accurate near rest */
    o->psi = 0.5 * mu * (Ic3 - log1p(0.25 * Ic3)) + 0.5 * la * Jm1 * (Jm1 + 2 * oma);
    if (what < EO_EVAL_GRAD) return;
    double cof[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
    for (int i = 0; i < 3; i++) o->g[i] = mu * s[i] * (1 - r) + la * (J - alpha) * cof[i];
    if (what < EO_EVAL_HESS) return;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int k = 3 - i - j;
            o->H[3 * i + j] = i == j ? mu * (1 - r) + 2 * mu * s[i] * s[i] * r * r + la * cof[i] * cof[i]
                                     : 2 * mu * s[i] * s[j] * r * r + la * s[k] * (2 * J - alpha);
        }
    static const int PK[3] = {2, 1, 0}; /* third index of pairs 01, 02, 12 */
    for (int p = 0; p < 3; p++) {
        double sk = s[PK[p]];
        o->twist[p] = mu * (1 - r) - la * (J - alpha) * sk;
        o->flip[p] = mu * (1 - r) + la * (J - alpha) * sk;
    }
}

/* cofactor matrix C = ∂J/∂F = J F⁻ᵀ (row-major) */
static void cofactor(const double F[9], double C[9])
{
    C[0] = F[4] * F[8] - F[5] * F[7], C[1] = F[5] * F[6] - F[3] * F[8], C[2] = F[3] * F[7] - F[4] * F[6];
    C[3] = F[2] * F[7] - F[1] * F[8], C[4] = F[0] * F[8] - F[2] * F[6], C[5] = F[1] * F[6] - F[0] * F[7];
    C[6] = F[1] * F[5] - F[2] * F[4], C[7] = F[2] * F[3] - F[0] * F[5], C[8] = F[0] * F[4] - F[1] * F[3];
}
/* I_C − 3 = tr(FᵀF) − 3 = 2 tr H + ‖H‖², H = F − I (accurate at small strain) */
static double ic_minus_3(const double F[9])
{
    double h0 = F[0] - 1, h4 = F[4] - 1, h8 = F[8] - 1;
    return 2 * (h0 + h4 + h8) + h0 * h0 + h4 * h4 + h8 * h8 + F[1] * F[1] + F[2] * F[2] + F[3] * F[3] +
           F[5] * F[5] + F[6] * F[6] + F[7] * F[7];
}

/* J − 1 = det(I + H) − 1 = tr H + (sum of the principal 2×2 minors of H) + det H, accurate
 * at small strain where det F − 1 cancels */
static double det_minus_1(const double F[9])
{
    double h0 = F[0] - 1, h4 = F[4] - 1, h8 = F[8] - 1;
    double m = h0 * h4 - F[1] * F[3] + h0 * h8 - F[2] * F[6] + h4 * h8 - F[5] * F[7];
    double d = h0 * (h4 * h8 - F[5] * F[7]) - F[1] * (F[3] * h8 - F[5] * F[6]) + F[2] * (F[3] * F[7] - h4 * F[6]);
    return (h0 + h4 + h8) + m + d;
}

static double F_psi_grad(const eo_material_coef *c, const double F[9], double J, double P[9])
{
    (void)J; /* not a barrier: J − 1 is formed accurately from H instead */
    double mu = 4.0 / 3.0 * c->mu, la = c->lambda + 5.0 / 6.0 * c->mu;
    double alpha = 1 + 0.75 * mu / la, oma = -0.75 * mu / la; /* 1 − α */
    double Ic3 = ic_minus_3(F), Jm1 = det_minus_1(F);
    if (P) {
        double C[9], a = mu * (Ic3 + 3) / (Ic3 + 4), b = la * (Jm1 + oma);
        cofactor(F, C);
        for (int i = 0; i < 9; i++) P[i] = a * F[i] + b * C[i];
    }
    (void)alpha;
    return 0.5 * mu * (Ic3 - log1p(0.25 * Ic3)) + 0.5 * la * Jm1 * (Jm1 + 2 * oma);
}

const eo_material_type eo_material_stable_neo_hookean = {
    .info = {.name = "stable_neo_hookean", .summary = "stable Neo-Hookean (Smith, de Goes, Kim 2018), smooth through inversion"},
    .flags = EO_MATERIAL_INVERSION_SAFE,
    .sigma_eval = sigma_eval,
    .F_psi_grad = F_psi_grad,
};
