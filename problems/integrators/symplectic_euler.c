/* Symplectic (semi-implicit) Euler, 001 §2.5 eqs. 9–10 (the new velocity is reused):
 *
 *     vₙ₊₁ = vₙ + h a(tₙ, xₙ, vₙ),   xₙ₊₁ = xₙ + h vₙ₊₁.
 *
 * First order, symplectic: on the undamped oscillator the amplification matrix
 * [[1 − h²ω², h], [−hω², 1]] has determinant 1 and is stable for hω < 2; the energy is
 * not conserved exactly but oscillates within O(hω) of its initial value forever (a
 * nearby quadratic invariant is conserved). One force evaluation per step. */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    (void)restart;
    double *a = work;
    int rc = ode->accel(ode->data, t, x, v, a);
    if (rc < 0) return rc;
    for (int i = 0; i < ode->n; i++) {
        v[i] += h * a[i];
        x[i] += h * v[i];
    }
    return EO_OK;
}

const eo_integrator_type eo_integrator_symplectic_euler = {
    .info = {.name = "symplectic_euler",
             .summary = "explicit semi-implicit Euler (v then x): first order, symplectic"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 1,
};
