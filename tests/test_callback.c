/* Optimizers made of callbacks (callback.h): registration errors; the direction form
 * running a Newton direction through the shared loop reproduces the built-in newton +
 * clamp on the twisted bar (same iterations, positions to 1e-12); the minimize form (a
 * full-step Newton iteration that reports its iterates and uses the configured stopping
 * rule) reaches the same minimizer; both are found by name and gone after destroy. */
#include <math.h>
#include <string.h>

#include "elastopt/callback.h"
#include "elastopt/registry.h"
#include "elastopt/sim.h"
#include "testutil.h"

/* p = −H⁻¹∇g with H the clamp-projected Hessian, factored with sc->linear */
typedef struct newton_user {
    int calls;
    const eo_csc *analyzed;
} newton_user;

static int newton_p(eo_linsolve *ls, newton_user *u, eo_objective *obj, const double *x,
                    const double *grad, double *p)
{
    eo_csc *H;
    int rc = eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);
    if (rc < 0) return rc;
    if (u->analyzed != H && (rc = eo_linsolve_analyze(ls, H)) < 0) return rc;
    u->analyzed = H;
    if ((rc = eo_linsolve_factor(ls, H)) != EO_OK) return rc < 0 ? rc : EO_ERR_LINSOLVE;
    if ((rc = eo_linsolve_solve(ls, grad, p)) < 0) return rc;
    for (int i = 0; i < obj->n; i++) p[i] = -p[i];
    return EO_OK;
}

static int cb_direction(void *user, const eo_solver_ctx *sc, const double *x, double g,
                        const double *grad, double *p, double *alpha0, int *reason)
{
    newton_user *u = user;
    (void)g, (void)alpha0, (void)reason;
    u->calls++;
    return newton_p(sc->linear, u, sc->obj, x, grad, p);
}

/* full Newton steps; every iterate reported; the configured rule decides */
static int cb_minimize(void *user, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    newton_user *u = user;
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    double grad[4096], p[4096], g, gn0 = NAN, dec0 = NAN, dec_prev = NAN;
    if (n > 4096) return eo_error(sc->ctx, EO_ERR_INVALID, "test: n too large");
    for (int k = 0;; k++) {
        int rc = eo_objective_gradient(obj, x, &g, grad);
        if (rc < 0) return rc;
        double gn = 0;
        for (int i = 0; i < n; i++) gn += grad[i] * grad[i];
        gn = sqrt(gn);
        if (k == 0) gn0 = gn;
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN,
                             .alpha = NAN, .inverted = -1, .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = NAN, .grad_norm = gn,
                           .grad_norm0 = gn0, .decrement = NAN, .decrement0 = dec0, .decrement_prev = dec_prev,
                           .step_norm = NAN, .tol = sc->tol};
        int reason = sc->stop->check(sc->stop_params, &si);
        if (!reason) {
            u->calls++;
            if ((rc = newton_p(sc->linear, u, obj, x, grad, p)) < 0) return rc;
            double dg = 0;
            for (int i = 0; i < n; i++) dg += grad[i] * p[i];
            si.decrement = info.decrement = -dg / 2;
            if (k == 0) si.decrement0 = dec0 = si.decrement; /* relative_decrement's reference */
            if (sc->stop->needs_direction) reason = sc->stop->check(sc->stop_params, &si);
            dec_prev = si.decrement;
        }
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        res->iterations = k;
        res->g = g;
        res->grad_norm = gn;
        res->decrement = info.decrement;
        if (reason) {
            info.reason = res->reason = reason;
            eo_solver_report(sc, t0, &info);
            return EO_OK;
        }
        info.alpha = 1;
        if (eo_solver_report(sc, t0, &info)) {
            res->reason = EO_DIVERGED_EXTERNAL;
            return EO_OK;
        }
        for (int i = 0; i < n; i++) x[i] += p[i];
    }
}

static int cb_noreason(void *user, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    (void)user, (void)sc, (void)x, (void)res;
    return EO_OK;
}

static int count_records(const eo_iter_info *it, void *user)
{
    int *n = user;
    (*n)++;
    (void)it;
    return 0;
}

