/* The line-search descent loop shared by newton, gradient_descent, lbfgs, ncg and
 * projective_dynamics.
 *
 * At iterate x_k (k = 0, 1, ...):
 *   g_k = g(x_k), ∇g_k                                  (one gradient call)
 *   non-finite g or ∇g                    → EO_DIVERGED_NONFINITE
 *   stop rule without direction           → its reason (e.g. ‖∇g‖ small)
 *   time budget exceeded                  → EO_DIVERGED_TIME_BUDGET
 *   k > 0, a rule with needs_direction and an optimizer with decrement_estimate:
 *     the rule tested with the estimate λ̃²/2 (newton: from the factor already computed)
 *                                         → e.g. EO_CONVERGED_DECREMENT, no new direction
 *   stagnation (below)                    → EO_DIVERGED_STAGNATED
 *   k = max_iters                         → EO_DIVERGED_MAX_ITERS, before a new direction:
 *     at the cap the direction (newton: a Hessian and a factorization) could only turn
 *     "max_iters" into "converged", so only the estimate above can (a run of k
 *     iterations costs k directions: the fixed iteration budgets of the benchmark)
 *   p_k = direction(x_k)   (optimizer)    → its reason if none (not PD, linear solve)
 *   ∇g_kᵀp_k ≥ 0 or non-finite            → EO_DIVERGED_NOT_DESCENT
 *   λ_k²/2 = −α₀∇g_kᵀp_k/2;  stop rule with direction → e.g. EO_CONVERGED_DECREMENT
 *   line search from x_k along p_k, first trial α₀ → x_{k+1} and, from searches that
 *     evaluate gradients (wolfe, exact), ∇g(x_{k+1}) (else one more gradient call);
 *     while the last search accepted its first trial (and at k = 0) the value-only
 *     searches are asked to evaluate the first trial with its gradient
 *     (eo_ls_extra.grad_first): a full Newton step then costs one element pass, not two
 *     accepted when the search returns EO_OK, or a warning but g(x_{k+1}) < g_k;
 *     else                                → EO_DIVERGED_LINESEARCH (x stays x_k)
 *   record k is reported (callback non-zero → EO_DIVERGED_EXTERNAL, x stays x_k)
 *   EO_DESCENT_STALL_LIMIT (+ k/10, below) accepted steps in a row with g(x_{k+1}) ≥ g_k (accepted by
 *   the line searches' rounding-level tie only) and no new smallest ‖∇g‖ (so neither g
 *   nor the gradient makes progress) → EO_DIVERGED_STAGNATED: the stopping
 *   tolerance is below what the floating-point g can resolve; without this the loop
 *   would spend its whole iteration budget (and ~35 evaluations per iteration) at the
 *   rounding floor.
 *   Likewise EO_DESCENT_WEAK_LIMIT accepted steps in a row without SIGNIFICANT progress
 *   (g below its best significant value by more than 1e-14·|g|, or ‖∇g‖ below 0.9 times
 *   its best significant value; records, so that g wandering at its rounding level,
 *   about 1e-15·|g| between full Newton steps at the floor, does not count) →
 *   EO_DIVERGED_STAGNATED: at the floor g and ‖∇g‖ wander at the rounding
 *   level and set new "records" by noise now and then, which the rule above counts as
 *   progress (measured: Newton on the twist with a relative gradient tolerance of 1e-18
 *   ran 182 iterations at the floor before it; with this rule 20-80). The window grows
 *   with the run: EO_DESCENT_WEAK_LIMIT + k/10 steps at iteration k, because a
 *   first-order method whose g has reached the rounding level of g long before ‖∇g‖ is
 *   small still makes real but slow, non-monotone progress in ‖∇g‖ (measured: lbfgs +
 *   wolfe on cantilever_static, g − g* at the noise of g from ‖∇g‖ ≈ 1e-5·‖∇g₀‖ on,
 *   took 30-50 steps per 10% new record of ‖∇g‖ after 2300 iterations, and stopped
 *   stagnated at 3e-6 relative with a fixed window of 25; it needs no such window at
 *   the true floor, 3e-11 relative, reached by Newton).
 * The last record carries the reason. Converged reasons without a direction (and the
 * decrement estimate) are checked before the iteration cap, so a run that converges
 * exactly at k = max_iters by them says so.
 * Nothing here allocates. */
#include "descent.h"
#include "external.h" /* eo_external_inverted */

#include <string.h>

