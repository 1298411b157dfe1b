/* The `material` config section and the shared coefficients.
 *
 * Lamé parameters from Young's modulus E and Poisson ratio ν:
 *     μ = E / (2(1+ν)),   λ = E ν / ((1+ν)(1−2ν)).
 * Keys: model (registered material name), E (Pa), nu, density (kg/m³), k (N/m, springs),
 * pd_min, pd_max (bounds of the pd_strain_limit / pd_volume constraints). */
#include <stddef.h>

#include "elastopt/material.h"
#include "material_registry.h"

eo_material_coef eo_material_coef_from(double E, double nu, double density, double k)
{
    eo_material_coef c;
    c.E = E;
    c.nu = nu;
    c.mu = E / (2.0 * (1.0 + nu));
    c.lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    c.density = density;
    c.k = k;
    c.pd_min = 1;
    c.pd_max = 1;
    return c;
}

eo_material_coef eo_material_coef_from_opts(const eo_material_opts *o)
{
    eo_material_coef c = eo_material_coef_from(o->E, o->nu, o->density, o->k);
    c.pd_min = o->pd_min;
    c.pd_max = o->pd_max;
    return c;
}

const eo_param_desc eo_material_opts_desc[] = {
    {.key = "model", .kind = EO_PARAM_METHOD, .offset = offsetof(eo_material_opts, model),
     .size = sizeof(((eo_material_opts *)0)->model), .def.s = "stable_neo_hookean",
     .registry = &eo_reg_material, .help = "material model (registered name)"},
    {.key = "E", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_material_opts, E), .def.d = 1e5,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "Young's modulus (Pa)"},
    {.key = "nu", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_material_opts, nu), .def.d = 0.45,
     .min = -1, .max = 0.5, .range = EO_RANGE_OPEN, .help = "Poisson ratio"},
    {.key = "density", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_material_opts, density),
     .def.d = 1000, .min = 0, .range = EO_RANGE_POSITIVE, .help = "mass density (kg/m^3)"},
    {.key = "k", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_material_opts, k), .def.d = 1000,
     .min = 0, .range = EO_RANGE_POSITIVE, .help = "spring stiffness (N/m), spring model only"},
    {.key = "pd_min", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_material_opts, pd_min), .def.d = 1,
     .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "lower bound of the PD constraint: singular values (pd_strain_limit) or det F (pd_volume)"},
    {.key = "pd_max", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_material_opts, pd_max), .def.d = 1,
     .min = 0, .range = EO_RANGE_POSITIVE,
     .help = "upper bound of the PD constraint (>= pd_min): singular values or det F"},
    {0},
};
