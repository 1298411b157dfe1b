/* Every solver configuration reaches the same minimizer of the same step problem
 * (suite 'engine'): Newton with every registered Hessian fix, every registered line
 * search with newton, gradient_descent and lbfgs, and ncg (PR+, FR, HZ; lumped-mass and
 * PD preconditioners) and lbfgs with each initial matrix h0, with the wolfe search.
 * Then the first step of every built-in scene: lbfgs + wolfe and ncg + wolfe reach
 * ‖∇g‖ ≤ 1e-8·‖∇g₀‖ (gradient rule), every one of them (every examples/NAME.json, also
 * cantilever_static: its g reaches the rounding level of g near 1e-5 relative gradient,
 * below that only ‖∇g‖ measures progress; its gradient floor is 3e-11 relative, Newton +
 * hessian_fix none), with the line search chosen by solver.linesearch = auto (wolfe for
 * both) and one value+gradient call per line-search trial and none after acceptance
 * (n_value = 0, n_gradient = 1 + Σ trials).
 *
 * The step: a 0.2 m cube (3×3×3 cells, stable Neo-Hookean, E = 1e5) clamped at its
 * bottom face, starting stretched 20% along x and squeezed 10% along y, one backward
 * Euler step of 0.02 s under gravity: a nonlinear, well-posed problem. Reference:
 * Newton with the true Hessian to a decrement of 1e-24. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

static const char *scene =
    "{\"mesh\": {\"generate\": {\"size\": [0.2, 0.2, 0.2], \"cells\": [3, 3, 3]}},"
    " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e5, \"nu\": 0.3, \"density\": 1000},"
    " \"boundary\": [{\"box\": [[-1, -1, -1], [1, 1, 0]], \"fixed\": true}],"
    " \"initial\": {\"scale\": [1.2, 0.9, 1.0]},"
    " \"time\": {\"integrator\": \"backward_euler\", \"dt\": 0.02, \"steps\": 1}}";

/* Solve the first step with the given overrides; x (free coordinates) out. */
static int solve(const char *const *ov, double *x, int *n, int *iters, int *reason)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    int rc = eo_test_sim_open(&s, ctx, NULL, scene, ov);
    if (rc == 0) {
        eo_solve_result r;
        double *x0 = eo_test_sim_guess(s);
        rc = eo_solver_minimize(eo_sim_solver(s), eo_test_sim_obj(s), x0, NULL, NULL, &r);
        *n = eo_test_sim_obj(s)->n;
        memcpy(x, x0, (size_t)*n * sizeof(double));
        *iters = r.iterations;
        *reason = r.reason;
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return rc;
}

static double *xref;
static int nref;

static void compare_x(const char *opt, const char *fix, const char *ls, const char *stop, double tol,
                      int max_iters, const char *extra)
{
    char o[64], f[64], l[64], st[64], t[64], m[64];
    snprintf(o, sizeof o, "solver.optimizer=%s", opt);
    snprintf(f, sizeof f, "solver.hessian_fix=%s", fix);
    snprintf(l, sizeof l, "solver.linesearch=%s", ls);
    snprintf(st, sizeof st, "solver.stop=%s", stop);
    snprintf(t, sizeof t, "solver.tol=%g", tol);
    snprintf(m, sizeof m, "solver.max_iters=%d", max_iters);
    const char *ov[] = {o, f, l, st, t, m, extra, NULL};
    double *x = malloc((size_t)nref * sizeof(double));
    int n = 0, iters = 0, reason = 0;
    int rc = solve(ov, x, &n, &iters, &reason);
    double err = 0;
    for (int i = 0; i < n && i < nref; i++) err = fmax(err, fabs(x[i] - xref[i]));
    printf("  %-17s %-6s %-13s %-17s %5d iterations  %-22s max |x - x*| = %.2e %s\n", opt, fix, ls, stop,
           iters, eo_reason_name(reason), err, extra ? extra : "");
    CHECK(rc == 0 && n == nref, "%s/%s/%s: rc %d", opt, fix, ls, rc);
    CHECK(eo_reason_is_converged(reason), "%s/%s/%s: %s", opt, fix, ls, eo_reason_name(reason));
    CHECK(err < 1e-7, "%s/%s/%s: distance to the reference minimizer %g m", opt, fix, ls, err);
    free(x);
}

static void compare(const char *opt, const char *fix, const char *ls, const char *stop, double tol, int max_iters)
{
    compare_x(opt, fix, ls, stop, tol, max_iters, NULL);
}

typedef struct evcount {
    long trials;
    int records;
} evcount;

static int count_trials(const eo_iter_info *info, void *user)
{
    evcount *c = user;
    c->trials += info->ls_evals;
    c->records++;
    return 0;
}

