/* Barrier-aware line-search filter (registry key "barrier_filter").
 *
 * Zhu, Bridson & Kaufman 2018, "Blended Cured Quasi-Newton for Distortion Optimization"
 * (ACM TOG 37(4), BCQN), §5, after Smith & Schaefer 2015: distortion energies with an
 * element barrier (ψ → ∞ as det F → 0) block a line search that starts at α₀ = 1 beyond
 * the first inverting element, and an Armijo search that only shrinks wastes its trials
 * on +∞ values. The filter starts at the largest step that inverts no element:
 *
 *     α_max = min over elements with det F(x) > 0 of the smallest α > 0 with
 *             det F(x + αp) = 0          (objective op max_step: a cubic in α per tet,
 *                                         problems/step_objective.c, root by bisection
 *                                         on the cubic's monotone pieces)
 *     α₁ = min(α₀, safety·α_max),   then Armijo backtracking from α₁
 *          (solvers/linesearch/backtracking.c, with its rounding-level tests):
 *     g(x + αp) ≤ g(x) + c1·α·∇gᵀp,  α ← shrink·α.
 * Every trial is below safety·α_max < α_max, so no element that is un-inverted at x
 * is inverted by an accepted step, whatever the energy (also for the stable neo-Hookean
 * model, which has no barrier: the filter then keeps the iterates un-inverted). Elements
 * already inverted at x (the `inverted` scene's start) do not limit the step: they may
 * recover.
 * Defaults are those of the authors' released code (github.com/mike323zyf/BCQN,
 * get_feasible_step_size.m, line_check_search.m): safety 0.5, c1 0.2, shrink 0.5.
 * Differences: the paper's "curing" of the direction (a few projected-Jacobi sweeps on
 * an LCP that keeps the linearized per-element volumes c + Jᵀp ≥ 0, lcp_solve) is not
 * done here — a line search gets p as it is; the root is found by bisection on the
 * monotone pieces of the cubic rather than by the complex closed form with a 1e-5
 * imaginary-part tolerance of the authors' code.
 * Objectives without max_step (objective.h): the filter is plain Armijo backtracking
 * with these constants. Usable by every optimizer with a line search (newton, lbfgs,
 * bcqn, ncg, gradient_descent, projective_dynamics). */
#include <math.h>
#include <stddef.h>

#include "elastopt/impl/method.h"
#include "elastopt/impl/params.h"

/// Barrier-aware line-search filter (config `solver.barrier_filter.*`; BCQN §5): the first
/// trial is min(α₀, safety·α_max), α_max the step at which the first un-inverted element
/// inverts (objective op max_step), then Armijo backtracking. The first three fields are
/// laid out as eo_backtracking_params.
typedef struct eo_barrier_filter_params {
    double c1;           ///< Armijo constant (0.2, the authors' code)
    double shrink;       ///< α ← shrink·α after a rejected trial (0.5)
    int max_evals;       ///< trials before giving up (60)
    double safety;       ///< first trial at most safety·α_max, in (0, 1) (0.5, the authors' code)
} eo_barrier_filter_params;

/* The first three fields have the layout of eo_backtracking_params (the search hands
 * them to backtracking). */
static const eo_param_desc bf_desc[] = {
    {.key = "c1", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_barrier_filter_params, c1),
     .def.d = 0.2, .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "Armijo constant: accept g(x+ap) <= g + c1*a*grad'p (BCQN code: 0.2)"},
    {.key = "shrink", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_barrier_filter_params, shrink),
     .def.d = 0.5, .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "step factor after a rejected trial"},
    {.key = "max_evals", .kind = EO_PARAM_INT, .offset = offsetof(eo_barrier_filter_params, max_evals),
     .def.i = 60, .min = 1, .max = 10000, .range = EO_RANGE_CLOSED, .help = "trials before giving up"},
    {.key = "safety", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_barrier_filter_params, safety),
     .def.d = 0.5, .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX_OPEN,
     .help = "first trial at most safety*alpha_max, alpha_max the step at which the first element inverts "
             "(BCQN code: 0.5)"},
    {0},
};

static int bf_search(const void *params, eo_objective *obj, const double *x, const double *p, double g0,
                     double dg0, double alpha0, double *xnew, double *gnew, double *alpha, int *nevals,
                     double *work, eo_ctx *ctx, eo_ls_extra *extra)
{
    eo_barrier_filter_params def;
    const eo_barrier_filter_params *fp = params;
    if (!fp) {
        eo_params_default(bf_desc, &def);
        fp = &def;
    }
    double amax = INFINITY;
    int rc = eo_objective_max_step(obj, x, p, &amax);
    if (rc < 0 && rc != EO_ERR_UNSUPPORTED) return rc;
    if (rc == EO_ERR_UNSUPPORTED || !(amax > 0)) amax = INFINITY; /* no elements: plain backtracking */
    double a0 = alpha0 > 0 && isfinite(alpha0) ? alpha0 : 1;
    if (fp->safety * amax < a0) a0 = fp->safety * amax;
    const eo_backtracking_params bp = {.c1 = fp->c1, .shrink = fp->shrink, .max_evals = fp->max_evals};
    return eo_linesearch_backtracking.search(&bp, obj, x, p, g0, dg0, a0, xnew, gnew, alpha, nevals, work, ctx,
                                             extra);
}

const eo_linesearch_type eo_linesearch_barrier_filter = {
    .info = {.name = "barrier_filter",
             .summary = "BCQN line-search filter: first trial at most safety*alpha_max (no element inverts), then "
                        "Armijo backtracking",
             .params = bf_desc,
             .params_size = sizeof(eo_barrier_filter_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .search = bf_search,
};
