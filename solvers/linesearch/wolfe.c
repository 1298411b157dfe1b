/* Strong Wolfe line search with bracketing and zoom (registry key "wolfe").
 *
 * φ(α) = g(x + αp), φ(0) = g0, φ'(0) = ∇gᵀp = dg0 < 0; every trial is ONE value+gradient
 * call, and the gradient of the accepted trial is handed back (eo_ls_extra), so the
 * optimizer pays no extra evaluation after acceptance. A step α is accepted when
 *   (W1) φ(α) ≤ φ(0) + c1·α·φ'(0)                   sufficient decrease, and
 *   (W2) |φ'(α)| ≤ c2·|φ'(0)|                        strong curvature condition,
 * or, where g no longer changes measurably (φ(α) within ε_g = noise·ε_mach·|φ(0)| of
 * φ(0)), by the approximate Wolfe conditions of Hager & Zhang ("A new conjugate gradient
 * method with guaranteed descent and an efficient line search", SIAM J. Optim. 16, 2005,
 * eq. (4.1)):
 *   (AW) φ(α) ≤ φ(0) + ε_g  and  (2c1 − 1)·φ'(0) ≥ φ'(α)  and (W2),
 * the derivative form of (W1) for a quadratic φ, which stays accurate to rounding of ∇g
 * where comparing values of g would compare rounding noise. Values that differ by less
 * than ε_g count as equal everywhere below; then the sign of φ' decides.
 *
 * Algorithm (Nocedal & Wright, Numerical Optimization, 2nd ed., Alg. 3.5 and 3.6, with
 * the safeguarded cubic steps of Moré & Thuente, "Line search algorithms with guaranteed
 * sufficient decrease", ACM TOMS 20, 1994):
 * 1. Bracket from α₁ = α₀: at trial αᵢ
 *      φ(αᵢ) not finite, or (W1)/(AW) fails, or φ(αᵢ) > φ(αᵢ₋₁) + ε_g  → zoom(αᵢ₋₁, αᵢ)
 *      (W2) holds                                                     → accept αᵢ
 *      φ'(αᵢ) ≥ 0                                                     → zoom(αᵢ, αᵢ₋₁)
 *      else extrapolate: αᵢ₊₁ = minimizer of the cubic through (αᵢ₋₁, αᵢ) kept in
 *      [1.1αᵢ, 4αᵢ] (4αᵢ when the cubic has no minimizer beyond αᵢ).
 * 2. zoom(lo, hi): lo is the best point so far satisfying (W1)/(AW) and
 *    φ'(lo)·(hi − lo) < 0, so [lo, hi] (either order) contains points satisfying the
 *    strong Wolfe conditions (N&W Lemma 3.1). Trial: minimizer of the cubic through
 *    (lo, φ, φ') and (hi, φ, φ') (N&W eq. 3.59), or of the quadratic through φ(lo),
 *    φ'(lo), φ(hi) when φ'(hi) is unknown, kept at least 10% of the width inside the
 *    bracket; bisection when hi is not finite, when the interpolant fails, or when the
 *    bracket did not shrink to 2/3 in two trials (Moré–Thuente's safeguard). A trial
 *    that fails (W1)/(AW) or is worse than lo becomes hi; else it is accepted if (W2)
 *    holds, or becomes lo (the old lo becoming hi if φ' changed sign).
 * After max_evals trials, or when the bracket is narrower than 10·ε_mach·α, the best
 * point lo is returned with EO_WARN_NOT_CONVERGED (x itself, α = 0, if none is better
 * than x); its gradient is handed back only if lo was the last trial.
 *
 * c2: 0.9 for quasi-Newton (L-BFGS: the unit step is usually accepted at once), 0.1 for
 * nonlinear CG (needs a near-exact line search for conjugacy, N&W §5.2). The parameter
 * c2 = 0 (default) means "the optimizer's preference" (eo_ls_extra.c2; 0.9 if none). */
#include "elastopt/impl/params.h"
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "trial.h"

