/* Explicit midpoint method, 001 §2.5: one Euler half step to tₙ + h/2, then the full
 * step with the slopes there:
 *
 *     aₙ = a(tₙ, xₙ, vₙ),
 *     x_m = xₙ + (h/2) vₙ,   v_m = vₙ + (h/2) aₙ,   a_m = a(tₙ + h/2, x_m, v_m),
 *     xₙ₊₁ = xₙ + h v_m,   vₙ₊₁ = vₙ + h a_m.
 *
 * Second order, the same Dahlquist amplification 1 + z + z²/2 as Heun (two force
 * evaluations per step). */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    (void)restart;
    const int n = ode->n;
    double *a0 = work, *xm = work + n, *vm = work + 2 * n, *am = work + 3 * n;
    int rc = ode->accel(ode->data, t, x, v, a0);
    if (rc < 0) return rc;
    for (int i = 0; i < n; i++) {
        xm[i] = x[i] + 0.5 * h * v[i];
        vm[i] = v[i] + 0.5 * h * a0[i];
    }
    rc = ode->accel(ode->data, t + 0.5 * h, xm, vm, am);
    if (rc < 0) return rc;
    for (int i = 0; i < n; i++) {
        x[i] += h * vm[i];
        v[i] += h * am[i];
    }
    return EO_OK;
}

const eo_integrator_type eo_integrator_midpoint = {
    .info = {.name = "midpoint", .summary = "explicit midpoint (half Euler step, then full step): second order"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 4,
};
