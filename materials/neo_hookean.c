/* neo_hookean — compressible Neo-Hookean (Bonet & Wood), a barrier at J = 0.
 *
 *   ψ = μ/2 (I_C − 3) − μ log J + (λ/2) (log J)²,  I_C = tr(FᵀF) = Σσ_i²,  J = σ1σ2σ3;
 *   ψ = +∞ for J ≤ 0 (EO_MATERIAL_BARRIER: line searches must backtrack).
 * With ℓ = log J:
 *   ψ_i = μσ_i + (λℓ − μ)/σ_i,
 *   ∂²ψ/∂σ_i² = μ + (μ + λ(1 − ℓ))/σ_i²,   ∂²ψ/∂σ_i∂σ_j = λ/(σ_iσ_j),
 *   twist_ij = μ + (μ − λℓ)/(σ_iσ_j),
 *   flip_ij  = μ + (λℓ − μ)/(σ_iσ_j).
 * I_C − 3 is summed as Σ(σ_i − 1)(σ_i + 1) to keep small strains accurate.
 * Fast path from F (no SVD): I_C − 3 = 2 tr H + ‖H‖² (H = F − I), J = det F as the
 * kernel computed it (called only where J > 0, the inversion rule of material.h),
 *   P = μF + (λℓ − μ) F⁻ᵀ,   F⁻ᵀ = cof(F)/J. */
#include <math.h>

#include "elastopt/material.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    double mu = c->mu, la = c->lambda;
    if (!(s[0] > 0 && s[1] > 0 && s[2] > 0)) {
        o->psi = INFINITY;
        return;
    }
    double l = log(s[0]) + log(s[1]) + log(s[2]);
    double Ic3 = (s[0] - 1) * (s[0] + 1) + (s[1] - 1) * (s[1] + 1) + (s[2] - 1) * (s[2] + 1);
    o->psi = 0.5 * mu * Ic3 - mu * l + 0.5 * la * l * l;
    if (what < EO_EVAL_GRAD) return;
    for (int i = 0; i < 3; i++) o->g[i] = mu * s[i] + (la * l - mu) / s[i];
    if (what < EO_EVAL_HESS) return;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            o->H[3 * i + j] = i == j ? mu + (mu + la * (1 - l)) / (s[i] * s[i]) : la / (s[i] * s[j]);
    static const int PI[3] = {0, 0, 1}, PJ[3] = {1, 2, 2};
    for (int p = 0; p < 3; p++) {
        double ss = s[PI[p]] * s[PJ[p]];
        o->twist[p] = mu + (mu - la * l) / ss;
        o->flip[p] = mu + (la * l - mu) / ss;
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

static double F_psi_grad(const eo_material_coef *c, const double F[9], double J, double P[9])
{
    double mu = c->mu, la = c->lambda, l = log(J);
    if (P) {
        double C[9], k = (la * l - mu) / J;
        cofactor(F, C);
        for (int i = 0; i < 9; i++) P[i] = mu * F[i] + k * C[i];
    }
    return 0.5 * mu * ic_minus_3(F) - mu * l + 0.5 * la * l * l;
}

const eo_material_type eo_material_neo_hookean = {
    .info = {.name = "neo_hookean", .summary = "Neo-Hookean, psi = mu/2 (I_C-3) - mu log J + lambda/2 log^2 J (barrier at J <= 0)"},
    .flags = EO_MATERIAL_BARRIER,
    .sigma_eval = sigma_eval,
    .F_psi_grad = F_psi_grad,
};
