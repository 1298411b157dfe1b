/* linear — small-strain linear elasticity (notes §4.4.1 with Lamé coefficients).
 *
 *   ε = ½(F + Fᵀ) − I,   ψ = μ ε:ε + (λ/2) tr²(ε),
 *   P = 2μ ε + λ tr(ε) I,
 *   ∂P_ij/∂F_kl = μ(δ_ik δ_jl + δ_il δ_jk) + λ δ_ij δ_kl   (constant).
 * Not rotation invariant, so it is an F-space model. The Hessian is PSD (eigenvalues
 * 2μ+3λ on I, 2μ on the five deviatoric symmetric directions, 0 on the three skew
 * ones), hence every projection (clamp, abs) is the identity for it.
 * F_psi_grad (the energy/gradient fast path) is the same formula without the Hessian. */
#include <string.h>

#include "elastopt/material.h"

static double F_eval(const eo_material_coef *c, const double F[9], eo_eval_what what, double P[9],
                     double dPdF[81])
{
    double mu = c->mu, la = c->lambda, eps[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) eps[3 * i + j] = 0.5 * (F[3 * i + j] + F[3 * j + i]) - (i == j);
    double tr = eps[0] + eps[4] + eps[8], ee = 0;
    for (int k = 0; k < 9; k++) ee += eps[k] * eps[k];
    if (what >= EO_EVAL_GRAD && P)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) P[3 * i + j] = 2 * mu * eps[3 * i + j] + (i == j ? la * tr : 0);
    if (what >= EO_EVAL_HESS && dPdF) {
        memset(dPdF, 0, 81 * sizeof(double));
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                dPdF[(3 * i + j) * 9 + (3 * i + j)] += mu;
                dPdF[(3 * i + j) * 9 + (3 * j + i)] += mu;
                if (i == j)
                    for (int k = 0; k < 3; k++) dPdF[(3 * i + i) * 9 + (3 * k + k)] += la;
            }
    }
    return mu * ee + 0.5 * la * tr * tr;
}

static double F_psi_grad(const eo_material_coef *c, const double F[9], double J, double P[9])
{
    (void)J;
    return F_eval(c, F, P ? EO_EVAL_GRAD : EO_EVAL_ENERGY, P, NULL);
}

const eo_material_type eo_material_linear = {
    .info = {.name = "linear", .summary = "linear elasticity, psi = mu eps:eps + lambda/2 tr^2(eps) (not rotation invariant)"},
    .flags = EO_MATERIAL_INVERSION_SAFE,
    .F_eval = F_eval,
    .F_psi_grad = F_psi_grad,
};
