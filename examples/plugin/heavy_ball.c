/* heavy_ball: Polyak's heavy-ball momentum method as an elastopt plug-in (an example of a
 * method brought from outside the tree; built against the INSTALLED library only).
 *
 * Method (B. T. Polyak, "Some methods of speeding up the convergence of iteration
 * methods", USSR Comput. Math. Math. Phys. 4(5), 1964), with the metric D of the
 * objective (the lumped mass of a step problem; identity if it has none):
 *     x_{k+1} = x_k − a_k D⁻¹∇g(x_k) + β (x_k − x_{k−1}),
 * implemented as a line search from the Barzilai–Borwein step a = sᵀDs/sᵀy (s, y the last
 * changes of x and ∇g; a = min(1, 1/‖D⁻¹∇g‖_∞) at the start, 2α_{k−1} when sᵀy ≤ 0)
 * along v = −D⁻¹∇g + (β/a)s_{k−1}, s_{k−1} = x_k − x_{k−1}: a·v is Polyak's step with
 * step size a. The momentum is dropped (v = −D⁻¹∇g, a restart) when the last step went
 * uphill in the new gradient (∇g_kᵀs_{k−1} ≥ 0: the gradient restart of O'Donoghue &
 * Candès, "Adaptive restart for accelerated gradient schemes", 2015) or when v is not a
 * descent direction. Stopping: the configured rule (solver.stop, solver.tol), the iteration
 * cap and the time budget, as for the built-in optimizers.
 *
 * Build and use (see examples/plugin/README.md):
 *   cc -shared -fPIC heavy_ball.c $(pkg-config --cflags --libs elastopt) -o heavy_ball.so
 *   elastopt --plugin ./heavy_ball.so run --scene cantilever -o solver.optimizer=heavy_ball \
 *       -o solver.stop=gradient -o solver.tol=1e-6 -o solver.heavy_ball.beta=0.8
 * Parameters: solver.heavy_ball.beta (momentum, 0.3), solver.heavy_ball.scaled (use the
 * metric, true). */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include <elastopt/plugin.h>
#include <elastopt/impl/method.h> /* the method-author interface */

typedef struct hb_params {
    double beta; /* momentum factor in [0, 1) */
    int scaled;  /* D = objective metric (lumped mass) */
} hb_params;

static const eo_param_desc hb_desc[] = {
    {.key = "beta", .kind = EO_PARAM_DOUBLE, .offset = offsetof(hb_params, beta), .def.d = 0.3, .min = 0,
     .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN, .help = "momentum factor beta in [0, 1) (0.3: best of 0.3, 0.5, 0.8 on the cantilever)"},
    {.key = "scaled", .kind = EO_PARAM_BOOL, .offset = offsetof(hb_params, scaled), .def.i = 1,
     .help = "scale the gradient by the objective's diagonal metric (lumped mass)"},
    {0},
};

typedef struct hb_state {
    int n;
    double *mem; /* one block: dinv, v, grad, grad_new, x_new, work */
    double *dinv, *v, *grad, *grad_new, *x_new, *work;
} hb_state;

static int hb_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    hb_state *st = vst;
    (void)params;
    eo_free(ctx, st->mem);
    memset(st, 0, sizeof *st);
    size_t nn = (size_t)(n > 0 ? n : 1);
    st->mem = eo_calloc(ctx, 6 * nn, sizeof(double));
    if (!st->mem) return eo_error(ctx, EO_ERR_NOMEM, "heavy_ball: out of memory (n = %d)", n);
    st->n = n;
    st->dinv = st->mem;
    st->v = st->dinv + nn;
    st->grad = st->v + nn;
    st->grad_new = st->grad + nn;
    st->x_new = st->grad_new + nn;
    st->work = st->x_new + nn;
    return EO_OK;
}

static void hb_destroy(void *vst, eo_ctx *ctx)
{
    hb_state *st = vst;
    eo_free(ctx, st->mem);
    st->mem = NULL;
}

static double dot(int n, const double *a, const double *b)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

