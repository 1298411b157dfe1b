/* Implicit Newmark, β = ¼, γ = ½ (average acceleration / trapezoidal rule), 002 §3.1
 * with the ERRATA's mass-matrix form:
 *
 *     xₙ₊₁ = xₙ + (h/2)(vₙ + vₙ₊₁),   M vₙ₊₁ = M vₙ + (h/2)(fₙ + fₙ₊₁)
 *  ⇔  xₙ₊₁ = argmin ½‖x − x̃‖²_M + (h²/4)(E(x) − fₙᵀx),   x̃ = xₙ + h vₙ,  fₙ = −∇E(xₙ),
 *     vₙ₊₁ = 2(xₙ₊₁ − xₙ)/h − vₙ.
 *
 * Second order, unconditionally stable, and for linear forces it conserves the
 * total energy ½vᵀMv + E exactly (up to the solver tolerance). */
#include "elastopt/step.h"

static double weight(double h) { return 0.25 * h * h; }

static void predict(int n, double h, const double *xn, const double *vn, double *xt)
{
    for (int i = 0; i < n; i++) xt[i] = xn[i] + h * vn[i];
}

static void velocity(int n, double h, const double *xn, const double *vn, const double *x, double *v)
{
    for (int i = 0; i < n; i++) v[i] = 2.0 * (x[i] - xn[i]) / h - vn[i];
}

const eo_integrator_type eo_integrator_newmark = {
    .info = {.name = "newmark",
             .summary = "implicit Newmark beta=1/4 gamma=1/2: weight h^2/4, energy conserving"},
    .inertia = 1,
    .force_n = 1,
    .weight = weight,
    .predict = predict,
    .velocity = velocity,
};
