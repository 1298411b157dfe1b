/* Suite 'unit': Eisenstat–Walker forcing terms (solvers/optim/forcing.c).
 * Hand-computed values of choice 2 and of each safeguard, and the convergence order of
 * an inexact Newton iteration on F(x) = eˣ − 1 whose linear solve leaves exactly the
 * relative residual η_k: the order log(F_{k+1}/F_k)/log(F_k/F_{k−1}) approaches α = 2
 * with the forcing terms (> 1.8 over the last steps), while a constant η = 0.1 only
 * converges linearly (order < 1.2, rate F_{k+1}/F_k → 0.1). Newton's `auto` forcing
 * through a scripted iterative solver: η = eta_global after a damped step or a slowly
 * falling decrement, Eisenstat–Walker after a fast one, and the guard ended for the rest
 * of the minimization once a guarded solve needed more than global_max_iters
 * iterations (multigrid on nearly incompressible problems). */
#include <math.h>

#include "../solvers/optim/forcing.h"
#include "elastopt/linsolve.h"
#include "elastopt/sparse.h"
#include "testutil.h"

/* a scripted iterative solver: each solve reports `script_iters` iterations */
static int script_iters;
static double script_rtol;
static int fake_analyze(void *st, const eo_csc *A, eo_ctx *ctx) { (void)st, (void)A, (void)ctx; return EO_OK; }
static int fake_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)st, (void)A, (void)stats, (void)ctx;
    return EO_OK;
}
static int fake_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)st, (void)ctx;
    x[0] = b[0];
    stats->iterations = script_iters;
    return EO_OK;
}
static void fake_set_rtol(void *st, double rtol) { (void)st, script_rtol = rtol; }
static int fake_is_iterative(const void *st) { (void)st; return 1; }
static const eo_linsolve_type fake_type = {.info = {.name = "scripted", .summary = "test"},
                                           .analyze = fake_analyze,
                                           .factor = fake_factor,
                                           .solve = fake_solve,
                                           .set_rtol = fake_set_rtol,
                                           .is_iterative = fake_is_iterative};

static void test_auto_guard(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_linsolve *ls = NULL;
    eo_csc *A = NULL;
    CHECK(eo_linsolve_create(ctx, &fake_type, NULL, &ls) == EO_OK && eo_csc_create(ctx, 1, 1, &A) == EO_OK,
          "scripted solver");
    A->colptr[1] = 1;
    A->rowind[0] = 0;
    A->val[0] = 1;
    CHECK(eo_linsolve_analyze(ls, A) == EO_OK && eo_linsolve_factor(ls, A) == EO_OK, "analyze, factor");
    double b = 1, x = 0;
    /* g: gradient norms; a: accepted step lengths; d: decrements; its: iterations of each solve */
    const double g[] = {1, 0.9, 0.5, 0.1, 0.08, 0.07};
    const double a[] = {0.5, 1, 1, 0.5, 1};
    const double d[] = {1, 0.9, 0.05, 0.04, 0.03};
    const int its[] = {3, 5, 4, 50, 50}; /* the 50 after direction 3 (ew2) does not count */
    double eta[6];
    eo_inexact s;
    eo_inexact_begin(&s, EO_FORCING_AUTO, 0.5, 0.9, 2, 0, 0.9);
    for (int k = 0; k < 6; k++) {
        eta[k] = eo_inexact_before(&s, ls, g[k]);
        CHECK(script_rtol == eta[k], "direction %d: the solver got eta %g (%g)", k, eta[k], script_rtol);
        if (k == 5) break;
        script_iters = its[k];
        eo_linsolve_solve(ls, &b, &x);
        eo_inexact_after(&s, g[k], NAN, a[k], d[k]);
    }
    printf("auto forcing: eta %g %g %g %g %g %g\n", eta[0], eta[1], eta[2], eta[3], eta[4], eta[5]);
    CHECK(eta[0] == 0.5, "first direction: eta0 (%g)", eta[0]);
    CHECK(eta[1] == 1e-4, "after a damped step: eta_global (%g)", eta[1]);
    CHECK(eta[2] == 1e-4, "full step but the decrement fell only to 0.9 of the one before: eta_global (%g)",
          eta[2]);
    const double ew = 0.9 * (0.1 / 0.5) * (0.1 / 0.5);
    CHECK(fabs(eta[3] - ew) < 1e-15, "full step, decrement fell 18x: ew2 %g (%g)", ew, eta[3]);
    CHECK(eta[4] == 1e-4, "after a damped step again: eta_global (%g)", eta[4]);
    const double ew5 = 0.9 * (0.07 / 0.08) * (0.07 / 0.08);
    CHECK(fabs(eta[5] - ew5) < 1e-15,
          "the guarded solve took 50 > 20 iterations: ew2 from here on although the last step was damped "
          "(%g, expected %g)",
          eta[5], ew5);
    eo_csc_destroy(&A);
    eo_linsolve_destroy(&ls);
    eo_test_ctx_done(&ctx);
}

