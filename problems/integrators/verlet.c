/* Velocity Verlet, 001 §2.5 (eq. 23 written with an explicit velocity):
 *
 *     aₙ = a(tₙ, xₙ, vₙ),
 *     xₙ₊₁ = xₙ + h vₙ + (h²/2) aₙ,
 *     aₙ₊₁ = a(tₙ₊₁, xₙ₊₁, vₙ + h aₙ),     (velocity predicted only for damping forces)
 *     vₙ₊₁ = vₙ + (h/2)(aₙ + aₙ₊₁).
 *
 * Its positions are those of Størmer–Verlet xₙ₊₁ = 2xₙ − xₙ₋₁ + h² aₙ (eq. 23); the
 * velocity is the trapezoidal one instead of a finite difference. Second order,
 * symplectic and time reversible for velocity-independent forces: stable for hω < 2
 * with the energy oscillating within O(h²ω²) and no drift. Two force evaluations per
 * step (aₙ is recomputed rather than cached so that any state change between steps is
 * honoured; `leapfrog` is the one-evaluation staggered form). */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    (void)restart;
    const int n = ode->n;
    double *a0 = work, *a1 = work + n, *vp = work + 2 * n;
    int rc = ode->accel(ode->data, t, x, v, a0);
    if (rc < 0) return rc;
    for (int i = 0; i < n; i++) {
        x[i] += h * v[i] + 0.5 * h * h * a0[i];
        vp[i] = v[i] + h * a0[i];
    }
    rc = ode->accel(ode->data, t + h, x, vp, a1);
    if (rc < 0) return rc;
    for (int i = 0; i < n; i++) v[i] += 0.5 * h * (a0[i] + a1[i]);
    return EO_OK;
}

const eo_integrator_type eo_integrator_verlet = {
    .info = {.name = "verlet", .summary = "explicit velocity Verlet: second order, symplectic"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 3,
};
