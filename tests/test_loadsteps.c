/* Quasi-static load stepping (suite 'engine'): time.integrator = static with
 * time.load_steps = L ramps gravity (λₖ = min(1, k/L)) and the prescribed motions
 * (evaluated at min(t, L·dt)) linearly, each increment a minimization.
 *
 *  - examples/cantilever_loadsteps.json: the clamped 1 × 0.1 × 0.1 m bar, E = 1e6 Pa,
 *    ν = 0.3, ρ = 1000 kg/m³ under its own weight (q = ρgA = 98.1 N/m,
 *    qL³/(EI) = 11.77): every increment converges, and the last one (full load) ends
 *    at the equilibrium of a single full-load solve (1e-5 m);
 *  - the tip deflection against the elastica of an inextensible Euler beam under a
 *    distributed dead load, EI φ'' = −q(L − s) cos φ, φ(0) = 0, φ'(L) = 0 (solved here
 *    by shooting; 0.738318 m; linear theory qL⁴/(8EI) = 1.47 m): the P1 tets lock, so
 *    the deflection is below the elastica and approaches it under refinement: 20×2×2
 *    and 30×3×3 cells inside the band [0.85, 1.0] of the elastica, the finer one
 *    closer;
 *  - a prescribed translation ramps linearly over the load steps and holds after;
 *  - load_steps with a dynamic integrator is a config error. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "engine_util.h"

/* Elastica tip deflection/L for K = qL³/(EI) (RK4 shooting on φ'(0), bisection). */
static void elastica_rhs(double K, double s, const double y[4], double f[4])
{
    f[0] = y[1];                          /* φ' */
    f[1] = -K * (1 - s) * cos(y[0]);      /* φ'' */
    f[2] = sin(y[0]);                     /* deflection */
    f[3] = cos(y[0]);
}
static void elastica_shoot(double K, double c0, double out[4])
{
    const int N = 4000;
    const double h = 1.0 / N;
    double y[4] = {0, c0, 0, 0}, k1[4], k2[4], k3[4], k4[4], t[4];
    for (int i = 0; i < N; i++) {
        double s = i * h;
        elastica_rhs(K, s, y, k1);
        for (int j = 0; j < 4; j++) t[j] = y[j] + 0.5 * h * k1[j];
        elastica_rhs(K, s + 0.5 * h, t, k2);
        for (int j = 0; j < 4; j++) t[j] = y[j] + 0.5 * h * k2[j];
        elastica_rhs(K, s + 0.5 * h, t, k3);
        for (int j = 0; j < 4; j++) t[j] = y[j] + h * k3[j];
        elastica_rhs(K, s + h, t, k4);
        for (int j = 0; j < 4; j++) y[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
    for (int j = 0; j < 4; j++) out[j] = y[j];
}
static double elastica_tip(double K)
{
    double lo = 0, hi = K / 2, y[4]; /* linear theory: φ'(0) = K/2 */
    for (int b = 0; b < 80; b++) {
        double mid = 0.5 * (lo + hi);
        elastica_shoot(K, mid, y);
        if (y[1] > 0) hi = mid;
        else lo = mid;
    }
    elastica_shoot(K, 0.5 * (lo + hi), y);
    return y[2];
}

static double run_tip(eo_ctx *ctx, const char *cells, const char *extra1, const char *extra2, int *all_converged,
                      int *iters)
{
    char c[64];
    snprintf(c, sizeof c, "mesh.generate.cells=%s", cells);
    const char *ov[] = {c, extra1, extra2, NULL};
    eo_sim *s = NULL;
    eo_cfg *cfg = NULL;
    int rc = eo_scene_cfg_load(ctx, eo_test_src_path("examples/cantilever_loadsteps.json"), NULL, &cfg);
    for (const char *const *o = ov; rc >= 0 && *o; o++) rc = eo_cfg_override(ctx, cfg, *o);
    if (rc >= 0) rc = eo_sim_create(ctx, cfg, &s);
    else eo_cfg_destroy(&cfg);
    if (rc < 0) {
        CHECK(0, "open example: %s", eo_ctx_message(ctx));
        return NAN;
    }
    *all_converged = 1;
    *iters = 0;
    for (int k = 0; k < eo_sim_scene(s)->time.steps; k++) {
        eo_sim_step_result r;
        rc = eo_sim_step(s, &r);
        *all_converged &= rc == EO_OK && r.reason > 0;
        *iters += r.iterations;
    }
    double tip = eo_test_tip_dz(s, 1.0 - 1e-9);
    eo_sim_destroy(&s);
    return tip;
}

static void test_cantilever(eo_ctx *ctx)
{
    const double E = 1e6, b = 0.1, L = 1, q = 1000 * 9.81 * b * b, I = b * b * b * b / 12, K = q * L * L * L / (E * I);
    const double ref = elastica_tip(K) * L;
    printf("elastica: qL^3/EI = %.4f, tip deflection %.6f m (linear %.4f m)\n", K, ref, q * L * L * L * L / (8 * E * I));
    CHECK(fabs(ref - 0.7383) < 1e-3, "elastica reference %g", ref);
    const char *cells[2] = {"[20,2,2]", "[30,3,3]"};
    double tip[2];
    for (int i = 0; i < 2; i++) {
        int ok, it;
        tip[i] = -run_tip(ctx, cells[i], NULL, NULL, &ok, &it);
        printf("  cells %-9s tip deflection %.6f m = %.4f x elastica, every increment converged %d (%d iterations)\n",
               cells[i], tip[i], tip[i] / ref, ok, it);
        CHECK(ok, "%s: every load step converged", cells[i]);
        CHECK(tip[i] / ref > 0.85 && tip[i] / ref < 1.0, "%s: within the P1 locking band: %g", cells[i], tip[i] / ref);
    }
    CHECK(tip[1] > tip[0], "closer under refinement: %g, %g", tip[0], tip[1]);
    /* the last increment carries the full load: the same equilibrium as one solve under
     * the full gravity (which Newton reaches here too, in more iterations) */
    int ok, it;
    double one = -run_tip(ctx, cells[0], "time.load_steps=0", "time.steps=1", &ok, &it);
    printf("  cells %-9s one full-load solve: tip %.6f m, converged %d (%d iterations)\n", cells[0], one, ok, it);
    CHECK(ok && fabs(one - tip[0]) < 1e-5, "full-load equilibrium %g vs load-stepped %g", one, tip[0]);
}

/* A prescribed translation under load stepping: L = 4 steps, then held. */
static void test_motion_ramp(eo_ctx *ctx)
{
    const char *ov[] = {"time.integrator=static", "time.load_steps=4", "time.steps=6", "time.dt=0.5", "gravity=[0,0,0]",
                        "mesh.generate.cells=[4,1,1]",
                        "boundary=[{\"box\": [[-1,-1,-1],[0,1,1]], \"fixed\": true},"
                        " {\"box\": [[1,-1,-1],[2,1,1]], \"translate\": [0.02, 0, 0]}]",
                        NULL};
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) < 0) {
        CHECK(0, "open");
        eo_sim_destroy(&s);
        return;
    }
    for (int k = 1; k <= 6; k++) {
        eo_sim_step(s, NULL);
        const eo_step *st = eo_sim_step_problem(s);
        const eo_mesh *m = eo_step_mesh(st);
        int v = -1;
        for (int j = 0; j < m->nv && v < 0; j++)
            if (m->X[3 * j] >= 1 - 1e-9) v = j;
        double ux = eo_step_x(st)[3 * v] - m->X[3 * v], expect = 0.02 * 0.5 * (k < 4 ? k : 4);
        CHECK(fabs(ux - expect) < 1e-12, "step %d: end displacement %g, expected %g", k, ux, expect);
    }
    eo_sim_destroy(&s);
}

static void test_errors(eo_ctx *ctx)
{
    const char *ov[] = {"time.integrator=newmark", "time.load_steps=3", NULL};
    eo_sim *s = NULL;
    CHECK(eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) == EO_ERR_INVALID, "load_steps with newmark rejected");
    CHECK(strstr(eo_ctx_message(ctx), "load_steps") != NULL, "message names the key: %s", eo_ctx_message(ctx));
    eo_sim_destroy(&s);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    test_cantilever(ctx);
    test_motion_ramp(ctx);
    test_errors(ctx);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_loadsteps");
}
