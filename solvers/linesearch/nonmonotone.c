/* Non-monotone backtracking line search (registry key "nonmonotone").
 *
 * φ(α) = g(x + αp), φ'(0) = ∇gᵀp = dg0 < 0. Trials α = α₀, shrink·α₀, … until
 *     φ(α) ≤ R_k + c1·α·φ'(0)
 * with a reference value R_k ≥ g(x_k) built from the values of the earlier iterates of
 * this minimization (eo_ls_extra.g_hist, kept by the descent loop), so that g may rise
 * for a while as long as it falls on average:
 *
 *   reference = "max" (Grippo, Lampariello & Lucidi 1986, "A nonmonotone line search
 *               technique for Newton's method", SIAM J. Numer. Anal. 23):
 *                   R_k = max_{0 ≤ j ≤ m(k)} g(x_{k−j}),   m(k) = min(k, memory)
 *   reference = "average" (Zhang & Hager 2004, "A nonmonotone line search technique and
 *               its application to unconstrained optimization", SIAM J. Optim. 14):
 *                   C_0 = g(x_0), Q_0 = 1,
 *                   Q_{j+1} = η Q_j + 1,  C_{j+1} = (η Q_j C_j + g(x_{j+1})) / Q_{j+1},
 *               R_k = C_k: a weighted average of all earlier values with weights ∝ η^{k−j}
 *               (η = 0 is Armijo, η = 1 the plain mean). The history holds the last
 *               EO_LS_HISTORY = 64 values; beyond 64 iterations the recursion restarts
 *               at the oldest one kept (the lost weight is η^64 = 3e-5 for η = 0.85).
 * At k = 0 both are Armijo (R_0 = g(x_0)): a first step that raises g is rejected as by
 * `backtracking`. Without a history (extra NULL) the search is Armijo backtracking.
 * At rounding level (α|φ'(0)| ≤ 100·ε_g, ε_g = 4·ε_mach·|g(x_k)|) φ(α) ≤ g(x_k) + ε_g
 * is also accepted, as in backtracking. A non-finite trial is rejected; after
 * max_evals rejected trials the search returns x itself (α = 0, EO_WARN_NOT_CONVERGED).
 * Values only, except the first trial when the caller asks for its gradient
 * (extra->grad_first, as backtracking). */
#include "elastopt/impl/params.h"
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "trial.h"

static const char *const references[] = {"max", "average", NULL};

static const eo_param_desc nm_desc[] = {
    {.key = "c1", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_nonmonotone_params, c1), .def.d = 1e-4,
     .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "sufficient decrease constant: accept g(x+ap) <= R + c1*a*grad'p"},
    {.key = "shrink", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_nonmonotone_params, shrink), .def.d = 0.5,
     .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "step factor after a rejected trial"},
    {.key = "max_evals", .kind = EO_PARAM_INT, .offset = offsetof(eo_nonmonotone_params, max_evals), .def.i = 60,
     .min = 1, .max = 10000, .range = EO_RANGE_CLOSED, .help = "trials before giving up"},
    {.key = "reference", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_nonmonotone_params, reference),
     .size = sizeof(((eo_nonmonotone_params *)0)->reference), .def.s = "max", .choices = references,
     .help = "R = max of the last memory+1 values (Grippo-Lampariello-Lucidi) or average = Zhang-Hager's "
             "weighted mean C_k"},
    {.key = "memory", .kind = EO_PARAM_INT, .offset = offsetof(eo_nonmonotone_params, memory), .def.i = 10,
     .min = 0, .max = 63, .range = EO_RANGE_CLOSED, .help = "max: earlier values M in the maximum (0 = Armijo)"},
    {.key = "eta", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_nonmonotone_params, eta), .def.d = 0.85,
     .min = 0, .max = 1, .range = EO_RANGE_CLOSED, .help = "average: weight eta of Zhang-Hager's C_k (0 = Armijo)"},
    {0},
};

/* R_k from the history h[0..n−1] (oldest first, h[n−1] = g(x_k)). */
static double reference(const eo_nonmonotone_params *p, const double *h, int n, double g0)
{
    if (!h || n <= 0) return g0;
    double R;
    if (!strcmp(p->reference, "average")) {
        double C = h[0], Q = 1;
        for (int j = 1; j < n; j++) {
            double Qn = p->eta * Q + 1;
            C = (p->eta * Q * C + h[j]) / Qn;
            Q = Qn;
        }
        R = C;
    } else {
        int m = p->memory + 1 < n ? p->memory + 1 : n;
        R = h[n - 1];
        for (int j = n - m; j < n; j++) R = h[j] > R ? h[j] : R;
    }
    return isfinite(R) && R > g0 ? R : g0;
}

static int nm_search(const void *params, eo_objective *obj, const double *x, const double *p, double g0,
                     double dg0, double alpha0, double *xnew, double *gnew, double *alpha, int *nevals,
                     double *work, eo_ctx *ctx, eo_ls_extra *extra)
{
    eo_nonmonotone_params def;
    const eo_nonmonotone_params *np = params;
    (void)work, (void)ctx;
    if (!np) {
        eo_params_default(nm_desc, &def);
        np = &def;
    }
    const double R = extra ? reference(np, extra->g_hist, extra->n_hist, g0) : g0;
    if (extra) extra->have_grad = 0;
    double a = eo_ls_first_step(alpha0);
    const double noise = 4 * DBL_EPSILON * fabs(g0);
    double *g1 = eo_ls_first_grad(extra);
    *nevals = 0;
    for (int k = 0; k < np->max_evals; k++) {
        double f;
        int rc = eo_ls_eval(obj, x, p, a, xnew, &f, nevals, k == 0 ? g1 : NULL);
        if (rc < 0) return rc;
        if (isfinite(f) && (f <= R + np->c1 * a * dg0 || (-a * dg0 <= 100 * noise && f <= g0 + noise))) {
            if (k == 0 && g1) extra->have_grad = 1;
            *gnew = f;
            *alpha = a;
            return EO_OK;
        }
        a *= np->shrink;
    }
    return eo_ls_give_up(obj->n, x, g0, xnew, gnew, alpha);
}

const eo_linesearch_type eo_linesearch_nonmonotone = {
    .info = {.name = "nonmonotone",
             .summary = "non-monotone Armijo backtracking: g(x+ap) <= R + c1*a*grad'p, R = max of recent values (GLL) "
                        "or Zhang-Hager average",
             .params = nm_desc,
             .params_size = sizeof(eo_nonmonotone_params),
             .flags = EO_METHOD_DISTRIBUTED},
    .search = nm_search,
};
