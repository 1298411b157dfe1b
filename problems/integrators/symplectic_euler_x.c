/* Symplectic Euler, position first: 001 §2.5 eqs. 7–8 (the new position is reused):
 *
 *     xₙ₊₁ = xₙ + h vₙ,   vₙ₊₁ = vₙ + h a(tₙ₊₁, xₙ₊₁, vₙ).
 *
 * The adjoint of `symplectic_euler` (eqs. 9–10, velocity first). First order,
 * symplectic: on the undamped oscillator the one-step matrix [[1, h], [−hω², 1 − h²ω²]]
 * has determinant 1 and is stable for hω < 2; the energy oscillates within O(hω) of
 * its initial value without drift. Damping forces see the old velocity vₙ. One force
 * evaluation per step. */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    (void)restart;
    double *a = work;
    for (int i = 0; i < ode->n; i++) x[i] += h * v[i];
    int rc = ode->accel(ode->data, t + h, x, v, a);
    if (rc < 0) return rc;
    for (int i = 0; i < ode->n; i++) v[i] += h * a[i];
    return EO_OK;
}

const eo_integrator_type eo_integrator_symplectic_euler_x = {
    .info = {.name = "symplectic_euler_x",
             .summary = "explicit symplectic Euler, x then v (001 eqs. 7-8): first order, symplectic"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 1,
};