/* steps of the twisted bar (3 Newton iterations each) with an optimizer: final positions into x (3 nv) */
static int run_steps(eo_ctx *ctx, const char *opt, int steps, double *x, int *iters, int *conv,
                     int *records)
{
    char o1[64], o2[64];
    snprintf(o1, sizeof o1, "solver.optimizer=%s", opt);
    snprintf(o2, sizeof o2, "time.steps=%d", steps);
    const char *ov[] = {o1, o2, "solver.hessian_fix=clamp", "mesh.generate.cells=[8,2,2]",
                        "time.dt=0.03", NULL};
    eo_sim *sim;
    int rc = eo_sim_create_from(ctx, NULL, "twist", ov, &sim);
    if (rc < 0) return rc;
    if (records) eo_sim_set_iter_callback(sim, count_records, records);
    *iters = *conv = 0;
    for (int k = 0; k < steps && rc >= 0; k++) {
        eo_sim_step_result r;
        rc = eo_sim_step(sim, &r);
        *iters += r.iterations;
        *conv += r.reason > 0;
    }
    eo_sim_get_state(sim, x, NULL, NULL, NULL);
    eo_sim_destroy(&sim);
    return rc;
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    newton_user ud = {0}, um = {0};
    eo_callback_optimizer *od = NULL, *om = NULL, *bad = NULL;

    /* registration errors */
    eo_callback_optimizer_def d0 = {.name = "cb_none", .summary = "x"};
    CHECK(eo_callback_optimizer_register(ctx, &d0, &bad) == EO_ERR_INVALID && !bad, "no callback");
    d0.direction = cb_direction;
    d0.minimize = cb_minimize;
    CHECK(eo_callback_optimizer_register(ctx, &d0, &bad) == EO_ERR_INVALID && !bad, "both callbacks");
    eo_callback_optimizer_def dn = {.name = "newton", .direction = cb_direction};
    CHECK(eo_callback_optimizer_register(ctx, &dn, &bad) == EO_ERR_INVALID && !bad &&
              strstr(eo_ctx_message(ctx), "already registered"),
          "duplicate name: %s", eo_ctx_message(ctx));
    eo_callback_optimizer_def dbad = {.name = "a b", .direction = cb_direction};
    CHECK(eo_callback_optimizer_register(ctx, &dbad, &bad) == EO_ERR_INVALID && !bad, "bad name");

    eo_callback_optimizer_def dd = {.name = "cb_newton", .summary = "Newton direction from a callback",
                                    .needs_hessian = 1, .needs_linear = 1,
                                    .direction = cb_direction, .user = &ud, .newton_decrement = 1};
    eo_callback_optimizer_def dm = {.name = "cb_full_newton", .summary = "full Newton steps, minimize callback",
                                    .needs_hessian = 1, .needs_linear = 1,
                                    .minimize = cb_minimize, .user = &um, .newton_decrement = 1};
    CHECK(eo_callback_optimizer_register(ctx, &dd, &od) == EO_OK, "%s", eo_ctx_message(ctx));
    CHECK(eo_callback_optimizer_register(ctx, &dm, &om) == EO_OK, "%s", eo_ctx_message(ctx));
    const void *found = NULL;
    CHECK(eo_registry_find(ctx, EO_KIND_OPTIMIZER, "cb_newton", &found) == EO_OK &&
              found == eo_callback_optimizer_type(od), "lookup");

    enum { STEPS = 3 };
    static double xr[3 * 4096], xd[3 * 4096], xm[3 * 4096];
    int ir, cr, id, cd, im, cm, recd = 0;
    CHECK(run_steps(ctx, "newton", STEPS, xr, &ir, &cr, NULL) == EO_OK, "%s", eo_ctx_message(ctx));
    CHECK(run_steps(ctx, "cb_newton", STEPS, xd, &id, &cd, &recd) == EO_OK, "%s", eo_ctx_message(ctx));
    CHECK(run_steps(ctx, "cb_full_newton", STEPS, xm, &im, &cm, NULL) == EO_OK, "%s", eo_ctx_message(ctx));
    const int nv = 9 * 3 * 3;
    double dmax = 0, mmax = 0;
    for (int i = 0; i < 3 * nv; i++) {
        dmax = fmax(dmax, fabs(xd[i] - xr[i]));
        mmax = fmax(mmax, fabs(xm[i] - xr[i]));
    }
    CHECK(cr == STEPS && cd == STEPS && cm == STEPS, "converged %d %d %d of %d", cr, cd, cm, STEPS);
    CHECK(id == ir && ir > STEPS, "direction form: %d iterations, newton %d", id, ir);
    /* one direction per iteration plus the one whose decrement stops each step */
    CHECK(ud.calls == ir + STEPS, "direction callback called %d times for %d iterations", ud.calls, ir);
    CHECK(recd == ir + STEPS, "records %d, expected iterations + one final per step = %d", recd, ir + STEPS);
    CHECK(dmax <= 1e-12, "direction form vs newton: max |dx| = %g", dmax);
    /* backtracking accepts every full Newton step here: the same iterates */
    CHECK(mmax <= 1e-12 && im == ir, "minimize form vs newton: max |dx| = %g (%d iterations)", mmax, im);
    printf("callback: newton %d iterations, direction form %d (max |dx| %.2e), minimize form %d (max |dx| %.2e)\n",
           ir, id, dmax, im, mmax);

    /* a minimize callback that returns no reason is an error naming it */
    eo_callback_optimizer_def dz = {.name = "cb_noreason", .minimize = cb_noreason};
    eo_callback_optimizer *oz = NULL;
    CHECK(eo_callback_optimizer_register(ctx, &dz, &oz) == EO_OK, "%s", eo_ctx_message(ctx));
    CHECK(run_steps(ctx, "cb_noreason", 1, xm, &im, &cm, NULL) == EO_ERR_INVALID &&
              strstr(eo_ctx_message(ctx), "'cb_noreason' returned without a reason"),
          "no reason: %s", eo_ctx_message(ctx));
    eo_callback_optimizer_destroy(&oz);
    eo_callback_optimizer_destroy(&od);
    CHECK(!od && eo_registry_find(ctx, EO_KIND_OPTIMIZER, "cb_newton", &found) == EO_ERR_UNKNOWN_NAME,
          "unregistered after destroy");
    eo_callback_optimizer_destroy(&om);
    eo_callback_optimizer_destroy(&om); /* accepts NULL */
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_callback");
}
