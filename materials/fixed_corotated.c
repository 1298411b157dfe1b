/* fixed_corotated — fixed corotated elasticity (Stomakhin et al. 2012).
 *
 *   ψ = μ Σ(σ_i − 1)² + (λ/2)(J − 1)²,   J = σ1 σ2 σ3 = det F (signed σ3).
 * With (i,j,k) a permutation of (0,1,2):
 *   ψ_i = 2μ(σ_i − 1) + λ(J − 1) σ_j σ_k,
 *   ∂²ψ/∂σ_i² = 2μ + λ(σ_j σ_k)²,   ∂²ψ/∂σ_i∂σ_j = λ σ_k (2J − 1),
 *   twist_ij = 2μ − λ(J − 1) σ_k,
 *   flip_ij  = 2μ + λ(J − 1) σ_k − 4μ/(σ_i + σ_j).
 * flip is genuinely singular at σ_i + σ_j = 0 (non-unique polar rotation, ψ not
 * differentiable there); the denominator is kept at |σ_i + σ_j| ≥ 1e-12 (sign kept).
 * Fast path from F (no SVD): R from eo_polar3 (R = U Vᵀ of the signed SVD), J = det F:
 *   ψ = μ‖F − R‖² + (λ/2)(J − 1)²,   P = 2μ(F − R) + λ(J − 1) cof(F). */
#include <math.h>

#include "elastopt/material.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    double mu = c->mu, la = c->lambda, J = s[0] * s[1] * s[2];
    double d0 = s[0] - 1, d1 = s[1] - 1, d2 = s[2] - 1;
    o->psi = mu * (d0 * d0 + d1 * d1 + d2 * d2) + 0.5 * la * (J - 1) * (J - 1);
    if (what < EO_EVAL_GRAD) return;
    double cof[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
    for (int i = 0; i < 3; i++) o->g[i] = 2 * mu * (s[i] - 1) + la * (J - 1) * cof[i];
    if (what < EO_EVAL_HESS) return;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int k = 3 - i - j;
            o->H[3 * i + j] = i == j ? 2 * mu + la * cof[i] * cof[i] : la * s[k] * (2 * J - 1);
        }
    static const int PI[3] = {0, 0, 1}, PJ[3] = {1, 2, 2}, PK[3] = {2, 1, 0};
    for (int p = 0; p < 3; p++) {
        double den = s[PI[p]] + s[PJ[p]], sk = s[PK[p]];
        if (fabs(den) < 1e-12) den = den < 0 ? -1e-12 : 1e-12;
        o->twist[p] = 2 * mu - la * (J - 1) * sk;
        o->flip[p] = 2 * mu + la * (J - 1) * sk - 4 * mu / den;
    }
}

/* cofactor matrix C = ∂J/∂F = J F⁻ᵀ (row-major) */
static void cofactor(const double F[9], double C[9])
{
    C[0] = F[4] * F[8] - F[5] * F[7], C[1] = F[5] * F[6] - F[3] * F[8], C[2] = F[3] * F[7] - F[4] * F[6];
    C[3] = F[2] * F[7] - F[1] * F[8], C[4] = F[0] * F[8] - F[2] * F[6], C[5] = F[1] * F[6] - F[0] * F[7];
    C[6] = F[1] * F[5] - F[2] * F[4], C[7] = F[2] * F[3] - F[0] * F[5], C[8] = F[0] * F[4] - F[1] * F[3];
}

static double F_psi_grad(const eo_material_coef *c, const double F[9], double J, double P[9])
{
    double mu = c->mu, la = c->lambda, R[9];
    eo_polar3(F, R);
    double dd = 0;
    for (int i = 0; i < 9; i++) dd += (F[i] - R[i]) * (F[i] - R[i]);
    if (P) {
        double C[9];
        cofactor(F, C);
        for (int i = 0; i < 9; i++) P[i] = 2 * mu * (F[i] - R[i]) + la * (J - 1) * C[i];
    }
    return mu * dd + 0.5 * la * (J - 1) * (J - 1);
}

const eo_material_type eo_material_fixed_corotated = {
    .info = {.name = "fixed_corotated", .summary = "fixed corotated, psi = mu sum (s_i-1)^2 + lambda/2 (J-1)^2"},
    .flags = EO_MATERIAL_INVERSION_SAFE,
    .sigma_eval = sigma_eval,
    .F_psi_grad = F_psi_grad,
};