static const eo_param_desc wolfe_desc[] = {
    {.key = "c1", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_wolfe_params, c1), .def.d = 1e-4,
     .min = 0, .max = 0.5, .range = EO_RANGE_OPEN,
     .help = "sufficient decrease: g(x+ap) <= g + c1*a*grad'p"},
    {.key = "c2", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_wolfe_params, c2), .def.d = 0,
     .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "curvature: |grad(x+ap)'p| <= c2*|grad'p| (c1 <= c2 < 1, raised to c1); 0 = optimizer's choice "
             "(lbfgs 0.9, ncg 0.1), else 0.9"},
    {.key = "max_evals", .kind = EO_PARAM_INT, .offset = offsetof(eo_wolfe_params, max_evals),
     .def.i = 40, .min = 1, .max = 10000, .range = EO_RANGE_CLOSED,
     .help = "trials (one value+gradient each) before giving up"},
    {.key = "noise", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_wolfe_params, noise), .def.d = 1e-10,
     .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "relative resolution of g: values within noise*|g| are equal and the approximate "
             "Wolfe test on g' decides"},
    {0},
};

typedef struct pt {
    double a, f, d; /* α, φ(α) (+∞ if not finite), φ'(α) (NAN if φ not finite) */
} pt;

/* One trial: xt = x + a·p, g and ∇g (into grad). */
static int eval(eo_objective *obj, const double *x, const double *p, double a, double *xt,
                double *grad, pt *out, int *nevals)
{
    const int n = obj->n;
    double f;
    eo_ls_point(n, x, p, a, xt);
    ++*nevals;
    int rc = eo_objective_gradient(obj, xt, &f, grad);
    if (rc < 0) return rc;
    out->a = a;
    out->f = isfinite(f) ? f : INFINITY;
    out->d = NAN;
    if (isfinite(f)) {
        double d = 0;
        d = eo_vdot(obj->space, n, grad, p);
        out->d = isfinite(d) ? d : NAN;
        if (!isfinite(d)) out->f = INFINITY;
    }
    return EO_OK;
}

/* Minimizer of the cubic through (a, fa, da), (b, fb, db) (N&W eq. 3.59); NAN if none. */
static double cubic_min(const pt *u, const pt *v)
{
    double d1 = u->d + v->d - 3 * (u->f - v->f) / (u->a - v->a);
    double rad = d1 * d1 - u->d * v->d;
    if (!(rad >= 0)) return NAN;
    double d2 = (v->a > u->a ? 1 : -1) * sqrt(rad);
    double den = v->d - u->d + 2 * d2;
    if (!(fabs(den) > 0)) return NAN;
    double c = v->a - (v->a - u->a) * (v->d + d2 - d1) / den;
    return isfinite(c) ? c : NAN;
}

/* Minimizer of the quadratic through φ(lo), φ'(lo), φ(hi); NAN if not convex. */
static double quad_min(const pt *lo, const pt *hi)
{
    double w = hi->a - lo->a;
    double den = 2 * (hi->f - lo->f - lo->d * w);
    if (!(den > 0)) return NAN;
    double c = lo->a - lo->d * w * w / den;
    return isfinite(c) ? c : NAN;
}

