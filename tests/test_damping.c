/* Damping everywhere (suite 'engine'): global viscous damping γ (a = (f − γv)/m) and
 * Rayleigh damping C = αM + βK₀ (K₀ the clamped elastic Hessian at the start of the
 * step) in explicit and implicit integrators.
 *
 *  - log decrement of a damped spring (mesh.points: vertex 0 fixed, mass m = 2 on a
 *    spring k = 8 along x, ω = 2, u(t) = (v₀/ω_d) e^{−ζωt} sin ω_d t): successive
 *    displacement maxima (parabolic interpolation) decay by exactly e^{−δ},
 *    δ = 2πζ/√(1 − ζ²), with ζ = γ/(2√(km)) (viscous), α/(2ω) (Rayleigh α), βω/2
 *    (Rayleigh β), each ζ = 0.05: measured δ within 0.1% for rk4, newmark,
 *    implicit_midpoint, bdf2 and within 0.2% for verlet and both symplectic Eulers at
 *    h = T/400; backward Euler adds its own numerical damping (δ larger);
 *  - FD check (central differences, step sweep) of the step objective's gradient and
 *    Hessian with all three dampings on a tet cantilever, consistent and lumped mass,
 *    for backward_euler, newmark, implicit_midpoint and bdf2 (after its start step);
 *  - a rigid translation of a free tet cube (consistent mass) under Rayleigh damping
 *    (K₀v = 0: only αM acts) decays by each method's exact amplification of z = −αh
 *    (backward Euler, Newmark, implicit midpoint with β = 0.01 too; rk4 at a step its
 *    elastic modes allow) to 1e-10, undeformed;
 *  - `static` with damping is a config error naming the key. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

static const double PI = 3.14159265358979323846;

static const char *spring =
    "{\"mesh\": {\"points\": [[0, 0, 0], [1, 0, 0]]},"
    " \"point_mass\": 2, \"gravity\": [0, 0, 0],"
    " \"springs\": {\"edges\": \"list\", \"list\": [[0, 1]], \"k\": 8},"
    " \"boundary\": [{\"nearest\": [0, 0, 0], \"fixed\": true}],"
    " \"initial\": {\"velocity\": [0.1, 0, 0]},"
    " \"time\": {\"integrator\": \"newmark\", \"dt\": 0.01, \"steps\": 1},"
    " \"solver\": {\"tol\": 1e-28, \"max_iters\": 50}}";

/* Measured log decrement over the first `np` maxima of u = x₁ − 1. */
static double log_decrement(eo_ctx *ctx, const char *integrator, const char *damping, double dt, int np)
{
    char a[64], b[64];
    snprintf(a, sizeof a, "time.integrator=%s", integrator);
    snprintf(b, sizeof b, "time.dt=%.17g", dt);
    const char *ov[] = {a, b, damping, NULL};
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, NULL, spring, ov) < 0) {
        CHECK(0, "open %s %s", integrator, damping);
        eo_sim_destroy(&s);
        return NAN;
    }
    double u0 = 0, u1 = 0, peaks[16];
    int npk = 0;
    for (long k = 0; k < 200000 && npk < np; k++) {
        eo_sim_step_result r;
        if (eo_sim_step(s, &r) < 0 || r.reason < 0) break;
        double u2 = eo_step_x(eo_sim_step_problem(s))[3] - 1;
        if (k >= 2 && u1 > u0 && u1 >= u2) {
            double c = u2 - 2 * u1 + u0;
            peaks[npk++] = u1 - (u2 - u0) * (u2 - u0) / (8 * c);
        }
        u0 = u1;
        u1 = u2;
    }
    eo_sim_destroy(&s);
    CHECK(npk == np, "%s: %d peaks", integrator, npk);
    return npk == np ? log(peaks[0] / peaks[np - 1]) / (np - 1) : NAN;
}

