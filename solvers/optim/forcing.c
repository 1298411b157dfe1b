/* Eisenstat–Walker forcing terms, choice 2 with safeguards (see forcing.h for the
 * formulas and the references). */
#include "forcing.h"

#include <math.h>
#include <stddef.h>

const eo_param_desc eo_forcing_desc[] = {
    {.key = "gamma", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_forcing_params, gamma), .def.d = 0.9,
     .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX,
     .help = "Eisenstat-Walker choice 2: eta_k = gamma (|g_k|/|g_k-1|)^alpha"},
    {.key = "alpha", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_forcing_params, alpha), .def.d = 2,
     .min = 1, .max = 2, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX, .help = "exponent alpha in (1, 2]"},
    {.key = "eta0", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_forcing_params, eta0), .def.d = 0.5,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "forcing term of the first iteration"},
    {.key = "eta_max", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_forcing_params, eta_max), .def.d = 0.9,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "upper bound of the forcing term"},
    {.key = "eta_min", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_forcing_params, eta_min), .def.d = 0,
     .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN, .help = "lower bound of the forcing term"},
    {.key = "gtol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_forcing_params, gtol), .def.d = 0, .min = 0,
     .range = EO_RANGE_MIN,
     .help = "absolute gradient tolerance: eta_k >= 0.5 gtol/|g_k| (no oversolving); 0 = off"},
    {0},
};

void eo_forcing_params_default(eo_forcing_params *p)
{
    *p = (eo_forcing_params){.gamma = 0.9, .alpha = 2, .eta0 = 0.5, .eta_max = 0.9, .eta_min = 0, .gtol = 0};
}

double eo_forcing_eta(const eo_forcing_params *p, int k, double gnorm, double gnorm_prev, double eta_prev)
{
    double eta;
    if (k <= 0) {
        eta = p->eta0;
    } else {
        if (!(gnorm >= 0) || !(gnorm_prev > 0) || !isfinite(gnorm) || !isfinite(gnorm_prev)) return p->eta_max;
        eta = p->gamma * pow(gnorm / gnorm_prev, p->alpha);
        double floor = p->gamma * pow(eta_prev, p->alpha); /* (a) */
        if (floor > 0.1 && eta < floor) eta = floor;
    }
    if (eta > p->eta_max) eta = p->eta_max; /* (b) */
    if (p->gtol > 0 && gnorm > 0 && eta < 0.5 * p->gtol / gnorm) eta = 0.5 * p->gtol / gnorm; /* (c) */
    if (eta > p->eta_max) eta = p->eta_max;
    if (eta < p->eta_min) eta = p->eta_min; /* (d) */
    return eta;
}