/* First step of a built-in scene with optimizer opt + wolfe to a relative gradient tol. */
static void scene_first_step(const char *scene_name, const char *opt, double tol)
{
    eo_ctx *ctx = eo_test_ctx();
    char o[64], t[64];
    snprintf(o, sizeof o, "solver.optimizer=%s", opt);
    snprintf(t, sizeof t, "solver.tol=%g", tol);
    const char *ov[] = {o, "solver.linesearch=auto", "solver.stop=gradient", t, "solver.max_iters=20000", NULL};
    eo_sim *s = NULL;
    int rc;
    if (strstr(scene_name, ".json")) { /* an example without a built-in twin */
        char path[1024];
        const char *root = getenv("EO_SOURCE_ROOT");
        snprintf(path, sizeof path, "%s/%s", root ? root : ".", scene_name);
        rc = eo_sim_create_from(ctx, path, NULL, ov, &s);
        if (rc == 0) rc = eo_sim_prepare(s, NULL, NULL);
    } else {
        rc = eo_test_sim_open(&s, ctx, scene_name, NULL, ov);
    }
    CHECK(rc == 0, "%s: open: %s", scene_name, eo_ctx_message(ctx));
    if (rc == 0) {
        eo_solve_result r;
        evcount c = {0, 0};
        double *x = eo_test_sim_guess(s);
        rc = eo_solver_minimize(eo_sim_solver(s), eo_test_sim_obj(s), x, count_trials, &c, &r);
        CHECK(rc == 0, "%s/%s: minimize", scene_name, opt);
        printf("  %-18s %-6s %5d iterations  %-20s |grad| %.2e  value calls %ld, gradient calls %ld = 1 + %ld "
               "trials\n", scene_name, opt, r.iterations, eo_reason_name(r.reason), r.grad_norm, r.n_value,
               r.n_gradient, c.trials);
        CHECK(r.reason == EO_CONVERGED_GRADIENT, "%s/%s: %s", scene_name, opt, eo_reason_name(r.reason));
        CHECK(r.n_value == 0 && r.n_gradient == 1 + c.trials,
              "%s/%s: %ld value and %ld gradient calls for %ld trials", scene_name, opt, r.n_value,
              r.n_gradient, c.trials);
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    xref = malloc(100000 * sizeof(double));
    int iters, reason;
    const char *ov[] = {"solver.hessian_fix=none", "solver.tol=1e-24", "solver.max_iters=100", NULL};
    CHECK(solve(ov, xref, &nref, &iters, &reason) == 0, "reference solve");
    CHECK(eo_reason_is_converged(reason), "reference: %s", eo_reason_name(reason));
    printf("reference: newton/none, %d iterations, %d free coordinates\n", iters, nref);

    for (const void *const *t = eo_registry_list(EO_KIND_HESSFIX); *t; t++)
        compare("newton", eo_method_info_of(*t)->name, "backtracking", "newton_decrement", 1e-20, 200);
    for (const void *const *t = eo_registry_list(EO_KIND_LINESEARCH); *t; t++) {
        const char *ls = eo_method_info_of(*t)->name;
        compare("newton", "clamp", ls, "newton_decrement", 1e-20, 200);
        compare("lbfgs", "clamp", ls, "gradient", 1e-10, 5000);
        if (strcmp(ls, "none") != 0) /* unit steps of steepest descent need not converge */
            compare("gradient_descent", "clamp", ls, "gradient", 1e-10, 20000);
    }
    compare("ncg", "clamp", "wolfe", "gradient", 1e-10, 5000);
    compare_x("ncg", "clamp", "wolfe", "gradient", 1e-10, 5000, "solver.ncg.beta=fr");
    compare_x("ncg", "clamp", "wolfe", "gradient", 1e-10, 5000, "solver.ncg.beta=hz");
    compare_x("ncg", "clamp", "wolfe", "gradient", 1e-10, 5000, "solver.ncg.precond=pd");
    compare_x("ncg", "clamp", "wolfe", "gradient", 1e-10, 5000, "solver.ncg.precond=none");
    compare_x("lbfgs", "clamp", "wolfe", "gradient", 1e-10, 5000, "solver.lbfgs.h0=pd");
    compare_x("lbfgs", "clamp", "wolfe", "gradient", 1e-10, 5000, "solver.lbfgs.h0=scaled_identity");
    free(xref);

    printf("built-in scenes, first step, wolfe line search, gradient rule:\n");
    const char *scenes[] = {"cantilever", "twist", "stretch", "inverted", "drop", "freefall", "cantilever_static",
                            "examples/spring_chain.json"};
    for (int i = 0; i < 8; i++) {
        scene_first_step(scenes[i], "lbfgs", 1e-8);
        scene_first_step(scenes[i], "ncg", 1e-8);
    }
    return eo_test_finish("test_engine_solvers");
}
