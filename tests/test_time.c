/* Implicit integrators posed as min g(x), the fixed-point optimizer (suite 'engine'),
 * on a single spring (mesh.points: vertex 0 fixed, vertex 1 of mass m on a spring of
 * stiffness k along x, ω = √(k/m); x₁(t) = 1 + (v₀/ω) sin ωt) through eo_sim:
 *
 *  - measured orders by step halving at T = 1 (error of (x, v) against the closed
 *    form, slope of the last halving within ±0.2): bdf2 2, implicit_midpoint 2,
 *    newmark 2, backward_euler 1;
 *  - energy ½mv² + ½k(l − L)²: implicit_midpoint conserves it to 1e-10 (relative, solver
 *    tolerance level) over 1000 steps of hω = 0.5; bdf2 dissipates it (E decreasing,
 *    E(T)/E₀ < 0.999) but less than backward_euler; newmark conserves it too;
 *  - bdf2 restart: the history (eo_sim_get_history / eo_sim_set_history) after 5 steps
 *    reproduces steps 6–10 exactly (1e-13); without it the restart takes the backward
 *    Euler start and differs;
 *  - fixed_point on the backward-Euler step: where h²k/m < 1 (h = 0.5/ω, 0.9/ω) it
 *    agrees with Newton's step to 1e-10 with both initializations; where h²k/m > 1
 *    (h = 1.1/ω, 2/ω) it stops with diverged_not_contracting within window + 2
 *    iterations, not at max_iters, having measured the ratio h²k/m = 1.21 to 1e-5
 *    (at hω = 2: ≥ 1); on a tet cantilever (consistent mass) it agrees with
 *    Newton at a step below 1/√ρ(M⁻¹K) and reports not contracting above. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

static const char *spring =
    "{\"mesh\": {\"points\": [[0, 0, 0], [1, 0, 0]]},"
    " \"point_mass\": 2, \"gravity\": [0, 0, 0],"
    " \"springs\": {\"edges\": \"list\", \"list\": [[0, 1]], \"k\": 8},"
    " \"boundary\": [{\"nearest\": [0, 0, 0], \"fixed\": true}],"
    " \"initial\": {\"velocity\": [0.1, 0, 0]},"
    " \"time\": {\"integrator\": \"bdf2\", \"dt\": 0.01, \"steps\": 1},"
    " \"solver\": {\"tol\": 1e-28, \"max_iters\": 50}}";
static const double OMEGA = 2.0, V0 = 0.1, MASS = 2, K = 8;

static eo_sim *open_spring(eo_ctx *ctx, const char *integrator, double dt, const char *extra1, const char *extra2)
{
    char a[64], b[64];
    snprintf(a, sizeof a, "time.integrator=%s", integrator);
    snprintf(b, sizeof b, "time.dt=%.17g", dt);
    const char *ov[] = {a, b, extra1, extra2, NULL};
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, NULL, spring, ov) < 0) {
        CHECK(0, "open spring %s", integrator);
        eo_sim_destroy(&s);
    }
    return s;
}

static double energy(const eo_sim *s)
{
    const double *x = eo_step_x(eo_sim_step_problem(s)), *v = eo_step_v(eo_sim_step_problem(s));
    double l = x[3] - x[0], vv = v[3] * v[3] + v[4] * v[4] + v[5] * v[5];
    return 0.5 * MASS * vv + 0.5 * K * (l - 1) * (l - 1);
}

/* error of (x₁, v₁) at T = N h */
static double run_error(eo_ctx *ctx, const char *integrator, int N)
{
    const double T = 1;
    eo_sim *s = open_spring(ctx, integrator, T / N, NULL, NULL);
    if (!s) return NAN;
    int ok = 1;
    for (int k = 0; k < N; k++) {
        eo_sim_step_result r;
        ok &= eo_sim_step(s, &r) == EO_OK && r.reason > 0;
    }
    CHECK(ok, "%s: every step converged", integrator);
    const double *x = eo_step_x(eo_sim_step_problem(s)), *v = eo_step_v(eo_sim_step_problem(s));
    double ex = 1 + V0 / OMEGA * sin(OMEGA * T), ev = V0 * cos(OMEGA * T);
    double e = hypot(x[3] - ex, (v[3] - ev) / OMEGA);
    eo_sim_destroy(&s);
    return e;
}

