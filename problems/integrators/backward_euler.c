/* Backward (implicit) Euler:
 *
 *     xₙ₊₁ = xₙ + h vₙ₊₁,   M vₙ₊₁ = M vₙ + h f(xₙ₊₁)
 *  ⇔  xₙ₊₁ = argmin ½‖x − x̃‖²_M + h² E(x),   x̃ = xₙ + h vₙ,
 *     vₙ₊₁ = (xₙ₊₁ − xₙ)/h.
 *
 * First order, unconditionally stable, numerically dissipative (total energy
 * decreases), which makes it the robust choice for recovering from bad states. */
#include "elastopt/step.h"

static double weight(double h) { return h * h; }

static void predict(int n, double h, const double *xn, const double *vn, double *xt)
{
    for (int i = 0; i < n; i++) xt[i] = xn[i] + h * vn[i];
}

static void velocity(int n, double h, const double *xn, const double *vn, const double *x, double *v)
{
    (void)vn;
    for (int i = 0; i < n; i++) v[i] = (x[i] - xn[i]) / h;
}

const eo_integrator_type eo_integrator_backward_euler = {
    .info = {.name = "backward_euler",
             .summary = "implicit Euler: weight h^2, first order, dissipative"},
    .inertia = 1,
    .force_n = 0,
    .dissipative = 1,
    .weight = weight,
    .predict = predict,
    .velocity = velocity,
};