static void test_values(void)
{
    eo_forcing_params p;
    eo_forcing_params_default(&p);
    CHECK(p.gamma == 0.9 && p.alpha == 2 && p.eta0 == 0.5 && p.eta_max == 0.9, "defaults");
    CHECK(eo_forcing_eta(&p, 0, 3, 7, 0.1) == 0.5, "k = 0 gives eta0");
    /* choice 2: 0.9 (0.1)^2 = 0.009; safeguard (a) inactive: 0.9 * 0.01^2 < 0.1 */
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.01), 0.009, 1e-15);
    /* (a): eta_prev = 0.5: 0.9 * 0.25 = 0.225 > 0.1 replaces 0.009 */
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.5), 0.225, 1e-15);
    /* (a) only raises: raw 0.9 (0.5)^2 = 0.225 vs floor 0.9 * 0.4^2 = 0.144 */
    CHECK_CLOSE(eo_forcing_eta(&p, 2, 0.5, 1, 0.4), 0.225, 1e-15);
    /* (b): growth of the gradient caps at eta_max */
    CHECK(eo_forcing_eta(&p, 2, 2, 1, 0.1) == 0.9, "eta_max");
    /* (c): gtol = 1e-6, |g| = 1e-6: 0.5 gtol/|g| = 0.5 > raw 0.9e-6 */
    p.gtol = 1e-6;
    CHECK_CLOSE(eo_forcing_eta(&p, 5, 1e-6, 1e-3, 0.01), 0.5, 1e-15);
    CHECK_CLOSE(eo_forcing_eta(&p, 5, 1e-3, 1e-2, 0.01), 0.009, 1e-15); /* (c) inactive: 5e-4 < 0.009 */
    p.gtol = 0;
    /* (d) */
    p.eta_min = 0.05;
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.01), 0.05, 1e-15);
    p.eta_min = 0;
    /* alpha = golden ratio (choice 2 with the other exponent of the paper) */
    p.alpha = (1 + sqrt(5.0)) / 2;
    CHECK_CLOSE(eo_forcing_eta(&p, 3, 1e-2, 1e-1, 0.01), 0.9 * pow(0.1, p.alpha), 1e-14);
    eo_forcing_params_default(&p);
    /* non-finite or zero norms: a safe loose solve */
    CHECK(eo_forcing_eta(&p, 2, NAN, 1, 0.1) == 0.9 && eo_forcing_eta(&p, 2, 1, 0, 0.1) == 0.9 &&
              eo_forcing_eta(&p, 2, INFINITY, 1, 0.1) == 0.9,
          "non-finite norms give eta_max");
    CHECK(eo_forcing_eta(&p, 2, 0, 1, 0.1) == 0, "zero gradient: raw 0 stays 0 (nothing to solve)");
}

/* inexact Newton on F(x) = e^x − 1 from x = 2; constant eta if eta_const > 0 */
static int run(double eta_const, double *F, double *eta)
{
    eo_forcing_params p;
    eo_forcing_params_default(&p);
    double x = 2, f = exp(x) - 1, fprev = 0, e = 0;
    int k = 0;
    F[0] = fabs(f);
    for (; k < 60 && fabs(f) > 1e-14; k++) {
        e = eta_const > 0 ? eta_const : eo_forcing_eta(&p, k, fabs(f), fabs(fprev), e);
        eta[k] = e;
        double s = -f * (1 - e) / exp(x); /* F'(x) s + F = e F: relative residual exactly e */
        fprev = f;
        x += s;
        f = exp(x) - 1;
        F[k + 1] = fabs(f);
    }
    return k;
}

static void test_order(void)
{
    double F[64], eta[64];
    int k = run(0, F, eta);
    CHECK(k <= 10, "Eisenstat-Walker inexact Newton: %d iterations to |F| <= 1e-14", k);
    double q1 = log(F[k - 1] / F[k - 2]) / log(F[k - 2] / F[k - 3]);
    double q2 = log(F[k - 2] / F[k - 3]) / log(F[k - 3] / F[k - 4]);
    CHECK(q1 > 1.8 && q2 > 1.8, "order -> 2: %.3f %.3f", q2, q1);
    CHECK(eta[0] == 0.5 && eta[k - 1] < 1e-6, "eta from %g down to %g", eta[0], eta[k - 1]);
    int mono = 1;
    for (int i = 1; i < k; i++) mono &= eta[i] <= eta[i - 1];
    CHECK(mono, "eta decreases monotonically on this convex problem");
    int kc = run(0.1, F, eta);
    double r = F[kc] / F[kc - 1], rp = F[kc - 1] / F[kc - 2];
    double qc = log(F[kc - 1] / F[kc - 2]) / log(F[kc - 2] / F[kc - 3]);
    CHECK(kc > k + 3 && qc < 1.2 && fabs(rp - 0.1) < 0.01, "constant eta 0.1: %d iterations, order %.3f, rate %g %g",
          kc, qc, rp, r);
}

int main(void)
{
    test_values();
    test_order();
    test_auto_guard();
    return eo_test_finish("test_forcing");
}
