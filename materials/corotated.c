/* corotated — general corotated linear elasticity (notes §4.4.5, eq. 40).
 *
 *   ψ = μ Σ(σ_i − 1)² + (λ/2)(σ1 + σ2 + σ3 − 3)²   = μ‖F − R‖² + (λ/2) tr²(Σ − I),
 * with signed σ (R = U Vᵀ ∈ SO(3)). With t = Σσ_i − 3:
 *   ψ_i = 2μ(σ_i − 1) + λ t,
 *   ∂²ψ/∂σ² = 2μ I + λ 11ᵀ,
 *   twist_ij = 2μ,
 *   flip_ij  = 2μ + (2λ t − 4μ)/(σ_i + σ_j).
 * flip is genuinely singular at σ_i + σ_j = 0 (only possible for the pair (·,3) of an
 * inverted element with |σ3| = σ_j, or rank ≤ 1): there the polar rotation R is not
 * unique and ψ is not differentiable. The denominator is kept away from 0 by
 * |σ_i + σ_j| ≥ 1e-12 (sign kept; +1e-12 at exactly 0), which keeps values finite.
 * Fast path from F (no SVD): R from eo_polar3 (the same R = U Vᵀ as the signed SVD),
 * M = RᵀF (= V Σ Vᵀ), t = tr M − 3:  ψ = μ‖F − R‖² + (λ/2) t²,  P = 2μ(F − R) + λ t R. */
#include <math.h>

#include "elastopt/material.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    double mu = c->mu, la = c->lambda, t = s[0] + s[1] + s[2] - 3;
    double d0 = s[0] - 1, d1 = s[1] - 1, d2 = s[2] - 1;
    o->psi = mu * (d0 * d0 + d1 * d1 + d2 * d2) + 0.5 * la * t * t;
    if (what < EO_EVAL_GRAD) return;
    for (int i = 0; i < 3; i++) o->g[i] = 2 * mu * (s[i] - 1) + la * t;
    if (what < EO_EVAL_HESS) return;
    for (int i = 0; i < 9; i++) o->H[i] = la + (i % 4 == 0 ? 2 * mu : 0);
    static const int PI[3] = {0, 0, 1}, PJ[3] = {1, 2, 2};
    for (int p = 0; p < 3; p++) {
        double den = s[PI[p]] + s[PJ[p]];
        if (fabs(den) < 1e-12) den = den < 0 ? -1e-12 : 1e-12;
        o->twist[p] = 2 * mu;
        o->flip[p] = 2 * mu + (2 * la * t - 4 * mu) / den;
    }
}


static double F_psi_grad(const eo_material_coef *c, const double F[9], double J, double P[9])
{
    (void)J;
    double mu = c->mu, la = c->lambda, R[9];
    eo_polar3(F, R);
    double t = -3, dd = 0;
    for (int i = 0; i < 9; i++) {
        t += R[i] * F[i]; /* tr(RᵀF) */
        dd += (F[i] - R[i]) * (F[i] - R[i]);
    }
    if (P)
        for (int i = 0; i < 9; i++) P[i] = 2 * mu * (F[i] - R[i]) + la * t * R[i];
    return mu * dd + 0.5 * la * t * t;
}

const eo_material_type eo_material_corotated = {
    .info = {.name = "corotated", .summary = "general corotated, psi = mu sum (s_i-1)^2 + lambda/2 (sum s_i - 3)^2"},
    .flags = EO_MATERIAL_INVERSION_SAFE,
    .sigma_eval = sigma_eval,
    .F_psi_grad = F_psi_grad,
};
