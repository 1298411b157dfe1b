/* Exact line search (registry key "exact"): a local minimizer of φ(α) = g(x + αp), α > 0
 * (002 Def. 3).
 *
 * φ(0) = g0, φ'(0) = dg0 < 0, φ'(α) = ∇g(x + αp)ᵀp (each trial is one gradient call).
 * 1. Bracket: trials α₀, 2α₀, 4α₀, … while φ keeps decreasing with φ' < 0. The first
 *    trial where φ is +∞ (outside a barrier's domain) or above the best value so far, or
 *    where φ' ≥ 0, closes the bracket. The bracket [lo, hi] (either order) always has
 *    φ(lo) ≤ φ(0) the best value seen, φ'(lo)·(hi − lo) < 0, and hi either worse than
 *    lo, +∞, or with φ' pointing back to lo, so it holds a local minimizer.
 * 2. Zoom (Brent-style safeguarded interpolation; Nocedal & Wright, Numerical
 *    Optimization, Alg. 3.6 with §3.5's interpolants): the next trial is the secant root
 *    of φ' when φ'(lo) and φ'(hi) differ in sign, else the minimizer of the cubic (or,
 *    without φ'(hi), the quadratic) interpolant, kept 1% of the width inside the
 *    bracket; bisection when hi is +∞, when the interpolant fails, or when the bracket
 *    did not halve in two trials. Every interpolant is exact for quadratic φ, so a
 *    quadratic g is minimized along the line to rounding in one or two trials.
 * Values within 4·ε_mach·|φ(0)| of each other count as equal (then the sign of φ'
 * decides), so the search keeps working where g only changes at rounding level.
 * Converged (EO_OK) when |φ'(lo)| ≤ tol·|φ'(0)| or the bracket is narrower than
 * tol·|α|; returns lo, the best point. Why derivatives and not golden section on values
 * alone: from values only, the minimizer of φ is determined to about √ε_mach ≈ 1.5e-8
 * relative (φ is flat there), which could not reproduce exact-line-search iterates
 * (002 Example 2) to 1e-10; the sign of φ' keeps the bracket correct to rounding.
 * After max_evals trials the best point is returned with EO_WARN_NOT_CONVERGED (x
 * itself, α = 0, if nothing was better). A non-finite φ is never accepted.
 * ∇g at the returned point is handed back through eo_ls_extra (copied when lo moves), so
 * the caller needs no further gradient call. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "trial.h"

/// Exact line search (config `solver.exact.*`).
typedef struct eo_exact_params {
    double tol;          ///< stop when |φ'(α)| ≤ tol·|φ'(0)| or the bracket is narrower
                         ///< than tol·α (1e-8)
    int max_evals;       ///< evaluations before giving up (100)
} eo_exact_params;

static const eo_param_desc exact_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_exact_params, tol), .def.d = 1e-8,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN,
     .help = "stop when |phi'(a)| <= tol*|phi'(0)| or the bracket is narrower than tol*a"},
    {.key = "max_evals", .kind = EO_PARAM_INT, .offset = offsetof(eo_exact_params, max_evals),
     .def.i = 100, .min = 2, .max = 100000, .range = EO_RANGE_CLOSED,
     .help = "objective evaluations before giving up"},
    {0},
};

typedef struct pt {
    double a, f, d;  /* α, φ(α), φ'(α) (NAN if φ not finite) */
} pt;

static int eval(eo_objective *obj, const double *x, const double *p, double a, double *xt,
                double *grad, pt *out, int *nevals)
{
    const int n = obj->n;
    double f;
    eo_ls_point(n, x, p, a, xt);
    int rc = eo_objective_gradient(obj, xt, &f, grad);
    ++*nevals;
    if (rc < 0) return rc;
    out->a = a;
    out->f = isfinite(f) ? f : INFINITY;
    out->d = NAN;
    if (isfinite(f)) {
        double d = 0;
        d = eo_vdot(obj->space, n, grad, p);
        out->d = d;
    }
    return EO_OK;
}

/* Interpolated trial inside (lo, hi), or NAN. */
static double interpolate(const pt *lo, const pt *hi)
{
    double w = hi->a - lo->a;
    if (isfinite(hi->f) && isfinite(hi->d) && lo->d * hi->d < 0)
        return lo->a - lo->d * w / (hi->d - lo->d);
    if (isfinite(hi->f) && isfinite(hi->d)) {
        double d1 = lo->d + hi->d - 3 * (lo->f - hi->f) / (lo->a - hi->a);
        double rad = d1 * d1 - lo->d * hi->d;
        if (!(rad >= 0)) return NAN;
        double d2 = (w > 0 ? 1 : -1) * sqrt(rad);
        double den = hi->d - lo->d + 2 * d2;
        if (den == 0) return NAN;
        return hi->a - w * (hi->d + d2 - d1) / den;
    }
    if (isfinite(hi->f)) {
        double den = 2 * (hi->f - lo->f - lo->d * w);
        if (!(den > 0)) return NAN;
        return lo->a - lo->d * w * w / den;
    }
    return NAN;
}

