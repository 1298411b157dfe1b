/* pd_arap — the as-rigid-as-possible constraint of projective dynamics (Bouaziz et al.
 * 2014 §5, "strain" with σ_min = σ_max = 1): C = SO(3), weight w = 2μ,
 *
 *   ψ = (w/2)‖F − R‖²_F = μ Σ(σ_i − 1)²,   R = U Vᵀ = proj_SO(3)(F) (signed SVD),
 *
 * i.e. `corotated` with λ = 0 (the volume term dropped). The PD weight (op pd_weight,
 * the global matrix of pd_local_global) is 2μ per unit rest volume. Derivatives: the
 * strain box of pd_constraint.h with a = b = 1: ψ_i = 2μ(σ_i − 1), ∂²ψ/∂σ² = 2μI,
 * twist = 2μ, flip = 2μ(1 − 2/(σ_i + σ_j)).
 * Fast path from F (no SVD): R from eo_polar3, ψ = μ‖F − R‖², P = 2μ(F − R). */
#include "pd_constraint.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    eo_pd_strain_add(2 * c->mu, 1, 1, s, what, o);
}

static double F_psi_grad(const eo_material_coef *c, const double F[9], double J, double P[9])
{
    (void)J;
    double R[9], dd = 0;
    eo_polar3(F, R);
    for (int i = 0; i < 9; i++) dd += (F[i] - R[i]) * (F[i] - R[i]);
    if (P)
        for (int i = 0; i < 9; i++) P[i] = 2 * c->mu * (F[i] - R[i]);
    return c->mu * dd;
}

static double pd_weight(const eo_material_coef *c) { return 2 * c->mu; }

const eo_material_type eo_material_pd_arap = {
    .info = {.name = "pd_arap",
             .summary = "PD as-rigid-as-possible constraint, psi = mu |F - R|^2 (corotated with lambda = 0), "
                        "PD weight 2 mu"},
    .flags = EO_MATERIAL_INVERSION_SAFE | EO_MATERIAL_NO_VOLUME,
    .sigma_eval = sigma_eval,
    .F_psi_grad = F_psi_grad,
    .pd_weight = pd_weight,
};
