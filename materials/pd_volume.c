/* pd_volume — ARAP plus the volume-preservation constraint of projective dynamics
 * (Bouaziz et al. 2014 §5): two constraints on the same F,
 *
 *   ψ = μ‖F − R‖²_F  +  (3λ/2)·min{‖F − T‖²_F : det T ∈ [pd_min, pd_max]},
 *
 * weights 2μ (SO(3)) and 3λ (volume), bounds material.pd_min, material.pd_max on det F
 * (default 1, 1: exact volume preservation). The weight 3λ makes the model linearize to
 * linear elasticity with the same μ, λ: near F = I the distance to {det = 1} is
 * tr(ε)/√3, so (3λ/2)·tr²(ε)/3 = (λ/2)tr²(ε), and μ‖F − R‖² ≈ μ‖ε‖². The PD weight of
 * the element (the global matrix) is the sum 2μ + 3λ. Derivatives: pd_constraint.h. */
#include "pd_constraint.h"

static void sigma_eval(const eo_material_coef *c, const double s[3], eo_eval_what what, eo_sigma_eval *o)
{
    eo_pd_strain_add(2 * c->mu, 1, 1, s, what, o);
    eo_pd_volume_add(3 * c->lambda, c->pd_min, c->pd_max, s, what, o);
}

static double pd_weight(const eo_material_coef *c) { return 2 * c->mu + 3 * c->lambda; }

const eo_material_type eo_material_pd_volume = {
    .info = {.name = "pd_volume",
             .summary = "PD ARAP + volume constraint (det F in [pd_min, pd_max]), weights 2 mu and 3 lambda"},
    .flags = EO_MATERIAL_INVERSION_SAFE,
    .sigma_eval = sigma_eval,
    .pd_weight = pd_weight,
};
