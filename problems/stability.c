/* Dahlquist stability of every registered integrator, measured (stability.h; notes 001
 * §2.6). The mappings of y' = λy onto the (x, v) form and the way implicit integrators
 * are stepped (their own weight/predict/velocity ops, the 1D step problem minimized in
 * closed form) are documented in stability.h.
 *
 * Theory (R(z) the amplification of the scalar equation, z = hλ):
 *   forward_euler      R = 1 + z                      real (−2, 0), imaginary: none
 *   heun, midpoint     R = 1 + z + z²/2               real (−2, 0), |R(iy)|² = 1 + y⁴/4: none
 *   rk4                R = Σ_{k≤4} z^k/k!             real (−2.78529356, 0), imaginary ±2√2
 *   backward_euler     R = 1/(1 − z)                  unconditional (A-stable)
 *   newmark (β = ¼)    R = (1 + z/2)/(1 − z/2)        unconditional (A-stable, |R(iy)| = 1)
 *   symplectic_euler, verlet, leapfrog: on the spring tr M = 2 − (hω)², det M = 1, so
 *                      stable iff hω < 2 (001 §2.6). On the real-axis mapping (v' = λv)
 *                      the velocity sees: symplectic Euler 1 + z (bound −2), velocity
 *                      Verlet 1 + z + z²/2 (−2), leapfrog from a synchronized state
 *                      (1 + z/2)² (−4) — derived for this mapping, not in the notes.
 *   static             no velocity: real n/a; x_{n+1} = 0 on the spring: unconditional.
 *   symplectic_euler_x x first, then v with the old velocity: v' = λv gives 1 + z (−2);
 *                      spring matrix [[1, h], [−hω², 1 − h²ω²]]: hω < 2.
 *   implicit_midpoint  R = (1 + z/2)/(1 − z/2) (θ = ½: stepped in the midpoint, the
 *                      damping force at v_{n+½}): unconditional.
 *   bdf2               A-stable; a single step from (xₙ, vₙ) is its backward Euler start,
 *                      which is what this one-step measurement sees.
 *   generalized_alpha  (default ρ∞) its state is (x, v, a); the one-step map measured
 *                      here is the start from the consistent a₀ = −kx − cv (measured:
 *                      unconditional on both axes; its norm, not its spectral radius,
 *                      grows with hω: the method's velocity overshoot). The method's own
 *                      3×3 amplification matrix has spectral radius → ρ∞ as hω → ∞
 *                      (Chung & Hulbert 1993); no theory row. */
#include <math.h>
#include <string.h>

#include "elastopt/stability.h"

static const double RHO2_TOL = 1e-13;   /* unstable: ρ² > 1 + RHO2_TOL */
static const double S_MAX = 1e4;        /* "unconditional" above this */
static const double S_NONE = 1e-3;      /* a bound below this is "none" */

typedef struct {
    double k, c;
} lin_ode;

static int lin_accel(void *data, double t, const double *x, const double *v, double *a)
{
    (void)t;
    const lin_ode *o = data;
    a[0] = -o->k * x[0] - o->c * v[0];
    return EO_OK;
}

