/* Generalized-α method (J. Chung and G. M. Hulbert, "A time integration algorithm for
 * structural dynamics with improved numerical dissipation: the generalized-α method",
 * J. Appl. Mech. 60(2):371–375, 1993) for M ẍ = −∇E(x) (E: elastic energy, springs,
 * contact, gravity potential), with the internal force evaluated at the blended point
 * as in the nonlinear analyses of S. Erlicher, L. Bonaventura and O. S. Bursi, "The
 * analysis of the generalized-α method for non-linear dynamic problems", Comput. Mech.
 * 28:83–104, 2002. With the algorithmic acceleration aₙ carried as state:
 *
 *     M a_{n+1−α_m} + ∇E(x_{n+1−α_f}) = 0,
 *     a_{n+1−α_m} = (1 − α_m) aₙ₊₁ + α_m aₙ,   x_{n+1−α_f} = (1 − α_f) xₙ₊₁ + α_f xₙ,
 *     xₙ₊₁ = xₙ + h vₙ + h²((½ − β) aₙ + β aₙ₊₁),
 *     vₙ₊₁ = vₙ + h((1 − γ) aₙ + γ aₙ₊₁),
 *
 * parameterized by the spectral radius at infinite frequency ρ∞ ∈ [0, 1] (the paper's
 * optimal choice: second order, maximal high-frequency dissipation for a given ρ∞):
 *
 *     α_m = (2ρ∞ − 1)/(ρ∞ + 1),  α_f = ρ∞/(ρ∞ + 1),  γ = ½ − α_m + α_f,
 *     β = ¼(1 − α_m + α_f)².
 *
 * As a minimization. Solve the Newmark update for aₙ₊₁ = (xₙ₊₁ − xₙ − h vₙ)/(βh²)
 * − (½ − β)/β · aₙ and write the residual in the stage z = x_{n+1−α_f}, θ = 1 − α_f
 * (xₙ₊₁ − xₙ = (z − xₙ)/θ); multiplying it by θβh²/(1 − α_m) gives
 *
 *     M(z − z̃) + w ∇E(z) = 0,   w = (1 − α_f) β h² / (1 − α_m),
 *     z̃ = xₙ + (1 − α_f)(h vₙ + h² c aₙ),   c = (½ − β) − β α_m/(1 − α_m),
 *
 * the stationarity condition of
 *
 *     z = argmin g(z) = ½‖z − z̃‖²_M + w E(z),
 *
 * convex wherever E is, so the step is the same kind of problem as Newmark's. (In
 * xₙ₊₁ it is min ½‖x − x̃‖²_M + βh²/((1 − α_m)(1 − α_f)) · E((1 − α_f)x + α_f xₙ),
 * x̃ = xₙ + h vₙ + h² c aₙ: the gradient of E at the blended point is the gradient in
 * xₙ₊₁ of E(x_{n+1−α_f})/(1 − α_f).) The engine minimizes in z (θ = 1 − α_f, the
 * prescribed coordinates at xₙ + θ(p(tₙ₊₁) − xₙ)), then xₙ₊₁ = xₙ + (z − xₙ)/θ and the
 * update above gives aₙ₊₁ and vₙ₊₁. A damping term −C v is evaluated at the stage
 * velocity v_{n+1−α_f}, as C–H do. The start (no aₙ: first step, after a reset, a
 * set_state or a rejected step) uses the consistent a₀ = M⁻¹(−∇E(x₀) − C v₀).
 *
 * Properties (linear analysis of C–H): second order for every ρ∞ (γ = ½ − α_m + α_f),
 * unconditionally stable, high-frequency dissipation maximal for the given low-frequency
 * one: the amplification matrix tends to spectral radius ρ∞ as hω → ∞ and to 1 as
 * hω → 0. ρ∞ = 1 (α_m = α_f = ½, β = ¼, γ = ½) is no dissipation: then w = h²/4,
 * z̃ = xₙ + (h/2)vₙ and vₙ₊₁ = 2(xₙ₊₁ − xₙ)/h − vₙ (the aₙ terms cancel), exactly the
 * implicit midpoint rule (implicit_midpoint.c), which conserves quadratic energies.
 * ρ∞ = 0 annihilates the highest frequencies in one step (asymptotic annihilation).
 * For nonlinear E the energy is not guaranteed to decay (Erlicher et al. 2002 show
 * the method is not unconditionally energy-stable there), but ρ∞ < 1 damps the
 * unresolved high frequencies whose growth makes Newmark's trapezoidal rule blow up on
 * stiff scenes. */