/* accepted steps without a strict decrease of g before EO_DIVERGED_STAGNATED */
#define EO_DESCENT_STALL_LIMIT 5
/* accepted steps without significant progress before EO_DIVERGED_STAGNATED, plus a
 * tenth of the iterations so far (see the file comment) */
#define EO_DESCENT_WEAK_LIMIT 25

int eo_descent_ws_init(eo_ctx *ctx, int n, eo_descent_ws *w)
{
    memset(w, 0, sizeof *w);
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "optimizer: n = %d < 0", n);
    size_t m = (size_t)(n > 0 ? n : 1);
    w->n = n;
    w->p = eo_calloc(ctx, 5 * m, sizeof(double));
    if (!w->p) return eo_error(ctx, EO_ERR_NOMEM, "optimizer: out of memory (n = %d)", n);
    w->grad = w->p + m;
    w->grad_new = w->p + 2 * m;
    w->x_new = w->p + 3 * m;
    w->work = w->p + 4 * m;
    return EO_OK;
}

void eo_descent_ws_deinit(eo_ctx *ctx, eo_descent_ws *w)
{
    eo_free(ctx, w->p);
    memset(w, 0, sizeof *w);
}

int eo_descent_metric(const eo_solver_ctx *sc, double *d)
{
    int n = sc->obj->n, ok = 0;
    if (sc->obj->ops->metric_diag && sc->obj->ops->metric_diag(sc->obj->data, d) >= 0) {
        ok = 1;
        for (int i = 0; i < n; i++)
            if (!(isfinite(d[i]) && d[i] > 0)) ok = 0;
        ok = !eo_solver_agree(sc, !ok);
        if (!ok)
            eo_log(sc->ctx, EO_LOG_WARN,
                   "objective metric has a non-positive or non-finite entry; using identity");
    }
    if (!ok)
        for (int i = 0; i < n; i++) d[i] = 1;
    return ok;
}

