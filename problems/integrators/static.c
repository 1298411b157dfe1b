/* Static equilibrium: no inertia, each "step" solves
 *
 *     xₙ₊₁ = argmin E(x)   (elastic energy + gravity potential, weight 1)
 *
 * with the boundary conditions at tₙ₊₁ (so prescribed motions give a quasi-static
 * loading path); the velocity is 0. The previous solution is the starting guess.
 * Needs enough constrained vertices to remove the rigid motions.
 *
 * Quasi-static load stepping (time.load_steps = L > 0, the usual way to reach large
 * deflections, where Newton from the rest shape under the full load may fail): step
 * k = 1, 2, … minimizes
 *
 *     E_el(x) − λₖ f_gᵀx,   λₖ = min(1, k/L),
 *
 * with the prescribed motions evaluated at min(tₖ, L·dt): gravity and every prescribed
 * motion grow linearly over the first L steps and are held at their full value after,
 * each increment a minimization started from the previous equilibrium (the step
 * engine, problems/step_objective.c and step_bc.c). */
#include "elastopt/step.h"

static double weight(double h)
{
    (void)h;
    return 1.0;
}

static void predict(int n, double h, const double *xn, const double *vn, double *xt)
{
    (void)h, (void)vn;
    for (int i = 0; i < n; i++) xt[i] = xn[i];
}

static void velocity(int n, double h, const double *xn, const double *vn, const double *x, double *v)
{
    (void)h, (void)xn, (void)vn, (void)x;
    for (int i = 0; i < n; i++) v[i] = 0;
}

const eo_integrator_type eo_integrator_static = {
    .info = {.name = "static", .summary = "static equilibrium min E(x), no inertia, velocity 0"},
    .inertia = 0,
    .force_n = 0,
    .dissipative = 1,
    .weight = weight,
    .predict = predict,
    .velocity = velocity,
};
