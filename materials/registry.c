/* Material registry: one line per model. */
#include "elastopt/material.h"
#include "material_registry.h"

extern const eo_material_type eo_material_linear, eo_material_stvk, eo_material_corotated,
    eo_material_fixed_corotated, eo_material_neo_hookean, eo_material_stable_neo_hookean,
    eo_material_spring, eo_material_pd_arap, eo_material_pd_strain_limit, eo_material_pd_volume;

const void *const eo_registry_material[] = {
    &eo_material_linear,
    &eo_material_stvk,
    &eo_material_corotated,
    &eo_material_fixed_corotated,
    &eo_material_neo_hookean,
    &eo_material_stable_neo_hookean,
    &eo_material_spring,
    &eo_material_pd_arap,
    &eo_material_pd_strain_limit,
    &eo_material_pd_volume,
    NULL,
};

/* A material table must give its values in one of the three forms (material.h). */
static int check_material(eo_ctx *ctx, const void *type)
{
    const eo_material_type *t = type;
    int forms = (t->sigma_eval != NULL) + (t->F_eval != NULL) + (t->edge_eval != NULL);
    if (forms != 1)
        return eo_error(ctx, EO_ERR_INVALID,
                        "register material '%s': exactly one of sigma_eval, F_eval, edge_eval must be set",
                        t->info.name);
    if (t->F_psi_grad && t->edge_eval)
        return eo_error(ctx, EO_ERR_INVALID,
                        "register material '%s': F_psi_grad is for models of F, not edge models", t->info.name);
    if (!!(t->flags & EO_MATERIAL_EDGE) != (t->edge_eval != NULL))
        return eo_error(ctx, EO_ERR_INVALID,
                        "register material '%s': EO_MATERIAL_EDGE goes with edge_eval", t->info.name);
    if (t->pd_weight && !t->sigma_eval)
        return eo_error(ctx, EO_ERR_INVALID,
                        "register material '%s': pd_weight is for isotropic tet models (sigma_eval)", t->info.name);
    return EO_OK;
}

eo_registry eo_reg_material = EO_REGISTRY_INIT(EO_KIND_MATERIAL, eo_registry_material, check_material);