/* One step of `it` from (x, v), h = 1. */
static int one_step(eo_ctx *ctx, const eo_integrator_type *it, double k, double c, double *x, double *v)
{
    const double h = 1;
    if (it->explicit_step) {
        double work[16] = {0};
        if (it->work_vectors > 16)
            return eo_error(ctx, EO_ERR_INVALID, "stability: integrator '%s' needs %d work vectors (> 16)",
                            it->info.name, it->work_vectors);
        lin_ode o = {k, c};
        eo_ode ode = {.n = 1, .data = &o, .accel = lin_accel};
        int rc = it->explicit_step(&ode, 0, h, x, v, work, 1);
        if (rc < 0) return rc;
    } else {
        if (!(it->weight && it->predict && it->velocity) && !it->accel)
            return eo_error(ctx, EO_ERR_INVALID, "stability: integrator '%s' has neither explicit_step nor "
                            "weight/predict/velocity", it->info.name);
        const int acc = it->accel;
        const double xn = *x, vn = *v, an = -k * xn - c * vn; /* accel: the consistent start a₀ */
        const double w = acc ? it->accel_weight(NULL, h) : it->weight(h);
        const double th = acc ? it->accel_theta(NULL) : it->theta > 0 ? it->theta : 1.0;
        double xt, vs[2];
        if (acc) it->accel_predict(NULL, 1, h, &xn, &vn, &an, &xt);
        else it->predict(1, h, &xn, &vn, &xt);
        /* the damping force sees the stage velocity vₙ + θ(vₙ₊₁ − vₙ), affine in the
         * minimizer z (the stage; xₙ₊₁ = xₙ + (z − xₙ)/θ) */
        for (int j = 0; j < 2; j++) {
            double x1 = xn + (j - xn) / th, v1;
            if (acc) it->accel_velocity(NULL, 1, h, &xn, &vn, &an, &x1, &v1, NULL);
            else it->velocity(1, h, &xn, &vn, &x1, &v1);
            vs[j] = vn + th * (v1 - vn);
        }
        const double alpha = vs[1] - vs[0], beta = vs[0], in = it->inertia ? 1.0 : 0.0;
        const double cn = it->force_n ? -k * xn - c * vn : 0.0;
        const double den = in + w * (k + c * alpha);
        if (!(den > 0)) return EO_ERR_NONFINITE; /* g not strictly convex: no step */
        double xs = xn + ((in * xt - w * (c * beta - cn)) / den - xn) / th;
        if (acc) it->accel_velocity(NULL, 1, h, &xn, &vn, &an, &xs, v, NULL);
        else it->velocity(1, h, &xn, &vn, &xs, v);
        *x = xs;
    }
    return isfinite(*x) && isfinite(*v) ? EO_OK : EO_ERR_NONFINITE;
}

int eo_stability_matrix(eo_ctx *ctx, const eo_integrator_type *it, double k, double c, double M[4])
{
    double x = 1, v = 0;
    int rc = one_step(ctx, it, k, c, &x, &v);
    if (rc < 0) return rc;
    M[0] = x, M[2] = v;
    x = 0, v = 1;
    if ((rc = one_step(ctx, it, k, c, &x, &v)) < 0) return rc;
    M[1] = x, M[3] = v;
    return EO_OK;
}

double eo_stability_spectral_radius(const double M[4])
{
    const double tr = M[0] + M[3], det = M[0] * M[3] - M[1] * M[2];
    const double disc = 0.25 * tr * tr - det;
    if (disc < 0) return sqrt(det); /* complex pair: |μ|² = det */
    const double s = sqrt(disc);
    return fmax(fabs(0.5 * tr + s), fabs(0.5 * tr - s));
}

int eo_stability_rho(eo_ctx *ctx, const eo_integrator_type *it, double re, double im, double *rho)
{
    double M[4];
    int rc = eo_stability_matrix(ctx, it, re * re + im * im, -2 * re, M);
    if (rc == EO_ERR_NONFINITE) {
        *rho = INFINITY;
        return EO_OK;
    }
    if (rc < 0) return rc;
    *rho = eo_stability_spectral_radius(M);
    return EO_OK;
}

/* *unstable = 1 if one step of size s on the axis amplifies. */
static int unstable_at(eo_ctx *ctx, const eo_integrator_type *it, int imag, double s, int *unstable)
{
    double M[4];
    int rc = imag ? eo_stability_matrix(ctx, it, s * s, 0, M) : eo_stability_matrix(ctx, it, 0, s, M);
    if (rc == EO_ERR_NONFINITE) {
        *unstable = 1;
        return EO_OK;
    }
    if (rc < 0) return rc;
    double r = imag ? eo_stability_spectral_radius(M) : fabs(M[3]);
    *unstable = !(r * r <= 1 + RHO2_TOL);
    return EO_OK;
}

/* scan: 1e-5, 1e-4, 1e-3, then 0.01 steps to 10, then ×1.05 to S_MAX */
static double next_sample(double s)
{
    if (s < 0.005) return 10 * s;
    if (s < 10 - 1e-9) return 0.01 * (round(s / 0.01) + 1);
    return fmin(1.05 * s, S_MAX);
}

