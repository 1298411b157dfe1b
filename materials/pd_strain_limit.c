/* pd_strain_limit — the strain constraint of projective dynamics (Bouaziz et al. 2014
 * §5): C = {U diag(s) Vᵀ : s_i ∈ [σ_min, σ_max]}, bounds material.pd_min, material.pd_max
 * (default 1, 1: C = SO(3) and the model equals pd_arap), weight w = 2μ:
 *
 *   ψ = (w/2)‖F − proj_C(F)‖²_F = μ Σ (σ_i − clamp(σ_i, σ_min, σ_max))².
 *
 * No energy while every singular value is inside the bounds (strain limiting: the model
 * only resists stretch beyond σ_max and compression beyond σ_min); a rotated element
 * costs nothing. PD weight 2μ per unit rest volume. Derivatives: pd_constraint.h. */
#include "pd_constraint.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    eo_pd_strain_add(2 * c->mu, c->pd_min, c->pd_max, s, what, o);
}

static double pd_weight(const eo_material_coef *c) { return 2 * c->mu; }

const eo_material_type eo_material_pd_strain_limit = {
    .info = {.name = "pd_strain_limit",
             .summary = "PD strain-limiting constraint, psi = mu sum (s_i - clamp(s_i, pd_min, pd_max))^2, "
                        "PD weight 2 mu"},
    .flags = EO_MATERIAL_INVERSION_SAFE | EO_MATERIAL_NO_VOLUME,
    .sigma_eval = sigma_eval,
    .pd_weight = pd_weight,
};
