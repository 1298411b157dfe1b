/* Leapfrog, 001 §2.5 eqs. 24–26: velocities live at half steps, positions and
 * accelerations at whole steps,
 *
 *     v_{n+½} = v_{n−½} + h a(xₙ),   xₙ₊₁ = xₙ + h v_{n+½},
 *
 * started with a half Euler step v_{½} = v₀ + (h/2) a(x₀) (a full Euler step, as the
 * notes allow, would make the start first order). The staggered velocity persists in
 * the integrator's work vector between steps; the state velocity the engine reports
 * is the synchronized vₙ₊₁ = v_{n+½} + (h/2) aₙ₊₁ (for output and energies). Second
 * order, symplectic, one force evaluation per step (two on a restart). Damping forces
 * see the half-step velocity. */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    const int n = ode->n;
    double *vh = work, *a = work + n;
    int rc;
    if (restart) { /* v_{n+½} from the synchronized state */
        rc = ode->accel(ode->data, t, x, v, a);
        if (rc < 0) return rc;
        for (int i = 0; i < n; i++) vh[i] = v[i] + 0.5 * h * a[i];
    }
    for (int i = 0; i < n; i++) x[i] += h * vh[i];
    rc = ode->accel(ode->data, t + h, x, vh, a);
    if (rc < 0) return rc;
    for (int i = 0; i < n; i++) {
        v[i] = vh[i] + 0.5 * h * a[i];
        vh[i] += h * a[i]; /* v_{n+3/2} for the next step */
    }
    return EO_OK;
}

const eo_integrator_type eo_integrator_leapfrog = {
    .info = {.name = "leapfrog", .summary = "explicit leapfrog (staggered velocities): second order, symplectic"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 2,
};
