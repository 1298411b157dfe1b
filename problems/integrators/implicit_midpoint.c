/* Implicit midpoint rule (the one-stage Gauss–Legendre method) posed as a minimization
 * in the midpoint z = (xₙ + xₙ₊₁)/2:
 *
 *     xₙ₊₁ = xₙ + h v_{n+½},   M(vₙ₊₁ − vₙ) = h f(z),   v_{n+½} = (vₙ + vₙ₊₁)/2
 *  ⇔  M(z − x̃) = (h²/4) f(z),   x̃ = xₙ + (h/2) vₙ
 *  ⇔  z = argmin ½‖z − x̃‖²_M + (h²/4) E(z)      (a backward Euler step of h/2)
 *     xₙ₊₁ = 2z − xₙ,   vₙ₊₁ = 2(xₙ₊₁ − xₙ)/h − vₙ.
 *
 * So w = h²/4, x̃ = xₙ + (h/2)vₙ, linear term c = 0, and θ = ½ tells the step engine
 * that the minimizer is the stage z (prescribed coordinates at (xₙ + p(tₙ₊₁))/2,
 * xₙ₊₁ = xₙ + (z − xₙ)/θ). Second order, A-stable, symplectic: for linear forces it
 * conserves the quadratic energy ½vᵀMv + ½xᵀKx exactly (up to the solver tolerance);
 * on y' = λy its amplification is (1 + z/2)/(1 − z/2), the same as Newmark's, but for
 * nonlinear forces the two differ (Newmark averages the forces, this evaluates them at
 * the midpoint). */
#include "elastopt/step.h"

static double weight(double h) { return 0.25 * h * h; }

static void predict(int n, double h, const double *xn, const double *vn, double *xt)
{
    for (int i = 0; i < n; i++) xt[i] = xn[i] + 0.5 * h * vn[i];
}

static void velocity(int n, double h, const double *xn, const double *vn, const double *x, double *v)
{
    for (int i = 0; i < n; i++) v[i] = 2.0 * (x[i] - xn[i]) / h - vn[i];
}

const eo_integrator_type eo_integrator_implicit_midpoint = {
    .info = {.name = "implicit_midpoint",
             .summary = "implicit midpoint rule, min in the midpoint (weight h^2/4): second order, "
                        "conserves quadratic energies"},
    .inertia = 1,
    .force_n = 0,
    .weight = weight,
    .predict = predict,
    .velocity = velocity,
    .theta = 0.5,
};
