/* Classical fourth-order Runge–Kutta, 001 §2.5 eqs. 16–20 with the ERRATA's k₄, on the
 * first-order system y = (x, v), y' = F(t, y) = (v, a(t, x, v)):
 *
 *     k₁ = F(tₙ, yₙ),              k₂ = F(tₙ + h/2, yₙ + (h/2) k₁),
 *     k₃ = F(tₙ + h/2, yₙ + (h/2) k₂),   k₄ = F(tₙ + h, yₙ + h k₃),
 *     yₙ₊₁ = yₙ + (h/6)(k₁ + 2k₂ + 2k₃ + k₄).
 *
 * Fourth order. Dahlquist amplification R(z) = 1 + z + z²/2 + z³/6 + z⁴/24; on the
 * undamped oscillator (z = ihω) |R| ≤ 1 iff hω ≤ 2√2 ≈ 2.83 (slightly dissipative
 * below, blowing up above). Four force evaluations per step.
 * The x-part of stage kᵢ is the stage velocity, so the stage state (xs, vs) and the
 * accelerations ka suffice: 5 work vectors (xs, vs, ka and the two accumulators). */
#include "elastopt/step.h"

static int step(const eo_ode *ode, double t, double h, double *x, double *v, double *work, int restart)
{
    (void)restart;
    const int n = ode->n;
    double *xs = work, *vs = work + n, *ka = work + 2 * n, *sx = work + 3 * n, *sv = work + 4 * n;
    static const double c[4] = {0, 0.5, 0.5, 1}, wgt[4] = {1, 2, 2, 1};
    for (int i = 0; i < n; i++) {
        xs[i] = x[i];
        vs[i] = v[i];
        sx[i] = sv[i] = 0;
    }
    for (int s = 0; s < 4; s++) {
        if (s > 0) /* stage state yₙ + c h k_{s}: x-part uses the previous stage velocity vs */
            for (int i = 0; i < n; i++) {
                double kx = vs[i];
                xs[i] = x[i] + c[s] * h * kx;
                vs[i] = v[i] + c[s] * h * ka[i];
            }
        int rc = ode->accel(ode->data, t + c[s] * h, xs, vs, ka);
        if (rc < 0) return rc;
        for (int i = 0; i < n; i++) {
            sx[i] += wgt[s] * vs[i];
            sv[i] += wgt[s] * ka[i];
        }
    }
    for (int i = 0; i < n; i++) {
        x[i] += h / 6 * sx[i];
        v[i] += h / 6 * sv[i];
    }
    return EO_OK;
}

const eo_integrator_type eo_integrator_rk4 = {
    .info = {.name = "rk4", .summary = "explicit classical Runge-Kutta: fourth order, stable for h*omega < 2.83"},
    .inertia = 1,
    .explicit_step = step,
    .work_vectors = 5,
};
