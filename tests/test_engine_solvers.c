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

/* ---- newton_tr -------------------------------------------------------------------- */

typedef struct gnlog {
    int count;
    double gn[512];
} gnlog;

static int log_gn(const eo_iter_info *info, void *user)
{
    gnlog *l = user;
    if (l->count < 512) l->gn[l->count++] = info->grad_norm;
    return 0;
}

/* First step of a built-in scene; x out (malloc'ed), result in *r. */
static double *first_step(const char *scene_name, const char *const *ov, eo_solve_result *r, int *n, gnlog *l)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    double *out = NULL;
    int rc = eo_test_sim_open(&s, ctx, scene_name, NULL, ov);
    CHECK(rc == 0, "%s: open", scene_name);
    if (rc == 0) {
        double *x = eo_test_sim_guess(s);
        *n = eo_test_sim_obj(s)->n;
        rc = eo_solver_minimize(eo_sim_solver(s), eo_test_sim_obj(s), x, l ? log_gn : NULL, l, r);
        CHECK(rc == 0, "%s: minimize: %s", scene_name, eo_ctx_message(ctx));
        out = malloc((size_t)(*n > 0 ? *n : 1) * sizeof(double));
        memcpy(out, x, (size_t)*n * sizeof(double));
    }
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return out;
}

/* newton_tr reaches the minimizer of newton + clamp to 1e-9 m on the first step of every
 * built-in scene but the inverted start, with the true Hessian (default) and with Jacobi
 * preconditioning; on the inverted start it converges (to another local minimizer) and its
 * inner CG meets negative curvature and goes to the boundary; on cantilever_static (true
 * Hessian, forcing quadratic) the order estimated from three successive gradient norms
 * reaches 1.8 above the rounding floor and ‖∇g‖ goes from 1e-2 to 1e-10 relative in at
 * most 4 iterations (newton + clamp, linear there: 0.2 per iteration). */
static void test_newton_tr(void)
{
    printf("newton_tr, first step of the built-in scenes:\n");
    const char *scenes[] = {"cantilever", "twist", "stretch", "inverted", "drop", "freefall", "cantilever_static"};
    const char *ref_ov[] = {"solver.optimizer=newton", "solver.hessian_fix=clamp", "solver.tol=1e-20",
                            "solver.max_iters=300", NULL};
    for (int i = 0; i < 7; i++) {
        eo_solve_result rr, rt;
        int n = 0, nt = 0;
        double *xr = first_step(scenes[i], ref_ov, &rr, &n, NULL);
        CHECK(rr.reason == EO_CONVERGED_DECREMENT || rr.reason == EO_DIVERGED_STAGNATED, "%s: reference %s",
              scenes[i], eo_reason_name(rr.reason));
        for (int pc = 0; pc < 2; pc++) {
            const char *tr_ov[] = {"solver.optimizer=newton_tr", "solver.stop=gradient", "solver.tol=1e-10",
                                   "solver.max_iters=300",
                                   pc ? "solver.newton_tr.precond=jacobi" : "solver.newton_tr.precond=none", NULL};
            gnlog l = {0};
            double *xt = first_step(scenes[i], tr_ov, &rt, &nt, &l);
            double err = 0;
            for (int j = 0; xr && xt && j < n && j < nt; j++) err = fmax(err, fabs(xt[j] - xr[j]));
            printf("  %-18s %-6s %3d iterations %-20s CG %5ld, negative curvature %2ld, Hessians %3ld, "
                   "max |x - x_newton| = %.1e (newton+clamp: %d it., %s)\n",
                   scenes[i], pc ? "jacobi" : "none", rt.iterations, eo_reason_name(rt.reason), rt.n_inner,
                   rt.n_negcurv, rt.n_hessian, err, rr.iterations, eo_reason_name(rr.reason));
            CHECK(n == nt && rt.reason == EO_CONVERGED_GRADIENT, "%s: newton_tr %s", scenes[i],
                  eo_reason_name(rt.reason));
            /* the inverted start has several stationary points; from it the two methods end at
             * different local minimizers of the first step (measured: g = 145.73 newton+clamp,
             * 147.32 newton_tr, both with inverted tets left, recovered over the next steps) */
            if (strcmp(scenes[i], "inverted") != 0)
                CHECK(err <= 1e-9, "%s: newton_tr %g m from newton+clamp", scenes[i], err);
            else
                printf("    inverted: g = %.6g (newton_tr) vs %.6g (newton+clamp): another local minimizer\n",
                       rt.g, rr.g);
            CHECK(rt.n_hessian == rt.iterations + (rt.reason > 0 ? 0 : 1) || rt.n_hessian == rt.iterations,
                  "%s: one Hessian per accepted iterate (%ld for %d)", scenes[i], rt.n_hessian, rt.iterations);
            if (strcmp(scenes[i], "inverted") == 0)
                CHECK(rt.n_negcurv > 0, "inverted: negative curvature never met");
            if (strcmp(scenes[i], "cantilever_static") == 0 && pc == 0) {
                double qmax = 0;
                printf("    gradient norms:");
                for (int k = 0; k < l.count; k++) printf(" %.1e", l.gn[k]);
                printf("\n");
                for (int k = 1; k + 1 < l.count; k++) {
                    double a = l.gn[k - 1], b = l.gn[k], c = l.gn[k + 1];
                    if (c < 1e3 * 3.3e-10 || !(b < a && c < b)) continue; /* above the floor, decreasing */
                    double q = log(c / b) / log(b / a);
                    if (q > qmax) qmax = q;
                }
                /* from ‖∇g‖ ≤ 1e-2‖∇g₀‖ to 1e-10: a linear rate like newton+clamp's 0.2 needs ~10 */
                int k1 = 0;
                while (k1 < l.count && l.gn[k1] > 1e-2 * l.gn[0]) k1++;
                int tail = l.count - 1 - k1;
                printf("    largest order estimate log(g_k+1/g_k)/log(g_k/g_k-1) above the floor: %.2f; "
                       "%d iterations from 1e-2 to 1e-10 relative\n", qmax, tail);
                CHECK(qmax >= 1.8, "cantilever_static: newton_tr order %.2f < 1.8", qmax);
                CHECK(tail <= 4, "cantilever_static: %d iterations from 1e-2 to 1e-10 relative", tail);
            }
            free(xt);
        }
        free(xr);
    }
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
    compare("newton_tr", "clamp", "auto", "gradient", 1e-10, 200);
    compare_x("newton_tr", "clamp", "auto", "gradient", 1e-10, 200, "solver.newton_tr.precond=jacobi");
    compare_x("newton_tr", "clamp", "auto", "newton_decrement", 1e-20, 200, "solver.newton_tr.hessian=fix");
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
    test_newton_tr();
    return eo_test_finish("test_engine_solvers");
}
