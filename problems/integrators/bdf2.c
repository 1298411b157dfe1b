/* Second-order backward differentiation formula (BDF2) on x' = v, M v' = f(x):
 *
 *     xₙ₊₁ − (4/3)xₙ + (1/3)xₙ₋₁ = (2h/3) vₙ₊₁,
 *     vₙ₊₁ − (4/3)vₙ + (1/3)vₙ₋₁ = (2h/3) M⁻¹f(xₙ₊₁).
 *
 * Eliminating vₙ₊₁ = (3xₙ₊₁ − 4xₙ + xₙ₋₁)/(2h) from the second line and multiplying
 * by 2h/3 gives M(x − x̃) = (4h²/9) f(x), i.e.
 *
 *     xₙ₊₁ = argmin ½‖x − x̃‖²_M + (4h²/9) E(x),
 *     x̃ = (4xₙ − xₙ₋₁)/3 + (2h/9)(4vₙ − vₙ₋₁),   linear term c = 0,
 *     vₙ₊₁ = (3xₙ₊₁ − 4xₙ + xₙ₋₁)/(2h).
 *
 * A two-step method: the step engine keeps (xₙ₋₁, vₙ₋₁) (history = 1; exposed for
 * restarts as eo_sim_get_history / eo_sim_set_history) and takes a backward Euler step
 * (w = h², x̃ = xₙ + h vₙ) while it has none (the first step, after a reset or a
 * set_state). Second order, A-stable (L-stable): it dissipates oscillations, the energy
 * of an undamped spring decays by O(h³ω⁴) per unit time (much less than backward
 * Euler's O(hω²)). */
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

static double weight_history(double h) { return 4.0 * h * h / 9.0; }

static void predict_history(int n, double h, const double *xn, const double *vn, const double *xp,
                            const double *vp, double *xt)
{
    for (int i = 0; i < n; i++) xt[i] = (4.0 * xn[i] - xp[i]) / 3.0 + 2.0 * h / 9.0 * (4.0 * vn[i] - vp[i]);
}

static void velocity_history(int n, double h, const double *xn, const double *xp, const double *x, double *v)
{
    for (int i = 0; i < n; i++) v[i] = (3.0 * x[i] - 4.0 * xn[i] + xp[i]) / (2.0 * h);
}

const eo_integrator_type eo_integrator_bdf2 = {
    .info = {.name = "bdf2",
             .summary = "implicit BDF2 (weight 4h^2/9, backward Euler start): second order, dissipative"},
    .inertia = 1,
    .force_n = 0,
    .dissipative = 1,
    .weight = weight,
    .predict = predict,
    .velocity = velocity,
    .history = 1,
    .weight_history = weight_history,
    .predict_history = predict_history,
    .velocity_history = velocity_history,
};
