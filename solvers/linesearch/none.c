/* No line search (registry key "none"): take the optimizer's first trial step.
 *
 * α = α₀ (1 for newton and lbfgs, the Barzilai–Borwein step for gradient_descent),
 * accepted whatever g does there, unless g(x + αp) is not finite: then α is halved until
 * it is (at most 60 halvings; then x itself is returned with EO_WARN_NOT_CONVERGED).
 * Pure Newton steps: converges quadratically near a minimizer, may diverge far from it.
 * No parameters. */
#include <math.h>

#include "trial.h"

static int none_search(const void *params, eo_objective *obj, const double *x, const double *p,
                       double g0, double dg0, double alpha0, double *xnew, double *gnew,
                       double *alpha, int *nevals, double *work, eo_ctx *ctx,
                     eo_ls_extra *extra)
{
    (void)params, (void)dg0, (void)work, (void)ctx;
    if (extra) extra->have_grad = 0; /* values only */
    double a = eo_ls_first_step(alpha0);
    double *g1 = eo_ls_first_grad(extra);
    *nevals = 0;
    for (int k = 0; k <= 60; k++) {
        double f;
        int rc = eo_ls_eval(obj, x, p, a, xnew, &f, nevals, k == 0 ? g1 : NULL);
        if (rc < 0) return rc;
        if (isfinite(f)) {
            if (k == 0 && g1) extra->have_grad = 1;
            *gnew = f;
            *alpha = a;
            return EO_OK;
        }
        a *= 0.5;
    }
    return eo_ls_give_up(obj->n, x, g0, xnew, gnew, alpha);
}

const eo_linesearch_type eo_linesearch_none = {
    .info = {.name = "none",
             .summary = "full step a = a0, halved only where g is not finite",
             .params = NULL,
             .params_size = 0,
             .flags = EO_METHOD_DISTRIBUTED},
    .search = none_search,
};
