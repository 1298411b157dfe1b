/* Explicit integrators (suite 'unit'): each registered explicit integrator's
 * explicit_step op on the 1-D harmonic oscillator x'' = −ω²x (an eo_ode of n = 1) and on
 * the Dahlquist test equation y' = λy (as v' = λv):
 *
 *  - convergence order: error at T = 1 of x(t) = cos ωt (ω = 1) for h = T/N over four
 *    halvings; the measured slope log₂(e(h)/e(h/2)) of the last pair must lie within
 *    ±0.2 of the order (forward/symplectic Euler 1, Heun, midpoint, Verlet, leapfrog 2,
 *    RK4 4);
 *  - stability (Dahlquist): forward Euler on the undamped oscillator multiplies the
 *    energy ½(v² + ω²x²) by exactly 1 + h²ω² per step; symplectic Euler and Verlet keep
 *    it within O(hω), O(h²ω²) of E₀ over 10⁴ steps; RK4 decays for hω = 2.7 and 2.8
 *    (below 2√2) and blows up for hω = 2.9; forward Euler on v' = λv is exactly
 *    (1 + hλ)ⁿ: decays for hλ = −1.9, grows for hλ = −2.1;
 *  - every integrator that declares explicit_step is covered (the table is checked
 *    against the registry). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "elastopt/step.h"
#include "testutil.h"

typedef struct osc {
    double w2;      /* ω² (oscillator) */
    double lambda;  /* λ (Dahlquist, on v) */
    int dahlquist;
    long evals;
} osc;

static int accel(void *data, double t, const double *x, const double *v, double *a)
{
    (void)t;
    osc *o = data;
    o->evals++;
    a[0] = o->dahlquist ? o->lambda * v[0] : -o->w2 * x[0];
    return EO_OK;
}

static const eo_integrator_type *find(const char *name)
{
    const void *t = NULL;
    eo_registry_find(NULL, EO_KIND_INTEGRATOR, name, &t);
    return t;
}

/* Integrate N steps of h from (x0, v0); returns the final state. */
static void integrate(const eo_integrator_type *it, osc *o, double h, long N, double *x, double *v,
                      double *emax_dev)
{
    double work[16] = {0};
    eo_ode ode = {.n = 1, .data = o, .accel = accel};
    double e0 = 0.5 * (v[0] * v[0] + o->w2 * x[0] * x[0]);
    if (emax_dev) *emax_dev = 0;
    for (long k = 0; k < N; k++) {
        it->explicit_step(&ode, k * h, h, x, v, work, k == 0);
        if (emax_dev) {
            double e = 0.5 * (v[0] * v[0] + o->w2 * x[0] * x[0]);
            if (fabs(e - e0) / e0 > *emax_dev) *emax_dev = fabs(e - e0) / e0;
        }
    }
}

static const struct {
    const char *name;
    int order;
    int N0; /* coarsest N: the last halving is in the asymptotic range */
} table[] = {
    {"forward_euler", 1, 400}, {"symplectic_euler", 1, 400}, {"heun", 2, 100}, {"midpoint", 2, 100},
    {"rk4", 4, 10},            {"verlet", 2, 100},          {"leapfrog", 2, 100},
    {"symplectic_euler_x", 1, 400},
};
enum { NT = sizeof table / sizeof table[0] };

static void test_orders(void)
{
    for (int m = 0; m < NT; m++) {
        const eo_integrator_type *it = find(table[m].name);
        CHECK(it && it->explicit_step, "%s registered as explicit", table[m].name);
        if (!it || !it->explicit_step) continue;
        CHECK(it->work_vectors <= 16, "%s work", table[m].name);
        double err[4];
        for (int r = 0; r < 4; r++) {
            long N = (long)table[m].N0 << r;
            osc o = {.w2 = 1};
            double x = 1, v = 0;
            integrate(it, &o, 1.0 / N, N, &x, &v, NULL);
            err[r] = hypot(x - cos(1.0), v + sin(1.0));
        }
        double slope = log2(err[2] / err[3]);
        printf("  %-17s errors %.3e %.3e %.3e %.3e  slope %.3f (order %d)\n", table[m].name, err[0], err[1], err[2],
               err[3], slope, table[m].order);
        CHECK(fabs(slope - table[m].order) <= 0.2, "%s: measured order %.3f, expected %d", table[m].name, slope,
              table[m].order);
    }
    /* every registered explicit integrator is in the table */
    for (const void *const *t = eo_registry_list(EO_KIND_INTEGRATOR); *t; t++) {
        const eo_integrator_type *it = *t;
        if (!it->explicit_step) continue;
        int found = 0;
        for (int m = 0; m < NT; m++) found |= strcmp(table[m].name, it->info.name) == 0;
        CHECK(found, "explicit integrator %s has no order test", it->info.name);
    }
}

