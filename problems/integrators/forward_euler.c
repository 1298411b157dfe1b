/* Forward (explicit) Euler, 001 §2.5 eq. 6:
 *
 *     aₙ = a(tₙ, xₙ, vₙ),   xₙ₊₁ = xₙ + h vₙ,   vₙ₊₁ = vₙ + h aₙ.
 *
 * First order. On the Dahlquist test equation y' = λy it multiplies y by 1 + hλ: stable
 * iff |1 + hλ| ≤ 1 (−2 < hλ < 0 for real λ); on the undamped oscillator (λ = ±iω) the
 * amplification is |1 + ihω| = √(1 + h²ω²) > 1, so the energy grows by (1 + h²ω²) per
 * step for every h: never stable without damping. One force evaluation per step. */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    (void)restart;
    double *a = work;
    int rc = ode->accel(ode->data, t, x, v, a);
    if (rc < 0) return rc;
    for (int i = 0; i < ode->n; i++) {
        x[i] += h * v[i];
        v[i] += h * a[i];
    }
    return EO_OK;
}

const eo_integrator_type eo_integrator_forward_euler = {
    .info = {.name = "forward_euler",
             .summary = "explicit Euler: first order, gains energy on undamped oscillations"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 1,
};