static void test_decrement(eo_ctx *ctx)
{
    const double zeta = 0.05, omega = 2, delta = 2 * PI * zeta / sqrt(1 - zeta * zeta);
    const double dt = 2 * PI / omega / 400;
    const char *damp[3] = {"damping.viscous=0.4", "damping.rayleigh_alpha=0.2", "damping.rayleigh_beta=0.05"};
    const struct {
        const char *name;
        double tol;
    } integ[] = {{"rk4", 1e-3},     {"newmark", 1e-3},          {"implicit_midpoint", 1e-3}, {"bdf2", 1e-3},
                 {"verlet", 2e-3},  {"symplectic_euler", 2e-3}, {"symplectic_euler_x", 2e-3}};
    printf("log decrement, zeta = %.2f: theory %.6f\n", zeta, delta);
    for (int d = 0; d < 3; d++)
        for (size_t i = 0; i < sizeof integ / sizeof integ[0]; i++) {
            double m = log_decrement(ctx, integ[i].name, damp[d], dt, 6);
            printf("  %-26s %-18s delta %.6f (rel. error %+.2e)\n", damp[d], integ[i].name, m, m / delta - 1);
            CHECK(fabs(m / delta - 1) <= integ[i].tol, "%s %s: delta %g, theory %g", damp[d], integ[i].name, m, delta);
        }
    /* backward Euler: the damping plus its own numerical dissipation */
    double m = log_decrement(ctx, "backward_euler", damp[0], dt, 6);
    printf("  %-26s %-18s delta %.6f (rel. error %+.2e)\n", damp[0], "backward_euler", m, m / delta - 1);
    CHECK(m > delta && m < 1.5 * delta, "backward euler: %g vs %g", m, delta);
    /* undamped reference: no decay */
    m = log_decrement(ctx, "newmark", "damping.viscous=0", dt, 6);
    CHECK(fabs(m) < 1e-6, "undamped newmark: delta %g", m);
}

static void fd_check(eo_objective *obj, const double *x, double *gerr, double *herr)
{
    int n = obj->n;
    double *buf = calloc(6 * (size_t)n, sizeof(double));
    double *v = buf, *g0 = buf + n, *xp = buf + 2 * n, *gp = buf + 3 * n, *gm = buf + 4 * n, *Hv = buf + 5 * n;
    for (int i = 0; i < n; i++) v[i] = eo_test_rand(-1, 1);
    double f0, fp, fm;
    eo_objective_gradient(obj, x, &f0, g0);
    eo_csc *H;
    eo_objective_hessian(obj, x, EO_PROJ_NONE, &H);
    eo_csc_symv(H, v, Hv);
    double dg = 0, nhv = 0;
    for (int i = 0; i < n; i++) {
        dg += g0[i] * v[i];
        nhv += Hv[i] * Hv[i];
    }
    nhv = sqrt(nhv);
    *gerr = *herr = INFINITY;
    for (int e = 2; e <= 9; e++) {
        double eps = pow(10.0, -e);
        for (int i = 0; i < n; i++) xp[i] = x[i] + eps * v[i];
        eo_objective_gradient(obj, xp, &fp, gp);
        for (int i = 0; i < n; i++) xp[i] = x[i] - eps * v[i];
        eo_objective_gradient(obj, xp, &fm, gm);
        *gerr = fmin(*gerr, fabs((fp - fm) / (2 * eps) - dg) / fabs(dg));
        double d2 = 0;
        for (int i = 0; i < n; i++) {
            double d = (gp[i] - gm[i]) / (2 * eps) - Hv[i];
            d2 += d * d;
        }
        *herr = fmin(*herr, sqrt(d2) / nhv);
    }
    free(buf);
}

static void test_fd(eo_ctx *ctx)
{
    const char *integ[4] = {"backward_euler", "newmark", "implicit_midpoint", "bdf2"};
    const char *mass[2] = {"mass=consistent", "mass=lumped"};
    for (int i = 0; i < 4; i++)
        for (int m = 0; m < 2; m++) {
            char a[64];
            snprintf(a, sizeof a, "time.integrator=%s", integ[i]);
            const char *ov[] = {a, mass[m], "mesh.generate.cells=[4,1,1]", "damping.viscous=3", "damping.rayleigh_alpha=2",
                                "damping.rayleigh_beta=1e-3", "initial.velocity=[0.1,0.2,-0.3]", NULL};
            eo_sim *s = NULL;
            if (eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) < 0) {
                CHECK(0, "open");
                eo_sim_destroy(&s);
                continue;
            }
            eo_sim_step(s, NULL); /* a deformed, moving state (bdf2: with history) */
            eo_sim_step(s, NULL);
            eo_objective *obj = eo_test_sim_obj(s);
            int n = obj->n;
            double *x = malloc((size_t)n * sizeof(double)), ge, he;
            eo_test_seed(11);
            for (int k = 0; k < n; k++) x[k] = eo_test_sim_guess(s)[k] + 1e-3 * eo_test_rand(-1, 1);
            fd_check(obj, x, &ge, &he);
            printf("  FD %-18s %-16s gradient %.2e, Hessian %.2e\n", integ[i], mass[m], ge, he);
            CHECK(ge < 1e-7 && he < 1e-6, "FD %s %s: gradient %g, Hessian %g", integ[i], mass[m], ge, he);
            free(x);
            eo_sim_destroy(&s);
        }
}

