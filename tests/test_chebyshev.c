/* Chebyshev semi-iterative acceleration (suite 'solvers'): pd_local_global.chebyshev and
 * the optimizer jacobi_chebyshev (Wang 2015; solvers/optim/chebyshev.h).
 *
 *  - PD local/global on the twist with pd_arap (first step): plain, Chebyshev with ρ
 *    measured online, and Chebyshev with ρ from Wang's offline procedure (the rate of the
 *    plain run's last corrections) all reach Newton's minimizer within 1e-8 of the step's
 *    motion; both accelerated runs need fewer iterations than plain (the offline ρ at
 *    least 2.5x fewer);
 *  - damped block-Jacobi on the step objective (stable_neo_hookean) of cantilever and
 *    twist: plain and accelerated reach Newton's minimizer within 1e-8 of the motion, the
 *    accelerated one in at least 2x fewer iterations;
 *  - restart: an over-estimated ρ (0.999 where the plain rate is ~0.92 / ~0.998) makes the
 *    accelerated iterates raise g; the restart rule fires (n_fallback > 0) and the run
 *    still converges to the same minimizer;
 *  - anderson and chebyshev together are refused (EO_ERR_INVALID). */
#include <stdlib.h>
#include <string.h>

#include "elastopt/impl/method.h"
#include "engine_util.h"

typedef struct trace {
    int n;
    double gn[20001]; /* ‖∇g‖ per iterate */
} trace;

static int on_iter(const eo_iter_info *info, void *user)
{
    trace *t = user;
    if (t->n < 20001) t->gn[t->n] = info->grad_norm;
    t->n++;
    return 0;
}

/* minimize obj from x0 with the solver section `solver_json`; x out */
static int solve_with(eo_ctx *ctx, eo_objective *obj, const double *x0, double *x, const char *solver_json,
                      eo_solve_result *r, trace *tr)
{
    if (tr) tr->n = 0;
    return eo_test_solve_json(ctx, obj, x0, x, solver_json, tr ? on_iter : NULL, tr, r);
}

static const char *newton_json =
    "{\"optimizer\": \"newton\", \"hessian_fix\": \"project_on_demand\", \"stop\": \"gradient\", \"tol\": 1e-11,"
    " \"max_iters\": 200}";

/* Wang's offline ρ: the rate of the plain run's corrections over its last m iterates */
static double offline_rho(const trace *t, int m)
{
    const int k = (t->n < 20001 ? t->n : 20001) - 1;
    if (k - m < 1) return NAN;
    return pow(t->gn[k] / t->gn[k - m], 1.0 / m);
}

typedef struct run {
    const char *label, *json;
    int min_speedup10; /* plain iterations ≥ this/10 × accelerated (0: not asserted) */
    int want_restart;
} run;

static void check_case(const char *scene, const char *model, const char *plain_json, const run *runs, int nruns,
                       const char *rho_json_fmt)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    char mod[64];
    snprintf(mod, sizeof mod, "material.model=%s", model);
    const char *ov[] = {"solver.fallback=[]", mod, NULL};
    if (eo_test_sim_open(&s, ctx, scene, NULL, ov) < 0) {
        CHECK(0, "open %s", scene);
        eo_test_ctx_done(&ctx);
        return;
    }
    eo_objective *obj = eo_test_sim_obj(s);
    const int n = obj->n;
    double *x0 = malloc((size_t)n * sizeof(double)), *xs = malloc((size_t)n * sizeof(double));
    double *x = malloc((size_t)n * sizeof(double));
    trace *tr = malloc(sizeof *tr);
    memcpy(x0, eo_test_sim_guess(s), (size_t)n * sizeof(double));
    eo_solve_result rn, rp, r;
    CHECK(solve_with(ctx, obj, x0, xs, newton_json, &rn, NULL) == 0 &&
              (eo_reason_is_converged(rn.reason) || rn.reason == EO_DIVERGED_STAGNATED),
          "%s newton reference: %s", scene, eo_reason_name(rn.reason));
    CHECK(solve_with(ctx, obj, x0, x, plain_json, &rp, tr) == 0 && eo_reason_is_converged(rp.reason),
          "%s %s plain: %s", scene, model, eo_reason_name(rp.reason));
    const double ep = eo_test_motion_error(n, x, xs, x0), rho = offline_rho(tr, 10);
    printf("  %-10s %-18s plain: %5d it, err %.2e; offline rho %.5f\n", scene, model, rp.iterations, ep, rho);
    CHECK(ep <= 1e-8, "%s plain vs newton %g of the motion", scene, ep);
    for (int i = 0; i < nruns; i++) {
        char json[512];
        if (runs[i].json) snprintf(json, sizeof json, "%s", runs[i].json);
        else snprintf(json, sizeof json, rho_json_fmt, rho);
        int rc = solve_with(ctx, obj, x0, x, json, &r, NULL);
        const double e = eo_test_motion_error(n, x, xs, x0);
        printf("  %-10s %-18s %-22s %5d it (%ld restarts), err %.2e\n", scene, model, runs[i].label, r.iterations,
               r.n_fallback, e);
        CHECK(rc == 0 && eo_reason_is_converged(r.reason), "%s %s: %s", scene, runs[i].label,
              eo_reason_name(r.reason));
        CHECK(e <= 1e-8, "%s %s vs newton %g of the motion", scene, runs[i].label, e);
        if (runs[i].min_speedup10)
            CHECK(10 * rp.iterations >= runs[i].min_speedup10 * r.iterations,
                  "%s %s: %d iterations against plain %d (wanted %.1fx fewer)", scene, runs[i].label, r.iterations,
                  rp.iterations, runs[i].min_speedup10 / 10.0);
        if (runs[i].want_restart)
            CHECK(r.n_fallback > 0, "%s %s: the restart rule never fired", scene, runs[i].label);
    }
    free(tr);
    free(x0), free(xs), free(x);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