static int exact_search(const void *params, eo_objective *obj, const double *x, const double *p,
                        double g0, double dg0, double alpha0, double *xnew, double *gnew,
                        double *alpha, int *nevals, double *work, eo_ctx *ctx,
                     eo_ls_extra *extra)
{
    eo_exact_params def;
    const eo_exact_params *ep = params;
    const int n = obj->n;
    (void)ctx;
    if (extra) extra->have_grad = 0;
    if (!ep) {
        eo_params_default(exact_desc, &def);
        ep = &def;
    }
    const double dtol = ep->tol * fabs(dg0);
    const double noise = 4 * DBL_EPSILON * fabs(g0); /* values closer than this tie */
    pt lo = {0, g0, dg0}, hi = {NAN, NAN, NAN}, t;
    int have_hi = 0, converged = 0, rc;
    /* ∇g at lo is kept in extra->grad_new (when given): copied from work when lo moves */
    double *glo = extra ? extra->grad_new : NULL;
#define SET_LO(v)                                                                        \
    do {                                                                                 \
        lo = (v);                                                                        \
        if (glo) memcpy(glo, work, (size_t)n * sizeof(double));                          \
    } while (0)
    double a = eo_ls_first_step(alpha0);
    *nevals = 0;

    /* 1. bracket */
    while (*nevals < ep->max_evals) {
        if ((rc = eval(obj, x, p, a, xnew, work, &t, nevals)) < 0) return rc;
        if (!isfinite(t.f) || t.f > lo.f + noise) {
            hi = t;
            have_hi = 1;
            break;
        }
        if (fabs(t.d) <= dtol) {
            SET_LO(t);
            converged = 1;
            break;
        }
        if (t.d > 0) {
            hi = lo;
            SET_LO(t);
            have_hi = 1;
            break;
        }
        SET_LO(t);
        a *= 2;
        if (!isfinite(a)) break;
    }

    /* 2. zoom */
    double width_ref = have_hi ? fabs(hi.a - lo.a) : 0;
    int slow = 0;
    while (have_hi && !converged && *nevals < ep->max_evals) {
        double w = hi.a - lo.a;
        if (fabs(w) <= ep->tol * fmax(fabs(lo.a), fabs(hi.a))) {
            converged = 1;
            break;
        }
        double c = slow >= 2 ? NAN : interpolate(&lo, &hi);
        if (!isfinite(c)) c = lo.a + 0.5 * w;
        double b1 = lo.a + 0.01 * w, b2 = hi.a - 0.01 * w;
        double bmin = fmin(b1, b2), bmax = fmax(b1, b2);
        if (c < bmin) c = bmin;
        if (c > bmax) c = bmax;
        if ((rc = eval(obj, x, p, c, xnew, work, &t, nevals)) < 0) return rc;
        if (!isfinite(t.f) || t.f > lo.f + noise) {
            hi = t;
        } else {
            if (fabs(t.d) <= dtol) {
                SET_LO(t);
                converged = 1;
                break;
            }
            if (t.d * (hi.a - lo.a) >= 0) hi = lo;
            SET_LO(t);
        }
        double wn = fabs(hi.a - lo.a);
        if (wn > 0.5 * width_ref) {
            slow++;
        } else {
            slow = 0;
            width_ref = wn;
        }
        if (slow > 2) {
            slow = 0;
            width_ref = wn;
        }
    }

    if (!(lo.a > 0)) return eo_ls_give_up(n, x, g0, xnew, gnew, alpha);
    eo_ls_point(n, x, p, lo.a, xnew);
#undef SET_LO
    *gnew = lo.f;
    *alpha = lo.a;
    if (glo) extra->have_grad = 1;
    return converged ? EO_OK : EO_WARN_NOT_CONVERGED;
}

const eo_linesearch_type eo_linesearch_exact = {
    .info = {.name = "exact",
             .summary = "1-D minimization of g(x+ap): bracket, then safeguarded interpolation on g'",
             .params = exact_desc,
             .params_size = sizeof(eo_exact_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .search = exact_search,
};