static void test_orders(eo_ctx *ctx)
{
    const struct {
        const char *name;
        int order;
    } tab[] = {{"bdf2", 2}, {"implicit_midpoint", 2}, {"newmark", 2}, {"backward_euler", 1}};
    for (int i = 0; i < 4; i++) {
        double e[4];
        for (int r = 0; r < 4; r++) e[r] = run_error(ctx, tab[i].name, 20 << r);
        double slope = log2(e[2] / e[3]);
        printf("  %-18s errors %.3e %.3e %.3e %.3e  slope %.3f (order %d)\n", tab[i].name, e[0], e[1], e[2], e[3],
               slope, tab[i].order);
        CHECK(fabs(slope - tab[i].order) <= 0.2, "%s: measured order %.3f, expected %d", tab[i].name, slope,
              tab[i].order);
    }
}

static double energy_run(eo_ctx *ctx, const char *integrator, int N, double h, double *maxdev, int *monotone)
{
    eo_sim *s = open_spring(ctx, integrator, h, NULL, NULL);
    if (!s) return NAN;
    double e0 = energy(s), prev = e0, dev = 0;
    *monotone = 1;
    for (int k = 0; k < N; k++) {
        eo_sim_step(s, NULL);
        double e = energy(s);
        dev = fmax(dev, fabs(e - e0) / e0);
        if (e > prev * (1 + 1e-12)) *monotone = 0;
        prev = e;
    }
    *maxdev = dev;
    eo_sim_destroy(&s);
    return prev / e0;
}

static void test_energy(eo_ctx *ctx)
{
    const double h = 0.5 / OMEGA;
    const int N = 1000;
    double dev, ratio_bdf2, ratio_be, ratio;
    int mono;
    ratio = energy_run(ctx, "implicit_midpoint", N, h, &dev, &mono);
    printf("  implicit_midpoint  h w = 0.5, %d steps: max |E - E0|/E0 = %.3e\n", N, dev);
    CHECK(dev < 1e-10, "implicit midpoint conserves the quadratic energy: %g", dev);
    energy_run(ctx, "newmark", N, h, &dev, &mono);
    printf("  newmark            max |E - E0|/E0 = %.3e\n", dev);
    CHECK(dev < 1e-10, "newmark conserves it too: %g", dev);
    ratio_bdf2 = energy_run(ctx, "bdf2", N, h, &dev, &mono);
    printf("  bdf2               E(T)/E0 = %.3e (monotone %d)\n", ratio_bdf2, mono);
    CHECK(ratio_bdf2 < 0.999 && mono, "bdf2 dissipates: %g", ratio_bdf2);
    ratio_be = energy_run(ctx, "backward_euler", N, h, &dev, &mono);
    printf("  backward_euler     E(T)/E0 = %.3e\n", ratio_be);
    CHECK(ratio_be < ratio_bdf2, "bdf2 dissipates less than backward Euler: %g vs %g", ratio_bdf2, ratio_be);
    (void)ratio;
}