int eo_descent_minimize(const eo_descent_ops *ops, void *st, const void *params,
                        const eo_solver_ctx *sc, eo_descent_ws *w, double *x,
                        eo_solve_result *res)
{
    eo_objective *obj = sc->obj;
    const eo_vspace *vs = obj->space;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    double *grad = w->grad, *grad_new = w->grad_new, *p = w->p;
    double g = NAN, gn = NAN, gn0, g_prev = NAN, step_norm = NAN, last_dec = NAN, dec0 = NAN, dec_prev = NAN;
    int rc = EO_OK, reason = 0, k = 0, stalled = 0, weak = 0, first_ok = 1;
    double gn_best = INFINITY, gn_sig = INFINITY, g_sig = INFINITY;
    double ghist[EO_LS_HISTORY]; /* g of the accepted iterates, oldest first (nonmonotone) */
    int nhist = 0;

    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != w->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "optimizer set up for n = %d, objective has n = %d",
                      w->n, n);
        goto done;
    }
    double tg = eo_wtime(), cg = eo_cputime();
    rc = eo_objective_gradient(obj, x, &g, grad);
    res->t_gradient += eo_wtime() - tg;
    res->c_gradient += eo_cputime() - cg;
    res->n_gradient_outside++;
    if (rc < 0) goto done;
    gn = isfinite(g) ? eo_vnorm2(vs, n, grad) : NAN;
    gn0 = gn;
    ghist[nhist++] = g;
    if (ops->begin) {
        rc = ops->begin(st, params, sc, x, g, grad, res);
        if (rc < 0) goto done;
    }
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN,
                             .alpha = NAN, .ls_evals = 0, .shift = 0,
                             .inverted = eo_external_inverted(sc, x), .reason = 0, .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn,
                           .grad_norm0 = gn0, .decrement = NAN, .decrement0 = dec0, .decrement_prev = dec_prev,
                           .step_norm = step_norm,
                           .x_norm = eo_vnorm2(vs, n, x), .tol = sc->tol};
        double dg = NAN, alpha0 = 1;
        if (!isfinite(g) || !isfinite(gn)) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, grad);
        if (!reason && sc->time_budget > 0 && eo_solver_agree(sc, eo_wtime() - t0 > sc->time_budget))
            reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason && k > 0 && sc->stop->needs_direction && ops->decrement_estimate) {
            double est = NAN;
            rc = ops->decrement_estimate(st, params, sc, x, g, grad, &si, &est, res);
            if (rc < 0) goto done;
            if (est >= 0 && isfinite(est)) {
                si.decrement = est;
                int r = eo_solver_stop_check(sc, &si, x, grad);
                si.decrement = NAN;
                if (r > 0) {
                    reason = r;
                    info.decrement = last_dec = est;
                    res->decrement_estimated = 1;
                }
            }
        }
        /* the cap before the direction: at k = max_iters a new direction (a Hessian and a
         * factorization for newton) would only decide between two ways of stopping */
        if (!reason && (stalled >= EO_DESCENT_STALL_LIMIT + k / 10 || weak >= EO_DESCENT_WEAK_LIMIT + k / 10))
            reason = EO_DIVERGED_STAGNATED;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (!reason) {
            eo_direction_out d = {.alpha0 = 1, .shift = 0, .reason = 0};
            rc = ops->direction(st, params, sc, x, g, grad, p, &d, res);
            if (rc < 0) goto done;
            info.shift = d.shift;
            info.projected = d.projected;
            info.eta = d.eta;
            info.lin_iters = d.lin_iters;
            info.neg_curvature = d.neg_curvature;
            alpha0 = d.alpha0;
            reason = d.reason;
            if (!reason) {
                dg = eo_vdot(vs, n, grad, p);
                if (!(dg < 0) || !isfinite(dg)) {
                    reason = EO_DIVERGED_NOT_DESCENT;
                } else {
                    info.decrement = last_dec = -alpha0 * dg / 2;
                    if (k == 0) si.decrement0 = dec0 = last_dec;
                    if (sc->stop->needs_direction) {
                        si.decrement = info.decrement;
                        reason = eo_solver_stop_check(sc, &si, x, grad);
                    }
                }
            }
        }
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        double gnew = NAN, alpha = 0;
        int nev = 0;
        eo_ls_extra ex = {.grad_new = grad_new, .have_grad = 0, .c2 = ops->ls_c2, .g_hist = ghist,
                          .n_hist = nhist, .grad_first = first_ok};
        const double tls = eo_wtime(), cls = eo_cputime();
        rc = sc->linesearch->search(sc->linesearch_params, obj, x, p, g, dg, alpha0, w->x_new,
                                    &gnew, &alpha, &nev, w->work, sc->ctx, &ex);
        res->t_linesearch += eo_wtime() - tls;
        res->c_linesearch += eo_cputime() - cls;
        res->n_ls_evals += nev;
        info.ls_evals = nev;
        if (rc < 0) goto done;
        first_ok = rc == EO_OK && nev == 1;
        if (!isfinite(gnew) || !(rc == EO_OK || gnew < g) || !(alpha > 0)) {
            reason = EO_DIVERGED_LINESEARCH;
            info.reason = reason;
            rc = EO_OK;
            eo_solver_report(sc, t0, &info);
            break;
        }
        rc = EO_OK;
        if (gn < gn_best) gn_best = gn;
        info.alpha = alpha;
        if (eo_solver_agree(sc, eo_solver_report(sc, t0, &info) != 0)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        /* accept: the gradient at x_{k+1} from the line search if it has it, else one call */
        double gchk = gnew;
        if (!ex.have_grad) {
            tg = eo_wtime();
            cg = eo_cputime();
            rc = eo_objective_gradient(obj, w->x_new, &gchk, grad_new);
            res->t_gradient += eo_wtime() - tg;
            res->c_gradient += eo_cputime() - cg;
            res->n_gradient_outside++;
            if (rc < 0) goto done;
        }
        if (ops->accepted) ops->accepted(st, params, x, w->x_new, grad, grad_new, p, alpha);
        double s2 = 0;
        for (int i = 0; i < n; i++) {
            double s = w->x_new[i] - x[i];
            if (!vs || vs->own[i]) s2 += s * s;
            x[i] = w->x_new[i];
        }
        eo_vreduce(vs, &s2, 1, EO_REDUCE_SUM);
        step_norm = sqrt(s2);
        double *t = grad;
        grad = grad_new;
        grad_new = t;
        g_prev = g;
        g = gchk;
        if (nhist == EO_LS_HISTORY) memmove(ghist, ghist + 1, (EO_LS_HISTORY - 1) * sizeof ghist[0]), nhist--;
        ghist[nhist++] = g;
        gn = isfinite(g) ? eo_vnorm2(vs, n, grad) : NAN;
        dec_prev = last_dec;
        last_dec = NAN;
        stalled = (g < g_prev || gn < gn_best) ? 0 : stalled + 1;
        if (g < g_sig - 1e-14 * fabs(g_sig) || gn < 0.9 * gn_sig) {
            weak = 0;
            if (g < g_sig) g_sig = g;
            if (gn < gn_sig) gn_sig = gn;
        } else {
            weak++;
        }
    }
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    res->decrement = last_dec;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}
