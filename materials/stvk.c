/* stvk — Saint Venant–Kirchhoff (ERRATA form of notes §4.4.2).
 *
 *   E = ½(FᵀF − I),  ψ = μ E:E + (λ/2) tr²(E).
 * In singular values, E_i = (σ_i² − 1)/2, T = ΣE_i:
 *   ψ = μ Σ E_i² + (λ/2) T²,
 *   ψ_i = σ_i (2μ E_i + λT) = μ(σ_i³ − σ_i) + λ T σ_i,
 *   ∂²ψ/∂σ_i² = μ(3σ_i² − 1) + λT + λσ_i²,   ∂²ψ/∂σ_i∂σ_j = λ σ_i σ_j,
 *   twist_ij = (ψ_i − ψ_j)/(σ_i − σ_j) = μ(σ_i² + σ_iσ_j + σ_j² − 1) + λT,
 *   flip_ij  = (ψ_i + ψ_j)/(σ_i + σ_j) = μ(σ_i² − σ_iσ_j + σ_j² − 1) + λT.
 * Smooth everywhere, including inversion (where it famously resists weakly).
 * Fast path from F (no SVD): with H = F − I, E = ½(H + Hᵀ + HᵀH) (no cancellation at
 * small strain), ψ = μ E:E + (λ/2) tr²E and P = F (2μE + λ tr E I). */
#include "elastopt/material.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    double mu = c->mu, la = c->lambda, E[3];
    for (int i = 0; i < 3; i++) E[i] = 0.5 * (s[i] - 1) * (s[i] + 1);
    double T = E[0] + E[1] + E[2];
    o->psi = mu * (E[0] * E[0] + E[1] * E[1] + E[2] * E[2]) + 0.5 * la * T * T;
    if (what < EO_EVAL_GRAD) return;
    for (int i = 0; i < 3; i++) o->g[i] = s[i] * (2 * mu * E[i] + la * T);
    if (what < EO_EVAL_HESS) return;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            o->H[3 * i + j] = i == j ? mu * (3 * s[i] * s[i] - 1) + la * T + la * s[i] * s[i] : la * s[i] * s[j];
    static const int PI[3] = {0, 0, 1}, PJ[3] = {1, 2, 2};
    for (int p = 0; p < 3; p++) {
        double a = s[PI[p]], b = s[PJ[p]];
        o->twist[p] = mu * (a * a + a * b + b * b - 1) + la * T;
        o->flip[p] = mu * (a * a - a * b + b * b - 1) + la * T;
    }
}

static double F_psi_grad(const eo_material_coef *c, const double F[9], double J, double P[9])
{
    (void)J;
    double mu = c->mu, la = c->lambda, H[9], E[9];
    for (int k = 0; k < 9; k++) H[k] = F[k];
    H[0] -= 1, H[4] -= 1, H[8] -= 1;
    for (int i = 0; i < 3; i++)
        for (int j = i; j < 3; j++)
            E[3 * i + j] = E[3 * j + i] =
                0.5 * (H[3 * i + j] + H[3 * j + i] + H[i] * H[j] + H[3 + i] * H[3 + j] + H[6 + i] * H[6 + j]);
    double tr = E[0] + E[4] + E[8];
    double ee = E[0] * E[0] + E[4] * E[4] + E[8] * E[8] + 2 * (E[1] * E[1] + E[2] * E[2] + E[5] * E[5]);
    if (P) {
        double S[9];
        for (int k = 0; k < 9; k++) S[k] = 2 * mu * E[k];
        S[0] += la * tr, S[4] += la * tr, S[8] += la * tr;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) P[3 * i + j] = F[3 * i] * S[j] + F[3 * i + 1] * S[3 + j] + F[3 * i + 2] * S[6 + j];
    }
    return mu * ee + 0.5 * la * tr * tr;
}

const eo_material_type eo_material_stvk = {
    .info = {.name = "stvk", .summary = "Saint Venant-Kirchhoff, psi = mu E:E + lambda/2 tr^2(E)"},
    .flags = EO_MATERIAL_INVERSION_SAFE,
    .sigma_eval = sigma_eval,
    .F_psi_grad = F_psi_grad,
};
