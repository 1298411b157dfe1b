/* 2D Poisson FEM (suite 'unit', notes 001 §3–4): −Δu = 2π² sin(πx) sin(πy) on the unit
 * square, u = 0 on the boundary, linear triangles, exposed as g(u) = ½uᵀKu − Fᵀu.
 *
 *  - K is symmetric positive definite with the 5-point stencil on the structured mesh
 *    (diagonal 4, the four grid neighbours −1, the diagonal-edge couplings exactly 0);
 *  - O(h²) convergence: the L2 error for n = 8, 16, 32, 64 halves twice per refinement,
 *    measured rates 2 ± 0.15 (three refinements), max nodal error decreasing too;
 *  - every registered linear solver under Newton (cholmod, cholmod_ldlt, spqr, lapack,
 *    cg, pcg, gauss_seidel, sor, jacobi, ...) reaches the CHOLMOD solution to 1e-8, or
 *    (jacobi is allowed this) reports a negative reason cleanly;
 *  - every registered optimizer (newton, gradient_descent with exact line search,
 *    lbfgs, projective_dynamics, nlopt/ipopt when built) reaches it to 1e-8;
 *  - steepest descent with exact line search (001 eq. 62): the iteration count grows
 *    with n (the condition number of K grows like n²). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/poisson.h"
#include "elastopt/solver.h"
#include "testutil.h"

/* Solve with overrides; u (n) out. Returns the reason (0 on setup error). */
static int solve(eo_ctx *ctx, eo_poisson *p, const char *const *ov, double *u, int *iters)
{
    eo_cfg *cfg = NULL;
    eo_solver *s = NULL;
    eo_solver_opts so;
    eo_solver_opts_default(&so);
    eo_objective *obj = eo_poisson_objective(p);
    int rc = eo_cfg_create_empty(ctx, &cfg);
    for (const char *const *o = ov; rc >= 0 && *o; o++) rc = eo_cfg_override(ctx, cfg, *o);
    static const char *const top[] = {"solver", NULL};
    if (rc >= 0) eo_cfg_expect(cfg, "", top);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &so);
    if (rc >= 0) rc = eo_solver_create(ctx, &so, cfg, obj->n, &s);
    if (rc >= 0) rc = eo_cfg_finish(ctx, cfg);
    eo_solve_result r;
    memset(&r, 0, sizeof r);
    memset(u, 0, (size_t)obj->n * sizeof(double));
    if (rc >= 0) rc = eo_solver_minimize(s, obj, u, NULL, NULL, &r);
    if (rc < 0) fprintf(stderr, "solve: %s\n", eo_ctx_message(ctx));
    eo_solver_destroy(&s);
    eo_cfg_destroy(ctx, &cfg);
    if (iters) *iters = r.iterations;
    return rc < 0 ? 0 : r.reason;
}

static void test_matrix(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_poisson *p;
    CHECK(eo_poisson_create(ctx, 6, &p) == 0, "create");
    const eo_csc *K = eo_poisson_matrix(p);
    int n = K->n, bad = 0;
    double *D = malloc((size_t)n * n * sizeof(double));
    eo_csc_to_dense(K, D);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            int di = abs(i % 5 - j % 5) + abs(i / 5 - j / 5);
            double expect = i == j ? 4 : di == 1 ? -1 : 0;
            bad += fabs(D[i * n + j] - expect) > 1e-12;
        }
    CHECK(n == 25 && bad == 0, "5-point stencil: %d wrong entries", bad);
    free(D);
    eo_poisson *q = NULL;
    CHECK(eo_poisson_create(ctx, 1, &q) == EO_ERR_INVALID && q == NULL, "n = 1 rejected");
    eo_poisson_destroy(&p);
    eo_test_ctx_done(&ctx);
}

static void test_convergence(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const int ns[4] = {8, 16, 32, 64};
    double l2[4], mx[4];
    const char *ov[] = {"solver.tol=1e-24", NULL};
    for (int k = 0; k < 4; k++) {
        eo_poisson *p;
        CHECK(eo_poisson_create(ctx, ns[k], &p) == 0, "create");
        double *u = malloc((size_t)eo_poisson_objective(p)->n * sizeof(double));
        CHECK(solve(ctx, p, ov, u, NULL) > 0, "solve n = %d", ns[k]);
        eo_poisson_error(p, u, &l2[k], &mx[k]);
        free(u);
        eo_poisson_destroy(&p);
    }
    printf("Poisson L2 / max errors:");
    for (int k = 0; k < 4; k++) printf(" n=%d %.4e / %.4e;", ns[k], l2[k], mx[k]);
    printf("\n  L2 rates:");
    for (int k = 1; k < 4; k++) {
        double rate = log2(l2[k - 1] / l2[k]);
        printf(" %.4f", rate);
        CHECK(fabs(rate - 2) <= 0.15, "L2 rate n = %d -> %d: %g", ns[k - 1], ns[k], rate);
        CHECK(mx[k] < mx[k - 1], "max error decreases");
    }
    printf("\n");
    eo_test_ctx_done(&ctx);
}