static void check_refused(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_cfg *cfg = NULL;
    eo_solver *sv = NULL;
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    const char *json = "{\"solver\": {\"optimizer\": \"pd_local_global\", \"pd_local_global\": "
                       "{\"anderson\": true, \"chebyshev\": true}}}";
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &o);
    if (rc >= 0) rc = eo_solver_create(ctx, &o, cfg, &sv);
    eo_sim *s = NULL;
    const char *ov[] = {"solver.fallback=[]", "material.model=pd_arap", NULL};
    if (rc >= 0 && eo_test_sim_open(&s, ctx, "twist", NULL, ov) == 0) {
        eo_objective *obj = eo_test_sim_obj(s);
        double *x = malloc((size_t)obj->n * sizeof(double));
        memcpy(x, eo_test_sim_guess(s), (size_t)obj->n * sizeof(double));
        eo_solve_result r;
        rc = eo_solver_minimize(sv, obj, x, NULL, NULL, &r);
        free(x);
    }
    printf("  anderson + chebyshev: rc %d (%s)\n", rc, eo_ctx_message(ctx));
    CHECK(rc == EO_ERR_INVALID, "anderson + chebyshev refused: rc %d", rc);
    eo_sim_destroy(&s);
    eo_solver_destroy(&sv);
    eo_cfg_destroy(&cfg);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    /* PD local/global (its own PD energy) */
    const char *pd_plain = "{\"optimizer\": \"pd_local_global\", \"tol\": 1e-10, \"max_iters\": 20000}";
    const run pd_runs[] = {
        {"chebyshev (rho measured)",
         "{\"optimizer\": \"pd_local_global\", \"tol\": 1e-10, \"max_iters\": 20000,"
         " \"pd_local_global\": {\"chebyshev\": true}}", 15, 0},
        {"chebyshev (rho offline)", NULL, 25, 0},
        {"chebyshev (rho 0.999)",
         "{\"optimizer\": \"pd_local_global\", \"tol\": 1e-10, \"max_iters\": 20000,"
         " \"pd_local_global\": {\"chebyshev\": true, \"rho\": 0.999}}", 0, 1},
    };
    check_case("twist", "pd_arap", pd_plain, pd_runs, 3,
               "{\"optimizer\": \"pd_local_global\", \"tol\": 1e-10, \"max_iters\": 20000,"
               " \"pd_local_global\": {\"chebyshev\": true, \"rho\": %.6f}}");
    /* damped block-Jacobi on the hyperelastic step objective */
    const char *jc_plain = "{\"optimizer\": \"jacobi_chebyshev\", \"tol\": 1e-10, \"max_iters\": 20000,"
                           " \"jacobi_chebyshev\": {\"accelerated\": false}}";
    const run jc_runs[] = {
        {"chebyshev (rho measured)", "{\"optimizer\": \"jacobi_chebyshev\", \"tol\": 1e-10, \"max_iters\": 20000}", 20,
         0},
        {"chebyshev (rho 0.9999)",
         "{\"optimizer\": \"jacobi_chebyshev\", \"tol\": 1e-10, \"max_iters\": 20000,"
         " \"jacobi_chebyshev\": {\"rho\": 0.9999}}", 0, 1},
    };
    check_case("cantilever", "stable_neo_hookean", jc_plain, jc_runs, 2, NULL);
    check_case("twist", "stable_neo_hookean", jc_plain, jc_runs, 2, NULL);
    check_refused();
    return eo_test_finish("test_chebyshev");
}