static int wolfe_search(const void *params, eo_objective *obj, const double *x, const double *p,
                        double g0, double dg0, double alpha0, double *xnew, double *gnew,
                        double *alpha, int *nevals, double *work, eo_ctx *ctx, eo_ls_extra *extra)
{
    eo_wolfe_params def;
    const eo_wolfe_params *wp = params;
    const int n = obj->n;
    (void)ctx;
    if (!wp) {
        eo_params_default(wolfe_desc, &def);
        wp = &def;
    }
    const double c1 = wp->c1;
    double c2 = wp->c2 > 0 ? wp->c2 : (extra && extra->c2 > 0 && extra->c2 < 1 ? extra->c2 : 0.9);
    if (c2 < c1) c2 = c1; /* c1 ≤ c2 (Moré–Thuente allow equality) */
    const double eps_g = wp->noise * fabs(g0);
    const double curv = c2 * fabs(dg0), aw_hi = (2 * c1 - 1) * dg0;
    /* the gradient of each trial goes where the caller wants the accepted one */
    double *gt = extra && extra->grad_new ? extra->grad_new : work;
    if (extra) extra->have_grad = 0;
    *nevals = 0;

    /* (W1) where φ(α) differs measurably from φ(0), else (AW) */
#define SUFFICIENT(t)                                                                   \
    (isfinite((t).f) && ((t).f < g0 - eps_g ? (t).f <= g0 + c1 * (t).a * dg0             \
                                            : (t).f <= g0 + eps_g && (t).d <= aw_hi))
#define ACCEPT(t)                                                                       \
    do {                                                                                \
        *gnew = (t).f;                                                                  \
        *alpha = (t).a;                                                                 \
        if (extra && extra->grad_new) extra->have_grad = 1;                             \
        return EO_OK;                                                                   \
    } while (0)

    pt prev = {0, g0, dg0}, lo, hi, t;
    int rc, last_is_lo = 0, zoom = 0;
    double a = eo_ls_first_step(alpha0);

    /* 1. bracket */
    for (;;) {
        if (*nevals >= wp->max_evals) {
            lo = prev;
            last_is_lo = prev.a > 0;
            goto give_up;
        }
        if ((rc = eval(obj, x, p, a, xnew, gt, &t, nevals)) < 0) return rc;
        if (!SUFFICIENT(t) || t.f > prev.f + eps_g) {
            lo = prev;
            hi = t;
            last_is_lo = 0;
            zoom = 1;
            break;
        }
        if (fabs(t.d) <= curv) ACCEPT(t);
        if (t.d >= 0) {
            lo = t;
            hi = prev;
            last_is_lo = 1;
            zoom = 1;
            break;
        }
        /* still descending: extrapolate */
        double c = cubic_min(&prev, &t);
        double amin = t.a + 1.1 * (t.a - prev.a), amax = t.a + 4 * (t.a - prev.a);
        if (!(c >= amin && c <= amax)) c = amax;
        prev = t;
        a = c;
        if (!isfinite(a)) {
            lo = prev;
            last_is_lo = 1;
            goto give_up;
        }
    }

    /* 2. zoom */
    if (zoom) {
        double w_ref = fabs(hi.a - lo.a);
        int slow = 0;
        while (*nevals < wp->max_evals) {
            double w = hi.a - lo.a;
            if (fabs(w) <= 10 * DBL_EPSILON * fmax(fabs(lo.a), fabs(hi.a))) break;
            double c = NAN;
            if (slow < 2 && isfinite(hi.f)) {
                if (isfinite(hi.d) && lo.d * hi.d < 0 && fabs(hi.f - lo.f) <= eps_g)
                    c = lo.a - lo.d * w / (hi.d - lo.d); /* values tie: secant on φ' */
                else
                    c = isfinite(hi.d) ? cubic_min(&lo, &hi) : quad_min(&lo, &hi);
            }
            double b1 = lo.a + 0.1 * w, b2 = hi.a - 0.1 * w;
            double bmin = fmin(b1, b2), bmax = fmax(b1, b2);
            if (!isfinite(c)) c = lo.a + 0.5 * w;
            if (c < bmin) c = bmin;
            if (c > bmax) c = bmax;
            if ((rc = eval(obj, x, p, c, xnew, gt, &t, nevals)) < 0) return rc;
            if (!SUFFICIENT(t) || t.f > lo.f + eps_g) {
                hi = t;
                last_is_lo = 0;
            } else if (fabs(t.d) <= curv) {
                ACCEPT(t);
            } else if (t.f < lo.f - eps_g) { /* measurably better: N&W's update */
                if (t.d * (hi.a - lo.a) >= 0) hi = lo;
                lo = t;
                last_is_lo = 1;
            } else if (t.d * (hi.a - lo.a) < 0) { /* tie: the sign of φ' keeps the bracket */
                lo = t;
                last_is_lo = 1;
            } else {
                hi = t;
                last_is_lo = 0;
            }
            double wn = fabs(hi.a - lo.a);
            if (wn > (2.0 / 3.0) * w_ref) {
                slow++;
            } else {
                slow = 0;
                w_ref = wn;
            }
            if (slow > 2) { /* the bisection did its job: interpolate again */
                slow = 0;
                w_ref = wn;
            }
        }
    }

give_up:
#undef SUFFICIENT
#undef ACCEPT
    if (!(lo.a > 0)) return eo_ls_give_up(n, x, g0, xnew, gnew, alpha);
    eo_ls_point(n, x, p, lo.a, xnew);
    *gnew = lo.f;
    *alpha = lo.a;
    if (extra && extra->grad_new && last_is_lo) extra->have_grad = 1;
    return EO_WARN_NOT_CONVERGED;
}

const eo_linesearch_type eo_linesearch_wolfe = {
    .info = {.name = "wolfe",
             .summary = "strong Wolfe (bracket + safeguarded cubic zoom, approximate Wolfe at "
                        "rounding level); returns the gradient of the accepted point",
             .params = wolfe_desc,
             .params_size = sizeof(eo_wolfe_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .search = wolfe_search,
};
