/* Eisenstat–Walker forcing terms, choice 2 with safeguards (see forcing.h for the
 * formulas and the references). */
#include "forcing.h"

#include <string.h>

#include "elastopt/linsolve.h"

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

double eo_forcing_eta_ew1(const eo_forcing_params *p, int k, double gnorm, double gnorm_prev,
                          double linres_prev, double eta_prev)
{
    double eta;
    if (k <= 0) {
        eta = p->eta0;
    } else {
        if (!(gnorm >= 0) || !(gnorm_prev > 0) || !(linres_prev >= 0) || !isfinite(gnorm) ||
            !isfinite(gnorm_prev) || !isfinite(linres_prev))
            return p->eta_max;
        eta = fabs(gnorm - linres_prev) / gnorm_prev;
        const double phi = 0.5 * (1 + sqrt(5.0));
        double floor = pow(eta_prev, phi); /* safeguard (2.2) */
        if (floor > 0.1 && eta < floor) eta = floor;
    }
    if (eta > p->eta_max) eta = p->eta_max;
    if (p->gtol > 0 && gnorm > 0 && eta < 0.5 * p->gtol / gnorm) eta = 0.5 * p->gtol / gnorm;
    if (eta > p->eta_max) eta = p->eta_max;
    if (eta < p->eta_min) eta = p->eta_min;
    return eta;
}

int eo_forcing_kind(const char *name)
{
    static const char *const names[] = {"none", "constant", "ew1", "ew2", "auto"};
    for (int i = 0; i < 5; i++)
        if (name && !strcmp(name, names[i])) return i;
    return -1;
}

void eo_inexact_begin(eo_inexact *s, int kind, double eta, double gamma, double alpha, double eta_min,
                      double eta_max)
{
    memset(s, 0, sizeof *s);
    s->kind = kind;
    eo_forcing_params_default(&s->fp);
    s->fp.eta0 = eta;
    s->fp.gamma = gamma;
    s->fp.alpha = alpha;
    s->fp.eta_min = eta_min;
    s->fp.eta_max = eta_max;
    s->local_ratio = 0.1;
    s->eta_global = 1e-4;
    s->global_max_iters = 20;
    s->guard_off = s->guarded = 0;
    s->gnorm_prev = s->linres_prev = s->eta_prev = s->alpha_prev = s->dec_prev = s->dec_prev2 = NAN;
}

double eo_inexact_before(eo_inexact *s, struct eo_linsolve *ls, double gnorm)
{
    double eta = 0;
    switch (s->kind) { /* the four forcing rules of this file, not method names */
    case EO_FORCING_CONSTANT: eta = s->fp.eta0; break;
    case EO_FORCING_EW1:
        eta = eo_forcing_eta_ew1(&s->fp, s->k, gnorm, s->gnorm_prev, s->linres_prev, s->eta_prev);
        break;
    case EO_FORCING_AUTO: /* ew2 while the solves are iterative */
        if (!ls || !eo_linsolve_is_iterative(ls)) return 0;
        /* a guarded solve that needed many iterations: this solver's tight solves are
         * costly (multigrid on nearly incompressible problems), ew2 from here on */
        if (s->guarded && eo_linsolve_get_stats(ls)->iterations > s->global_max_iters) s->guard_off = 1;
        /* not yet fast local convergence (forcing.h): η = eta_global */
        s->guarded = !s->guard_off &&
                     (s->alpha_prev < 1 || (s->dec_prev2 > 0 && s->dec_prev > s->local_ratio * s->dec_prev2));
        eta = s->guarded ? s->eta_global : eo_forcing_eta(&s->fp, s->k, gnorm, s->gnorm_prev, s->eta_prev);
        break;
    case EO_FORCING_EW2: eta = eo_forcing_eta(&s->fp, s->k, gnorm, s->gnorm_prev, s->eta_prev); break;
    default: return 0;
    }
    if (!(eta > 0 && eta < 1)) eta = eta >= 1 ? 0.9 : 1e-16;
    eo_linsolve_set_rtol(ls, eta);
    s->eta_prev = eta;
    s->k++;
    return eta;
}

void eo_inexact_after(eo_inexact *s, double gnorm, double linres, double alpha, double dec)
{
    s->alpha_prev = alpha;
    s->dec_prev2 = s->dec_prev;
    s->dec_prev = dec;
    s->gnorm_prev = gnorm;
    s->linres_prev = linres;
}