/* Rayleigh damping of a rigid translation of a tet mesh (free cube, no gravity, v₀
 * uniform): K₀ v = 0, so only αM acts and every vertex obeys v' = −αv. One step of
 * each method multiplies v by its own amplification of z = −αh exactly: backward Euler
 * 1/(1 − z), Newmark and implicit midpoint (1 + z/2)/(1 − z/2), rk4 Σ_{k≤4} z^k/k!
 * (consistent mass through the CHOLMOD solve), and the cube stays undeformed. */
static void test_rigid_decay(eo_ctx *ctx)
{
    const double alpha = 3;
    const double zi = -alpha * 0.01, ze = -alpha * 1e-4; /* implicit h = 0.01; rk4 h = 1e-4 (stable for the
                                                            cube's elastic modes, which rounding excites) */
    const struct {
        const char *name;
        double R, h;
    } tab[] = {{"backward_euler", 1 / (1 - zi), 0.01},
               {"newmark", (1 + zi / 2) / (1 - zi / 2), 0.01},
               {"implicit_midpoint", (1 + zi / 2) / (1 - zi / 2), 0.01},
               {"rk4", 1 + ze + ze * ze / 2 + ze * ze * ze / 6 + ze * ze * ze * ze / 24, 1e-4}};
    for (int i = 0; i < 4; i++) {
        char a[64], dt[64];
        snprintf(a, sizeof a, "time.integrator=%s", tab[i].name);
        snprintf(dt, sizeof dt, "time.dt=%g", tab[i].h);
        const int implicit = i < 3;
        const char *ov[] = {a, dt, "gravity=[0,0,0]", "damping.rayleigh_alpha=3", "initial.velocity=[0.3,-0.2,0.1]",
                            "solver.tol=1e-24", implicit ? "damping.rayleigh_beta=0.01" : NULL, NULL};
        eo_sim *s = NULL;
        if (eo_test_sim_open(&s, ctx, "freefall", NULL, ov) < 0) {
            CHECK(0, "open freefall");
            eo_sim_destroy(&s);
            continue;
        }
        const int N = 20;
        for (int k = 0; k < N; k++) eo_sim_step(s, NULL);
        const eo_step *st = eo_sim_step_problem(s);
        const double *v = eo_step_v(st), *x = eo_step_x(st), *X = eo_step_mesh(st)->X;
        const double v0[3] = {0.3, -0.2, 0.1}, f = pow(tab[i].R, N);
        double ev = 0, shape = 0;
        for (int j = 0; j < 3 * eo_step_mesh(st)->nv; j++) {
            ev = fmax(ev, fabs(v[j] - f * v0[j % 3]));
            shape = fmax(shape, fabs((x[j] - X[j]) - (x[j % 3] - X[j % 3])));
        }
        printf("  rigid decay %-18s v/v0 = %.12f (R^N = %.12f, e^-at = %.6f), max |v - R^N v0| %.1e, deformation %.1e\n",
               tab[i].name, v[0] / v0[0], f, exp(-alpha * tab[i].h * N), ev, shape);
        CHECK(ev < 1e-10 && shape < 1e-10, "%s: velocity error %g, deformation %g", tab[i].name, ev, shape);
        eo_sim_destroy(&s);
    }
}

static void test_errors(eo_ctx *ctx)
{
    const char *ov[] = {"time.integrator=static", "damping.viscous=1", NULL};
    eo_sim *s = NULL;
    eo_ctx_set_logger(ctx, NULL, NULL, EO_LOG_ERROR);
    CHECK(eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) == EO_ERR_INVALID, "static + damping rejected");
    CHECK(strstr(eo_ctx_message(ctx), "damping") != NULL, "message names the key: %s", eo_ctx_message(ctx));
    eo_sim_destroy(&s);
    const char *ov2[] = {"damping.viscous=-1", NULL};
    CHECK(eo_test_sim_open(&s, ctx, "cantilever", NULL, ov2) == EO_ERR_RANGE, "negative damping rejected");
    eo_sim_destroy(&s);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    test_decrement(ctx);
    printf("FD with damping:\n");
    test_fd(ctx);
    test_rigid_decay(ctx);
    test_errors(ctx);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_damping");
}
