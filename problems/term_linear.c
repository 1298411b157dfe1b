/* Linear term: −w · cᵀx with a full-length vector c (t->vec) set by the step before
 * each solve. Newmark uses it for the trapezoidal force of the previous state,
 * c = fₙ = −∇E(xₙ) (elastic and gravity forces at xₙ), so that
 *     g(x) = ½‖x − x̃‖²_M + (h²/4)(E(x) − fₙᵀx),   x̃ = xₙ + h vₙ,
 * whose stationarity M(x − xₙ − h vₙ) = (h²/4)(f(x) + fₙ) is the Newmark update with
 * β = ¼, γ = ½, with no solve with M. No Hessian. */
#include "elastopt/step.h"
#include "term.h"

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    double e = 0;
    for (int j = 0; j < s->n_full; j++)
        if (eo_sys_vertex_on(s, j / 3)) e -= t->vec[j] * x[j];
    return t->weight * e;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    for (int j = 0; j < s->n_full; j++)
        if (eo_sys_vertex_on(s, j / 3)) g[j] -= t->weight * t->vec[j];
    return energy(t, s, x);
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    (void)t, (void)s, (void)x, (void)proj;
    return EO_OK;
}

static double vertex(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3)
{
    (void)s, (void)proj, (void)H3;
    double e = 0;
    for (int c = 0; c < 3; c++) {
        e -= t->weight * t->vec[3 * v + c] * x[3 * v + c];
        if (g3) g3[c] -= t->weight * t->vec[3 * v + c];
    }
    return e;
}

static const eo_term_ops linear_ops = {
    .name = "linear",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .vertex = vertex,
};

int eo_term_linear_create(eo_sys *s, eo_term **out) { return eo_term_alloc(s, &linear_ops, 1, out); }

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)cfg;
    *out = NULL;
    return sc->integrator->force_n ? eo_term_linear_create(s, out) : EO_OK;
}

const eo_term_type eo_term_type_linear = {
    .info = {.name = "linear", .summary = "the integrators' linear term −cᵀx, c = fₙ the force at the start of the step (force_n)"},
    .flags = EO_TERM_FORCE_N,
    .create = type_create,
};