static void test_stability(void)
{
    /* forward Euler gains exactly (1 + h²ω²) per step */
    {
        osc o = {.w2 = 4};
        double h = 0.05, x = 1, v = 0, dev;
        long N = 100;
        integrate(find("forward_euler"), &o, h, N, &x, &v, &dev);
        double e = 0.5 * (v * v + o.w2 * x * x), e0 = 0.5 * o.w2;
        double expect = pow(1 + h * h * o.w2, (double)N);
        printf("  forward_euler energy ratio %.12g (analytic %.12g)\n", e / e0, expect);
        CHECK(e / e0 > 1.5, "forward Euler gains energy: ratio %g", e / e0);
        CHECK_CLOSE(e / e0, expect, 1e-10);
    }
    /* symplectic Euler, Verlet, leapfrog: bounded over 10⁴ steps, no drift */
    const struct {
        const char *name;
        double bound;
    } sym[] = {{"symplectic_euler", 0.11}, {"verlet", 0.003}, {"leapfrog", 0.003}, {"symplectic_euler_x", 0.11}};
    for (int i = 0; i < 4; i++) {
        osc o = {.w2 = 1};
        double h = 0.1, x = 1, v = 0, dev;
        integrate(find(sym[i].name), &o, h, 10000, &x, &v, &dev);
        double e = 0.5 * (v * v + x * x);
        printf("  %-17s max |E - E0|/E0 over 1e4 steps (h w = 0.1): %.3e, final %.3e\n", sym[i].name, dev,
               fabs(e - 0.5) / 0.5);
        CHECK(dev < sym[i].bound, "%s energy deviation %g", sym[i].name, dev);
        /* bounded, not drifting: the largest deviation over the last 1000 of 10⁴ steps
         * equals that over the first 1000 (within 1%) */
        {
            const eo_integrator_type *it = find(sym[i].name);
            double work[16] = {0}, xs = 1, vs = 0, d_first = 0, d_last = 0;
            osc o3 = {.w2 = 1};
            eo_ode ode = {.n = 1, .data = &o3, .accel = accel};
            for (long k = 0; k < 10000; k++) {
                it->explicit_step(&ode, k * h, h, &xs, &vs, work, k == 0);
                double d = fabs(0.5 * (vs * vs + xs * xs) - 0.5) / 0.5;
                if (k < 1000 && d > d_first) d_first = d;
                if (k >= 9000 && d > d_last) d_last = d;
            }
            printf("  %-17s max deviation steps 0-999 %.6e, 9000-9999 %.6e\n", sym[i].name, d_first, d_last);
            CHECK(d_last <= 1.01 * d_first, "%s drifts: first %g, last %g", sym[i].name, d_first, d_last);
        }
    }
    /* the non-symplectic second-order methods drift for comparison (Heun gains) */
    {
        osc o = {.w2 = 1};
        double x = 1, v = 0, dev;
        integrate(find("heun"), &o, 0.1, 10000, &x, &v, &dev);
        CHECK(0.5 * (v * v + x * x) > 0.5 * 1.2, "heun drifts upward: E = %g", 0.5 * (v * v + x * x));
    }
    /* RK4 stability limit 2√2 on the imaginary axis */
    const double hw[3] = {2.7, 2.8, 2.9};
    for (int i = 0; i < 3; i++) {
        osc o = {.w2 = 1};
        double x = 1, v = 0;
        integrate(find("rk4"), &o, hw[i], 1000, &x, &v, NULL);
        double e = 0.5 * (v * v + x * x);
        printf("  rk4 h w = %.1f: E/E0 after 1000 steps %.3e\n", hw[i], e / 0.5);
        if (hw[i] < 2 * sqrt(2.0))
            CHECK(e < 0.5, "rk4 stable at h w = %g: E = %g", hw[i], e);
        else
            CHECK(e > 1e100 || !isfinite(e), "rk4 unstable at h w = %g: E = %g", hw[i], e);
    }
    /* Dahlquist y' = λy, forward Euler: yₙ = (1 + hλ)ⁿ y₀ */
    const double hl[2] = {-1.9, -2.1};
    for (int i = 0; i < 2; i++) {
        osc o = {.dahlquist = 1, .lambda = hl[i]};
        double x = 0, v = 1, work[4];
        eo_ode ode = {.n = 1, .data = &o, .accel = accel};
        for (int k = 0; k < 200; k++) find("forward_euler")->explicit_step(&ode, k, 1.0, &x, &v, work, k == 0);
        double expect = pow(1 + hl[i], 200);
        CHECK(fabs(v - expect) <= 1e-12 * fabs(expect), "v = %g, (1 + h lambda)^200 = %g", v, expect);
        if (hl[i] > -2)
            CHECK(fabs(v) < 1e-3, "h lambda = %g decays: %g", hl[i], v);
        else
            CHECK(fabs(v) > 10, "h lambda = %g grows: %g", hl[i], v);
    }
    /* force evaluations per step: leapfrog 1 (after the first), verlet 2, rk4 4 */
    const struct {
        const char *name;
        long evals;
    } ev[] = {{"leapfrog", 11}, {"verlet", 20}, {"rk4", 40}, {"forward_euler", 10}, {"heun", 20}};
    for (int i = 0; i < 5; i++) {
        osc o = {.w2 = 1};
        double x = 1, v = 0;
        integrate(find(ev[i].name), &o, 0.1, 10, &x, &v, NULL);
        CHECK(o.evals == ev[i].evals, "%s: %ld force evaluations for 10 steps, expected %ld", ev[i].name, o.evals,
              ev[i].evals);
    }
}

int main(void)
{
    printf("convergence orders on x'' = -x, T = 1:\n");
    test_orders();
    printf("stability:\n");
    test_stability();
    return eo_test_finish("test_integrators");
}