#include <stddef.h>

#include "elastopt/params.h"
#include "elastopt/step.h"

typedef struct ga_params {
    double rho_inf; /* spectral radius at infinite frequency, [0, 1]; default 0.8 */
} ga_params;

static const eo_param_desc ga_params_desc[] = {
    {.key = "rho_inf", .kind = EO_PARAM_DOUBLE, .offset = offsetof(ga_params, rho_inf), .def.d = 0.8, .min = 0,
     .max = 1, .range = EO_RANGE_CLOSED,
     .help = "spectral radius at infinite frequency rho_inf (Chung-Hulbert): 1 = no numerical dissipation (the "
             "implicit midpoint rule), smaller damps the high frequencies more (0 = removes them in one step); "
             "second order for every value"},
    {0},
};

typedef struct ga_coef {
    double am, af, beta, gamma;
} ga_coef;

static ga_coef coef(const void *params)
{
    const double r = params ? ((const ga_params *)params)->rho_inf : 0.8;
    ga_coef c;
    c.am = (2.0 * r - 1.0) / (r + 1.0);
    c.af = r / (r + 1.0);
    c.gamma = 0.5 - c.am + c.af;
    c.beta = 0.25 * (1.0 - c.am + c.af) * (1.0 - c.am + c.af);
    return c;
}

static double theta(const void *params) { return 1.0 - coef(params).af; }

static double weight(const void *params, double h)
{
    const ga_coef c = coef(params);
    return (1.0 - c.af) * c.beta * h * h / (1.0 - c.am);
}

static void predict(const void *params, int n, double h, const double *xn, const double *vn, const double *an,
                    double *zt)
{
    const ga_coef c = coef(params);
    const double th = 1.0 - c.af, ca = (0.5 - c.beta) - c.beta * c.am / (1.0 - c.am);
    for (int i = 0; i < n; i++) zt[i] = xn[i] + th * (h * vn[i] + h * h * ca * an[i]);
}

static void velocity(const void *params, int n, double h, const double *xn, const double *vn, const double *an,
                     const double *x, double *v, double *a)
{
    const ga_coef c = coef(params);
    const double ib = 1.0 / (c.beta * h * h), ka = (0.5 - c.beta) / c.beta;
    for (int i = 0; i < n; i++) {
        const double a1 = (x[i] - xn[i] - h * vn[i]) * ib - ka * an[i];
        v[i] = vn[i] + h * ((1.0 - c.gamma) * an[i] + c.gamma * a1);
        if (a) a[i] = a1;
    }
}

static int is_dissipative(const void *params) { return (params ? ((const ga_params *)params)->rho_inf : 0.8) < 1; }

const eo_integrator_type eo_integrator_generalized_alpha = {
    .info = {.name = "generalized_alpha",
             .summary = "implicit generalized-alpha (Chung-Hulbert, rho_inf): second order, tunable "
                        "high-frequency dissipation; rho_inf = 1 is the implicit midpoint rule",
             .params = ga_params_desc,
             .params_size = sizeof(ga_params)},
    .inertia = 1,
    .force_n = 0,
    .is_dissipative = is_dissipative,
    .accel = 1,
    .accel_weight = weight,
    .accel_theta = theta,
    .accel_predict = predict,
    .accel_velocity = velocity,
};