static void test_history(eo_ctx *ctx)
{
    eo_sim *s = open_spring(ctx, "bdf2", 0.05, NULL, NULL), *n = open_spring(ctx, "newmark", 0.05, NULL, NULL);
    if (!s || !n) {
        eo_sim_destroy(&s);
        eo_sim_destroy(&n);
        return;
    }
    CHECK(eo_sim_history_len(n) == 0, "newmark keeps no history");
    double hdummy[1];
    CHECK(eo_sim_get_history(n, hdummy) == EO_ERR_UNSUPPORTED, "newmark: get_history unsupported");
    const size_t len = eo_sim_history_len(s);
    CHECK(len == 2 * 6 + 1, "bdf2 history length %zu", len);
    double hist[13], x5[6], v5[6], t5, x10[6], x10b[6];
    int i5;
    CHECK(eo_sim_get_history(s, hist) == EO_OK && hist[12] == 0, "no valid history at the start");
    for (int k = 0; k < 5; k++) eo_sim_step(s, NULL);
    eo_sim_get_state(s, x5, v5, &t5, &i5);
    CHECK(eo_sim_get_history(s, hist) == EO_OK && hist[12] == 1, "valid history after 5 steps");
    for (int k = 0; k < 5; k++) eo_sim_step(s, NULL);
    eo_sim_get_state(s, x10, NULL, NULL, NULL);
    /* restart from step 5 with the history: identical */
    eo_sim_reset(s);
    eo_sim_set_state(s, x5, v5, t5, i5);
    CHECK(eo_sim_set_history(s, hist) == EO_OK, "set history");
    for (int k = 0; k < 5; k++) eo_sim_step(s, NULL);
    eo_sim_get_state(s, x10b, NULL, NULL, NULL);
    CHECK(fabs(x10b[3] - x10[3]) <= 1e-13, "restart with history: %.17g vs %.17g", x10b[3], x10[3]);
    /* without: backward Euler start, different */
    eo_sim_set_state(s, x5, v5, t5, i5);
    for (int k = 0; k < 5; k++) eo_sim_step(s, NULL);
    eo_sim_get_state(s, x10b, NULL, NULL, NULL);
    printf("  bdf2 restart without history: x10 differs by %.3e\n", fabs(x10b[3] - x10[3]));
    CHECK(fabs(x10b[3] - x10[3]) > 1e-8, "restart without history differs: %g", fabs(x10b[3] - x10[3]));
    hist[12] = 0.5;
    CHECK(eo_sim_set_history(s, hist) == EO_ERR_RANGE, "bad valid flag");
    eo_sim_destroy(&s);
    eo_sim_destroy(&n);
}

/* The contraction ratio fixed_point logs when it stops as not contracting. */
static double logged_rho = NAN;
static void rho_logger(eo_log_level level, const char *msg, void *user)
{
    (void)level, (void)user;
    const char *p = strstr(msg, "contraction ratio ");
    if (p) logged_rho = strtod(p + strlen("contraction ratio "), NULL);
}

/* One backward-Euler step of the spring with `optimizer`; returns x₁ and the reason. */
static double be_step(eo_ctx *ctx, double h, const char *optimizer, const char *init, int *reason, int *iters)
{
    char o[64], in[64];
    snprintf(o, sizeof o, "solver.optimizer=%s", optimizer);
    snprintf(in, sizeof in, "solver.fixed_point.init=%s", init ? init : "previous");
    char dt[64];
    snprintf(dt, sizeof dt, "time.dt=%.17g", h);
    const char *ov[] = {"time.integrator=backward_euler", o, in, "solver.max_iters=1000", dt, "solver.fallback=[]", NULL};
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, NULL, spring, ov) < 0) {
        CHECK(0, "open spring");
        eo_sim_destroy(&s);
    }
    if (!s) return NAN;
    eo_sim_step_result r;
    CHECK(eo_sim_step(s, &r) == EO_OK, "step");
    *reason = r.reason;
    *iters = r.iterations;
    double x = eo_step_x(eo_sim_step_problem(s))[3];
    eo_sim_destroy(&s);
    return x;
}

static void test_fixed_point(eo_ctx *ctx)
{
    const double hw[4] = {0.5, 0.9, 1.1, 2.0};
    const char *inits[2] = {"previous", "predictor"};
    for (int i = 0; i < 4; i++) {
        const double h = hw[i] / OMEGA;
        int rn, itn;
        double xn = be_step(ctx, h, "newton", NULL, &rn, &itn);
        CHECK(rn > 0, "newton converges at h w = %g", hw[i]);
        for (int j = 0; j < 2; j++) {
            int rf, itf;
            logged_rho = NAN;
            eo_ctx_set_logger(ctx, rho_logger, NULL, EO_LOG_INFO);
            double xf = be_step(ctx, h, "fixed_point", inits[j], &rf, &itf);
            eo_ctx_set_logger(ctx, NULL, NULL, EO_LOG_ERROR);
            printf("  fixed_point h w = %.1f (h^2 k/m = %.2f) init %-9s: %s after %d iterations, |x - x_newton| = %.2e\n",
                   hw[i], hw[i] * hw[i], inits[j], eo_reason_name(rf), itf, fabs(xf - xn));
            if (hw[i] < 1) {
                CHECK(rf > 0, "converges below 1/omega: %s", eo_reason_name(rf));
                CHECK(fabs(xf - xn) <= 1e-10, "agrees with newton: %g", fabs(xf - xn));
            } else {
                CHECK(rf == EO_DIVERGED_NOT_CONTRACTING, "diverges above 1/omega: %s", eo_reason_name(rf));
                CHECK(itf <= 3 + 2, "stops early: %d iterations", itf);
                /* one moving coordinate: the update is multiplied by exactly −h²k/m while the
                 * spring stays linear (at hω = 2 from the predictor the iterates pass through
                 * the fixed end within the window: the spring flips, the ratio is only ≥ 1) */
                printf("    measured contraction ratio %.6g, h^2 k/m = %.6g\n", logged_rho, hw[i] * hw[i]);
                if (hw[i] < 1.5)
                    CHECK(fabs(logged_rho - hw[i] * hw[i]) <= 1e-5 * hw[i] * hw[i], "ratio %g vs h^2 k/m %g", logged_rho,
                          hw[i] * hw[i]);
                else
                    CHECK(logged_rho >= 1, "ratio %g", logged_rho);
            }
        }
    }
}