static int measure_axis(eo_ctx *ctx, const eo_integrator_type *it, int imag, eo_stability_axis *ax)
{
    double lo = 0, hi = -1;
    int u, rc;
    for (double s = 1e-5;; s = next_sample(s)) {
        if ((rc = unstable_at(ctx, it, imag, s, &u)) < 0) return rc;
        if (u) {
            hi = s;
            break;
        }
        lo = s;
        if (s >= S_MAX) break;
    }
    if (hi < 0) {
        ax->kind = EO_STAB_UNCONDITIONAL;
        ax->bound = INFINITY;
        return EO_OK;
    }
    for (int b = 0; b < 60; b++) {
        double mid = 0.5 * (lo + hi);
        if ((rc = unstable_at(ctx, it, imag, mid, &u)) < 0) return rc;
        if (u) hi = mid;
        else lo = mid;
    }
    double bound = 0.5 * (lo + hi);
    ax->kind = bound < S_NONE ? EO_STAB_NONE : EO_STAB_BOUNDED;
    ax->bound = imag ? bound : -bound;
    return EO_OK;
}

int eo_stability_measure(eo_ctx *ctx, const eo_integrator_type *it, eo_stability_result *r)
{
    memset(r, 0, sizeof *r);
    eo_stability_result t;
    r->first_order_form = eo_stability_theory(it->info.name, &t) ? t.first_order_form : 0;
    int rc;
    if (it->inertia) {
        if ((rc = measure_axis(ctx, it, 0, &r->real)) < 0) return rc;
    } else {
        r->real.kind = EO_STAB_NA;
        r->real.bound = NAN;
    }
    return measure_axis(ctx, it, 1, &r->imag);
}

typedef struct {
    const char *name;
    eo_stability_result t;
} theory_row;

#define BND(b) {EO_STAB_BOUNDED, (b)}
#define NONE {EO_STAB_NONE, 0}
#define UNC {EO_STAB_UNCONDITIONAL, INFINITY}
#define NA {EO_STAB_NA, NAN}
static const theory_row theory[] = {
    {"forward_euler", {BND(-2), NONE, 1}},
    {"heun", {BND(-2), NONE, 1}},
    {"midpoint", {BND(-2), NONE, 1}},
    {"rk4", {BND(-2.785293563405282), BND(2.828427124746190), 1}},
    {"symplectic_euler", {BND(-2), BND(2), 0}},
    {"verlet", {BND(-2), BND(2), 0}},
    {"leapfrog", {BND(-4), BND(2), 0}},
    {"backward_euler", {UNC, UNC, 1}},
    {"newmark", {UNC, UNC, 1}},
    {"static", {NA, UNC, 0}},
    {"symplectic_euler_x", {BND(-2), BND(2), 0}},
    {"implicit_midpoint", {UNC, UNC, 1}},
    {"bdf2", {UNC, UNC, 0}}, /* A-stable; one step from a state is its backward Euler start */
};

int eo_stability_theory(const char *name, eo_stability_result *t)
{
    for (size_t i = 0; i < sizeof theory / sizeof theory[0]; i++)
        if (strcmp(theory[i].name, name) == 0) {
            *t = theory[i].t;
            return 1;
        }
    return 0;
}

int eo_stability_axis_agrees(const eo_stability_axis *m, const eo_stability_axis *t, double tol)
{
    if (t->kind == EO_STAB_NA) return 1;
    if (m->kind != t->kind) return 0;
    return t->kind != EO_STAB_BOUNDED || fabs(m->bound - t->bound) <= tol;
}

int eo_stability_agrees(const eo_stability_result *m, const eo_stability_result *t, double tol)
{
    return eo_stability_axis_agrees(&m->real, &t->real, tol) && eo_stability_axis_agrees(&m->imag, &t->imag, tol);
}

const char *eo_stability_kind_name(eo_stability_kind k)
{
    switch (k) {
    case EO_STAB_BOUNDED: return "bounded";
    case EO_STAB_NONE: return "none";
    case EO_STAB_UNCONDITIONAL: return "unconditional";
    default: return "n/a";
    }
}