static double maxdiff(int n, const double *a, const double *b)
{
    double d = 0;
    for (int i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

static void test_solvers(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_poisson *p;
    CHECK(eo_poisson_create(ctx, 16, &p) == 0, "create");
    int n = eo_poisson_objective(p)->n, it;
    double *ref = malloc((size_t)n * sizeof(double)), *u = malloc((size_t)n * sizeof(double));
    const char *ovr[] = {"solver.linear=cholmod", "solver.tol=1e-26", NULL};
    CHECK(solve(ctx, p, ovr, ref, NULL) > 0, "reference");
    printf("linear solvers under newton (n = 16, %d unknowns):\n", n);
    for (const void *const *t = eo_registry_list(EO_KIND_LINSOLVE); *t; t++) {
        const char *name = eo_method_info_of(*t)->name;
        char o1[64];
        snprintf(o1, sizeof o1, "solver.linear=%s", name);
        const char *ov[] = {o1, "solver.tol=1e-22", "solver.max_iters=200", NULL};
        int reason = solve(ctx, p, ov, u, &it);
        double d = maxdiff(n, u, ref);
        printf("  %-14s %-22s %3d newton iterations  max |u - u_ref| %.2e\n", name, eo_reason_name(reason), it, d);
        if (strcmp(name, "jacobi") == 0 && reason < 0) {
            CHECK(reason != 0, "jacobi reports cleanly");
            continue;
        }
        CHECK(reason > 0, "%s: %s", name, eo_reason_name(reason));
        CHECK(d < 1e-8, "%s: distance %g", name, d);
    }
    printf("optimizers (n = 16):\n");
    for (const void *const *t = eo_registry_list(EO_KIND_OPTIMIZER); *t; t++) {
        const char *name = eo_method_info_of(*t)->name;
        char o1[64];
        snprintf(o1, sizeof o1, "solver.optimizer=%s", name);
        int newton_like = strcmp(name, "newton") == 0;
        const char *ov[] = {o1, newton_like ? "solver.stop=newton_decrement" : "solver.stop=gradient",
                            newton_like ? "solver.tol=1e-22" : "solver.tol=1e-13",
                            strcmp(name, "gradient_descent") == 0 ? "solver.linesearch=exact"
                            : strcmp(name, "ncg") == 0            ? "solver.linesearch=wolfe"
                                                                  : "solver.linesearch=backtracking",
                            "solver.max_iters=100000", "solver.nlopt.algorithm=tnewton", NULL};
        /* (nlopt: its L-BFGS ends with NLOPT_FTOL_REACHED near 3e-8 from the solution even
         * with ftol_rel = 0; the preconditioned truncated Newton reaches 1e-10 gradients) */
        int reason = solve(ctx, p, ov, u, &it);
        double d = maxdiff(n, u, ref);
        printf("  %-20s %-26s %6d iterations  max |u - u_ref| %.2e\n", name, eo_reason_name(reason), it, d);
        CHECK(reason > 0, "%s: %s", name, eo_reason_name(reason));
        CHECK(d < 1e-8, "%s: distance %g", name, d);
    }
    free(ref);
    free(u);
    eo_poisson_destroy(&p);
    eo_test_ctx_done(&ctx);
}

static void test_steepest_descent(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const int ns[3] = {4, 8, 16};
    int its[3];
    const char *ov[] = {"solver.optimizer=gradient_descent", "solver.linesearch=exact", "solver.stop=gradient",
                        "solver.tol=1e-8", "solver.max_iters=100000", NULL};
    printf("steepest descent, exact line search, |grad| <= 1e-8 |grad0|:");
    for (int k = 0; k < 3; k++) {
        eo_poisson *p;
        CHECK(eo_poisson_create(ctx, ns[k], &p) == 0, "create");
        double *u = malloc((size_t)eo_poisson_objective(p)->n * sizeof(double));
        int reason = solve(ctx, p, ov, u, &its[k]);
        CHECK(reason > 0, "n = %d: %s", ns[k], eo_reason_name(reason));
        printf(" n=%d: %d iterations;", ns[k], its[k]);
        free(u);
        eo_poisson_destroy(&p);
    }
    printf("\n");
    CHECK(its[1] > 2 * its[0] && its[2] > 2 * its[1], "iterations grow with n (condition ~ n^2): %d %d %d", its[0],
          its[1], its[2]);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    test_matrix();
    test_convergence();
    test_solvers();
    test_steepest_descent();
    return eo_test_finish("test_poisson");
}
