/// @file stability.h
/// Dahlquist stability of the time integrators, measured (notes 001 §2.6).
///
/// Every registered integrator (registry kind EO_KIND_INTEGRATOR) is applied, one step
/// at a time, to the linear test system of one unit mass
///
///     x' = v,   v' = −k x − c v          (h = 1: k = (hω)², c = −hλ, all dimensionless)
///
/// and the amplification of one step is read off as the 2×2 matrix M with
/// (xₙ₊₁, vₙ₊₁) = M (xₙ, vₙ) (two steps, from (1, 0) and from (0, 1)). The mappings of
/// the scalar test equation y' = λy onto the (x, v) form:
///  - real axis, z = hλ < 0: k = 0, c = −z. The velocity obeys v' = λv exactly and x is
///    its integral without feedback, so the amplification is R = M_vv (for a Runge–Kutta
///    method, R(z) of the scalar equation);
///  - imaginary axis, z = ±ihω: the undamped spring k = (hω)², c = 0, eigenvalues ±iω;
///    the amplification is the spectral radius ρ(M) (for a Runge–Kutta method
///    |R(ihω)|; for the symplectic methods the spring's own one-step matrix);
///  - any complex z (the region plot): c = −2 Re z, k = |z|², whose eigenvalues are z
///    and z̄, so ρ(M) = |R(z)| for the methods that are a one-step rule on the
///    first-order ODE (forward Euler, Heun, midpoint, RK4, backward Euler, Newmark).
/// A step is unstable when the amplification exceeds 1 (ρ² > 1 + 1e-13, a threshold
/// above rounding): the bound is the end of the stable interval next to 0, found by a
/// scan (0.01 steps to 10, then ×1.05 to 1e4) and 60 bisections. No unstable sample up
/// to 1e4 → "unconditional"; a bound below 1e-3 (growth below the threshold's
/// resolution, e.g. Heun's |R(iy)|² = 1 + y⁴/4) → "none".
///
/// How each kind of integrator is stepped:
///  - explicit (explicit_step set): its own explicit_step on an eo_ode whose accel is
///    a = −k x − c v; leapfrog is stepped with restart = 1 (synchronized state in and
///    out; for velocity-independent forces this map is conjugate to its staggered one);
///  - implicit (weight, predict, velocity): the step problem min g(x) of step.h,
///        g(x) = inertia·½(x − x̃)² + w(P(x) − cₙx),   P'(x) = −f(x, v(x)),
///    with the integrator's own w = weight(h), x̃ = predict(xₙ, vₙ), velocity op
///    v(x) = αx + β (affine; α, β read from two calls) and cₙ = fₙ when force_n, where
///    f(x, v) = −kx − cv. The damping force is taken at the end-of-step velocity the
///    integrator's velocity op gives (for backward Euler and Newmark this is exactly the
///    method on the first-order system). g is a 1D quadratic, minimized in closed form
///    (x = (inertia·x̃ − w(cβ − cₙ)) / (inertia + w(k + cα))): the step engine's
///    solver is not run; this measures the integrator's ops, not a scene.
///    An integrator without inertia (static) has no velocity state: real axis n/a.
///    An integrator with a stage θ ≠ 1 (implicit_midpoint, θ = ½) is minimized in the
///    stage z, mapped back with xₙ₊₁ = xₙ + (z − xₙ)/θ, its damping force taken at the
///    stage velocity vₙ + θ(vₙ₊₁ − vₙ). A multistep integrator (bdf2) is measured by its
///    one-step start (backward Euler): one step from a state has no history.
///
/// ```c
/// eo_stability_result r, t;
/// eo_stability_measure(ctx, &eo_integrator_rk4, &r);      // r.real.bound ≈ −2.785
/// if (eo_stability_theory("rk4", &t)) eo_stability_agrees(&r, &t, 1e-3);
/// ```
/// The library never prints; `elastopt stability` prints the table and the plot.
#ifndef ELASTOPT_STABILITY_H
#define ELASTOPT_STABILITY_H

#include "export.h"
#include "step.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum eo_stability_kind {
    EO_STAB_NA = 0,          ///< not applicable (no velocity state) or no theory
    EO_STAB_BOUNDED,         ///< stable on (bound, 0) (real) or [0, bound) (imaginary)
    EO_STAB_NONE,            ///< unstable for every step > 0
    EO_STAB_UNCONDITIONAL,   ///< stable for every step (up to 1e4 when measured)
} eo_stability_kind;

/// One axis: the kind and, for EO_STAB_BOUNDED, the bound (hλ < 0 on the real axis,
/// hω > 0 on the imaginary axis).
typedef struct eo_stability_axis {
    eo_stability_kind kind;
    double bound;
} eo_stability_axis;

typedef struct eo_stability_result {
    eo_stability_axis real;  ///< test equation y' = λy, hλ < 0
    eo_stability_axis imag;  ///< undamped spring x'' = −ω²x (hλ = ±ihω)
    int first_order_form;    ///< theory: 1 if ρ(M) = |R(z)| of a one-step rule on (x, v)
} eo_stability_result;

/// One-step matrix M (row-major, (x, v) order) of integrator `it` on x'' = −kx − cx'
/// with unit mass and h = 1. Returns EO_OK, EO_ERR_INVALID for an integrator with
/// neither explicit_step nor weight/predict/velocity, EO_ERR_NONFINITE when the step
/// problem has no minimizer (inertia + w(k + cα) ≤ 0) or the step is not finite.
EO_API int eo_stability_matrix(eo_ctx *ctx, const eo_integrator_type *it, double k, double c, double M[4]);
/// Spectral radius of a 2×2 matrix (row-major).
EO_API double eo_stability_spectral_radius(const double M[4]);
/// ρ of one step for complex z = re + i·im through the mapping c = −2 re, k = re² + im²
/// (= |R(z)| for the first-order-form methods).
EO_API int eo_stability_rho(eo_ctx *ctx, const eo_integrator_type *it, double re, double im, double *rho);
/// Measure both axes of `it` (see the file comment). Errors of eo_stability_matrix
/// other than EO_ERR_NONFINITE (which counts as unstable).
EO_API int eo_stability_measure(eo_ctx *ctx, const eo_integrator_type *it, eo_stability_result *r);
/// The theory row of the integrator named `name` (001 §2.6 and the mappings above):
/// returns 1 and fills *t if known, 0 otherwise.
EO_API int eo_stability_theory(const char *name, eo_stability_result *t);
/// 1 if the measured axis matches the theory axis: the same kind and, when bounded,
/// |bound − theory| ≤ tol. A theory kind EO_STAB_NA matches anything.
EO_API int eo_stability_axis_agrees(const eo_stability_axis *measured, const eo_stability_axis *theory, double tol);
/// Both axes.
EO_API int eo_stability_agrees(const eo_stability_result *measured, const eo_stability_result *theory, double tol);
/// "bounded", "none", "unconditional", "n/a".
EO_API const char *eo_stability_kind_name(eo_stability_kind k);

#ifdef __cplusplus
}
#endif
#endif