/* Tet cantilever (consistent mass, E = 1e5): fixed_point vs newton on the first
 * backward-Euler step. */
static void test_fixed_point_mesh(eo_ctx *ctx)
{
    const double dts[2] = {5e-5, 1e-4}; /* 1/√ρ(M⁻¹K) lies between them (E = 1e7, 6×2×2 cells) */
    for (int i = 0; i < 2; i++) {
        char dt[64];
        snprintf(dt, sizeof dt, "time.dt=%g", dts[i]);
        const char *ovn[] = {"mesh.generate.cells=[6,2,2]", "time.integrator=backward_euler", dt, "solver.tol=1e-24",
                             "solver.max_iters=2000", "initial.scale=[1.01,1,1]", NULL};
        const char *ovf[] = {"mesh.generate.cells=[6,2,2]", "time.integrator=backward_euler", dt, "solver.tol=1e-24",
                             "solver.max_iters=2000", "initial.scale=[1.01,1,1]", "solver.optimizer=fixed_point", "solver.fallback=[]", NULL};
        eo_sim *a = NULL, *b = NULL;
        if (eo_test_sim_open(&a, ctx, "cantilever", NULL, ovn) < 0 || eo_test_sim_open(&b, ctx, "cantilever", NULL, ovf) < 0) {
            CHECK(0, "open cantilever");
            eo_sim_destroy(&a);
            eo_sim_destroy(&b);
            return;
        }
        eo_sim_step_result ra, rb;
        eo_sim_step(a, &ra);
        eo_sim_step(b, &rb);
        const double *xa = eo_step_x(eo_sim_step_problem(a)), *xb = eo_step_x(eo_sim_step_problem(b)),
                     *x0 = eo_step_x0(eo_sim_step_problem(a));
        double d = 0, u = 0;
        for (int j = 0; j < 3 * eo_step_mesh(eo_sim_step_problem(a))->nv; j++) {
            d = fmax(d, fabs(xa[j] - xb[j]));
            u = fmax(u, fabs(xa[j] - x0[j]));
        }
        printf("  cantilever dt = %g: newton %s (%d), fixed_point %s (%d), max |dx| = %.2e (motion %.2e)\n", dts[i],
               eo_reason_name(ra.reason), ra.iterations, eo_reason_name(rb.reason), rb.iterations, d, u);
        if (i == 0) {
            CHECK(rb.reason > 0 && d <= 1e-10, "fixed_point agrees on the mesh: %s, %g", eo_reason_name(rb.reason), d);
        } else {
            CHECK(rb.reason == EO_DIVERGED_NOT_CONTRACTING && rb.iterations < 50, "not contracting on the mesh: %s",
                  eo_reason_name(rb.reason));
        }
        eo_sim_destroy(&a);
        eo_sim_destroy(&b);
    }
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    printf("orders on the spring (T = 1):\n");
    test_orders(ctx);
    printf("energy:\n");
    test_energy(ctx);
    printf("history:\n");
    test_history(ctx);
    printf("fixed point:\n");
    test_fixed_point(ctx);
    test_fixed_point_mesh(ctx);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_time");
}