static int hb_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    hb_state *st = vst;
    hb_params def;
    const hb_params *hp = params;
    if (!hp) {
        eo_params_default(hb_desc, &def);
        hp = &def;
    }
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != st->n) return eo_error(sc->ctx, EO_ERR_INVALID, "heavy_ball: set up for n = %d, got %d", st->n, n);

    /* metric */
    int have = hp->scaled && obj->ops->metric_diag && obj->ops->metric_diag(obj->data, st->dinv) >= 0;
    for (int i = 0; i < n && have; i++)
        if (!(isfinite(st->dinv[i]) && st->dinv[i] > 0)) have = 0;
    for (int i = 0; i < n; i++) st->dinv[i] = have ? 1 / st->dinv[i] : 1;

    double g, g_prev = NAN, step_norm = NAN, alpha_prev = NAN;
    int rc = eo_objective_gradient(obj, x, &g, st->grad), reason = 0, k;
    if (rc < 0) return rc;
    double gn = sqrt(dot(n, st->grad, st->grad)), gn0 = gn;
    memset(st->v, 0, (size_t)n * sizeof(double));
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .inverted = obj->ops->inverted_count ? obj->ops->inverted_count(obj->data, x) : -1,
                             .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .step_norm = step_norm, .x_norm = sqrt(dot(n, x, x)), .tol = sc->tol};
        if (!isfinite(g) || !isfinite(gn)) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, st->grad);
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        double dg = 0, alpha0 = 1;
        if (!reason) {
            /* first trial a: Barzilai-Borwein (at the start min(1, 1/|D^-1 grad|_inf));
             * v = -D^-1 grad + (beta/a) s_prev, so that a v = -a D^-1 grad + beta s_prev is
             * Polyak's step when the line search accepts a */
            double gmax = 0;
            for (int i = 0; i < n; i++) gmax = fmax(gmax, fabs(st->dinv[i] * st->grad[i]));
            alpha0 = fmin(1, 1 / fmax(gmax, 1e-300));
            if (isfinite(alpha_prev)) { /* Barzilai-Borwein in the metric D: a = s'Ds / s'y */
                double sds = 0, sy = 0;
                for (int i = 0; i < n; i++) {
                    sds += st->v[i] * st->v[i] / st->dinv[i];
                    sy += st->v[i] * (st->grad[i] - st->grad_new[i]);
                }
                alpha0 = sy > 0 ? fmin(fmax(sds / sy, 1e-30), 1e30) : fmin(2 * alpha_prev, 1e30);
            }
            /* adaptive restart (O'Donoghue & Candes 2015): no momentum when grad's = 0 or uphill */
            double b = dot(n, st->grad, st->v) < 0 ? hp->beta / alpha0 : 0;
            for (int i = 0; i < n; i++) st->v[i] = b * st->v[i] - st->dinv[i] * st->grad[i];
            dg = dot(n, st->grad, st->v);
            if (!(dg < 0)) { /* restart: plain scaled gradient */
                for (int i = 0; i < n; i++) st->v[i] = -st->dinv[i] * st->grad[i];
                dg = dot(n, st->grad, st->v);
            }
            info.decrement = -alpha0 * dg / 2;
            if (!(dg < 0)) reason = EO_DIVERGED_NOT_DESCENT;
            else if (sc->stop->needs_direction) {
                si.decrement = info.decrement;
                reason = eo_solver_stop_check(sc, &si, x, st->grad);
            }
        }
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        double gnew = NAN, alpha = 0;
        int nev = 0;
        rc = sc->linesearch->search(sc->linesearch_params, obj, x, st->v, g, dg, alpha0, st->x_new, &gnew, &alpha,
                                    &nev, st->work, sc->ctx, NULL);
        if (rc < 0) return rc;
        info.ls_evals = nev;
        /* as the built-in loop: a search that succeeds at the rounding level of g is taken */
        if (!isfinite(gnew) || !(rc == EO_OK || gnew < g) || !(alpha > 0)) {
            info.reason = reason = EO_DIVERGED_LINESEARCH;
            eo_solver_report(sc, t0, &info);
            break;
        }
        info.alpha = alpha;
        if (eo_solver_report(sc, t0, &info)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        double gchk, s2 = 0;
        memcpy(st->grad_new, st->grad, (size_t)n * sizeof(double)); /* previous gradient, for y */
        rc = eo_objective_gradient(obj, st->x_new, &gchk, st->grad);
        if (rc < 0) return rc;
        for (int i = 0; i < n; i++) {
            double s = st->x_new[i] - x[i];
            s2 += s * s;
            x[i] = st->x_new[i];
            st->v[i] *= alpha; /* v now holds the step s taken: the next momentum term */
        }
        step_norm = sqrt(s2);
        alpha_prev = alpha;
        g_prev = g;
        g = gchk;
        gn = isfinite(g) ? sqrt(dot(n, st->grad, st->grad)) : NAN;
    }
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    res->time = eo_wtime() - t0;
    res->n_value = obj->n_value - nv0;
    res->n_gradient = obj->n_gradient - ng0;
    return EO_OK;
}

static const eo_optimizer_type heavy_ball = {
    .info = {.name = "heavy_ball",
             .summary = "Polyak heavy-ball momentum, v = beta v - D^-1 grad, line search (plug-in example)",
             .params = hb_desc,
             .params_size = sizeof(hb_params)},
    .state_size = sizeof(hb_state),
    .needs_linear = 0,
    .needs_hessian = 0,
    .setup = hb_setup,
    .minimize = hb_minimize,
    .destroy = hb_destroy,
};

EO_PLUGIN_ENTRY(ctx) { return eo_register(ctx, EO_KIND_OPTIMIZER, &heavy_ball); }
