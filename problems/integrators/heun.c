/* Heun's method (explicit trapezoidal rule), 001 §2.5 eqs. 11–15:
 *
 *     aₙ = a(tₙ, xₙ, vₙ),
 *     x̃ = xₙ + h vₙ,   ṽ = vₙ + h aₙ,          (Euler predictor)
 *     ã = a(tₙ + h, x̃, ṽ),
 *     xₙ₊₁ = xₙ + (h/2)(vₙ + ṽ),   vₙ₊₁ = vₙ + (h/2)(aₙ + ã).
 *
 * Second order (y' ≈ average of the slopes at both ends). Dahlquist amplification
 * 1 + z + z²/2 (z = hλ); on the undamped oscillator |R| = √(1 + (hω)⁴/4) > 1: a slow
 * energy gain. Two force evaluations per step. */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    (void)restart;
    const int n = ode->n;
    double *a0 = work, *xt = work + n, *vt = work + 2 * n, *at = work + 3 * n;
    int rc = ode->accel(ode->data, t, x, v, a0);
    if (rc < 0) return rc;
    for (int i = 0; i < n; i++) {
        xt[i] = x[i] + h * v[i];
        vt[i] = v[i] + h * a0[i];
    }
    rc = ode->accel(ode->data, t + h, xt, vt, at);
    if (rc < 0) return rc;
    for (int i = 0; i < n; i++) {
        x[i] += 0.5 * h * (v[i] + vt[i]);
        v[i] += 0.5 * h * (a0[i] + at[i]);
    }
    return EO_OK;
}

const eo_integrator_type eo_integrator_heun = {
    .info = {.name = "heun", .summary = "explicit Heun (trapezoidal predictor-corrector): second order"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 4,
};
