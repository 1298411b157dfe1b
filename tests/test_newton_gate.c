/* The decrement-estimate gate of Newton (suite 'engine', solver.newton.estimate_gate,
 * solvers/optim/newton.c): after a full step Newton may test the stopping rule with the
 * decrement estimated from the previous factor (one solve); the gate skips that solve
 * where the rule cannot plausibly pass (the quadratic-phase prediction of the decrement,
 * divided by the gate's safety factor, and the last decrement itself both fail the rule).
 *
 * Per scene (built-in, Newton, 1-10 steps), the same steps run twice from the same initial
 * state, gate off (estimate_gate = 0: the estimate after every full step) and on (10,
 * the default):
 *  1. the gate changes no iterate: after every step max|x_on − x_off| ≤ 1e-9·max(1, |x|)
 *     (measured: 0, the same iterates bit for bit), the same accepted iterations and
 *     every step converged in both; a skipped estimate that would have passed costs one
 *     more factorization at the same x (no iteration), so over all steps the
 *     factorizations may grow by at most one per ten steps (measured: none);
 *  2. the solves drop (the solver profile's n_solve; each direction is one solve, each
 *     tried estimate one more): by at least 25% over the scenes (measured 374 -> 277,
 *     factorizations 189 -> 189; the k = 1 estimate is always tried: gating it by the
 *     previous step's first ratio dropped 34%, but made a step depend on the steps
 *     before it, and a restarted run differ from an uninterrupted one), and
 *     on the linearly converging `inverted` scene (about 26 iterations per step) to at
 *     most 3 estimates per step (measured 157 solves for 79 directions -> 85); no scene
 *     gets more solves. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

typedef struct run_out {
    long n_solve, n_factor;
    int iters, converged;
} run_out;

static int run(const char *scene, const char *stop, const char *gate, int steps, double **xs, int *n,
               run_out *o)
{
    eo_ctx *ctx = eo_test_ctx();
    char g[64], st[64];
    snprintf(g, sizeof g, "solver.newton.estimate_gate=%s", gate);
    snprintf(st, sizeof st, "solver.stop=%s", stop);
    const char *ov[] = {"solver.optimizer=newton", st, g, NULL};
    eo_sim *s = NULL;
    int rc = eo_test_sim_open(&s, ctx, scene, NULL, ov);
    CHECK(rc == 0, "%s: open (%s)", scene, gate);
    if (rc) {
        eo_test_ctx_done(&ctx);
        return -1;
    }
    *o = (run_out){0, 0, 0, 0};
    int nx = 0;
    for (int k = 0; k < steps; k++) {
        eo_sim_step_result r;
        rc = eo_sim_step(s, &r);
        CHECK(rc == EO_OK, "%s step %d: rc %d", scene, k, rc);
        if (rc) break;
        o->iters += r.iterations;
        o->converged += r.reason > 0;
        if (!nx) {
            nx = 3 * eo_sim_scene(s)->mesh->nv; /* positions of every vertex */
            *xs = realloc(*xs, (size_t)steps * (size_t)nx * sizeof(double));
        }
        eo_sim_get_state(s, *xs + (size_t)k * (size_t)nx, NULL, NULL, NULL);
    }
    const eo_profile *p = eo_solver_get_profile(eo_sim_solver(s));
    o->n_solve = p->n_solve;
    o->n_factor = p->n_factor;
    *n = nx;
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
    return rc;
}

int main(void)
{
    struct {
        const char *scene, *stop;
        int steps;
    } sc[] = {{"twist", "newton_decrement", 6},     {"twist", "relative_decrement", 6},
              {"cantilever", "relative_decrement", 6}, {"cantilever_static", "relative_decrement", 1},
              {"stretch", "relative_decrement", 4}, {"drop", "relative_decrement", 10},
              {"inverted", "relative_decrement", 3}};
    long solve_off = 0, solve_on = 0, fac_off = 0, fac_on = 0;
    int total_steps = 0;
    for (size_t i = 0; i < sizeof sc / sizeof sc[0]; i++) {
        double *xa = NULL, *xb = NULL;
        int na = 0, nb = 0;
        run_out a, b;
        if (run(sc[i].scene, sc[i].stop, "0", sc[i].steps, &xa, &na, &a) ||
            run(sc[i].scene, sc[i].stop, "10", sc[i].steps, &xb, &nb, &b)) {
            free(xa), free(xb);
            continue;
        }
        double dmax = 0, xmax = 1;
        for (size_t j = 0; j < (size_t)sc[i].steps * (size_t)na; j++) {
            dmax = fmax(dmax, fabs(xa[j] - xb[j]));
            xmax = fmax(xmax, fabs(xa[j]));
        }
        printf("  %-18s %-18s %2d steps: gate off %3d iterations, %3ld factorizations, %3ld solves; on %3d, %3ld, "
               "%3ld; max|dx| = %.2e (|x| <= %.2e)\n",
               sc[i].scene, sc[i].stop, sc[i].steps, a.iters, a.n_factor, a.n_solve, b.iters, b.n_factor, b.n_solve,
               dmax, xmax);
        CHECK(na == nb && dmax <= 1e-9 * xmax, "%s: iterates differ by %.3e", sc[i].scene, dmax);
        CHECK(a.converged == b.converged && a.converged == sc[i].steps, "%s: converged %d / %d of %d", sc[i].scene,
              a.converged, b.converged, sc[i].steps);
        CHECK(b.iters == a.iters, "%s: iterations %d -> %d", sc[i].scene, a.iters, b.iters);
        if (!strcmp(sc[i].scene, "inverted"))
            CHECK(a.n_solve >= 2 * a.n_factor - sc[i].steps && b.n_solve <= b.n_factor + 3 * sc[i].steps,
                  "inverted: %ld solves for %ld factorizations -> %ld for %ld", a.n_solve, a.n_factor, b.n_solve,
                  b.n_factor);
        CHECK(b.n_solve <= a.n_solve, "%s: solves %ld -> %ld", sc[i].scene, a.n_solve, b.n_solve);
        solve_off += a.n_solve, solve_on += b.n_solve, fac_off += a.n_factor, fac_on += b.n_factor;
        total_steps += sc[i].steps;
        free(xa), free(xb);
    }
    printf("total: solves %ld -> %ld, factorizations %ld -> %ld over %d steps\n", solve_off, solve_on, fac_off, fac_on,
           total_steps);
    /* at least 25% (measured 26%: 374 -> 277) */
    CHECK(4 * (solve_off - solve_on) >= solve_off, "solves %ld -> %ld: less than 25%% dropped", solve_off,
          solve_on);
    CHECK(10 * (fac_on - fac_off) <= total_steps, "factorizations %ld -> %ld over %d steps", fac_off, fac_on,
          total_steps);
    return eo_test_finish("test_newton_gate");
}
