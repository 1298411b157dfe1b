/* Suite 'engine': one meaning of convergence for every optimizer (solvers/stop/).
 *
 *  1. No false failures: a clamped bar at rest without load, a backward-Euler body
 *     coming to rest and a static step started at its minimizer converge (the rounding
 *     floor at the step's start), for newton and for the first-order methods.
 *  2. No false successes: an optimizer that reports no first decrement (fixed_point,
 *     newton_tr) is held to the same relative measure: on a soft backward-Euler
 *     cantilever step each either reaches the reference within 1e-6 of the step's
 *     motion or reports non-convergence; never "converged" at a distance.
 *  3. The same accuracy whichever optimizer runs: with solver.tol = 1e-8 the first step
 *     of the dynamic cantilever solved by newton, lbfgs, ncg, gradient_descent and
 *     projective_dynamics ends within 1e-6 of the motion of the reference (or reports
 *     non-convergence), and newton's stop is not looser than before.
 * Errors are ‖x − x*‖₂ / ‖x* − x₀‖₂ with x* a tightly converged Newton solve from the
 * same start x₀ (the step's guess). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

/* every step of `steps` converged? returns the number converged; *worst = worst reason */
static int run_steps(eo_ctx *ctx, const char *scene, const char *json, const char *const *ov, int steps,
                     int *worst, int *iters)
{
    eo_sim *s = NULL;
    int conv = 0;
    *worst = 1;
    *iters = 0;
    if (eo_test_sim_open(&s, ctx, scene, json, ov) < 0) return -1;
    for (int k = 0; k < steps; k++) {
        eo_sim_step_result sr;
        if (eo_test_sim_step(s, NULL, NULL, &sr) < 0) break;
        if (sr.reason > 0)
            conv++;
        else if (*worst > 0)
            *worst = sr.reason;
        *iters += sr.iterations;
    }
    eo_sim_destroy(&s);
    return conv;
}

static void no_false_failures(eo_ctx *ctx)
{
    static const char *const opts[][4] = {
        {"solver.optimizer=newton", NULL},
        {"solver.optimizer=newton", "solver.hessian_fix=clamp", NULL},
        {"solver.optimizer=lbfgs", NULL},
        {"solver.optimizer=newton_tr", NULL},
        {"solver.optimizer=fixed_point", NULL},
        {"solver.optimizer=projective_dynamics", NULL},
    };
    for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++) {
        /* at rest, no load: every step starts at its minimizer */
        const char *ov[8] = {"gravity=[0,0,0]", "time.steps=10", NULL};
        int j = 2;
        for (int q = 0; opts[i][q]; q++) ov[j++] = opts[i][q];
        ov[j] = NULL;
        int worst, it;
        int c = run_steps(ctx, "cantilever", NULL, ov, 10, &worst, &it);
        printf("at rest, %s %s: %d/10 converged, %d iterations, worst %s\n", opts[i][0], opts[i][1] ? opts[i][1] : "",
               c, it, eo_reason_string(worst));
        CHECK(c == 10, "at rest (%s %s): every step converges: %d/10 (%s)", opts[i][0], opts[i][1] ? opts[i][1] : "",
              c, eo_reason_string(worst));
        CHECK(it <= 10 * 2, "at rest (%s): at most 2 iterations a step: %d in 10", opts[i][0], it);
    }
    /* backward Euler with damping: the sagging cantilever comes to rest */
    const char *be[] = {"time.integrator=backward_euler", "time.steps=60", "time.dt=0.05", "damping.rayleigh_alpha=5",
                        NULL};
    int worst, it;
    int c = run_steps(ctx, "cantilever", NULL, be, 60, &worst, &it);
    printf("backward Euler coming to rest: %d/60 converged, %d iterations, worst %s\n", c, it,
           eo_reason_string(worst));
    CHECK(c == 60, "backward Euler coming to rest: every step converges: %d/60 (%s)", c, eo_reason_string(worst));
}

/* ‖x − x*‖/‖x* − x₀‖ for one solver on the first step of a scene, x* converged Newton */
typedef struct acc {
    double err;
    int reason, iters;
} acc;

static acc accuracy(eo_ctx *ctx, const char *scene, const char *const *scene_ov, const char *const *solver_ov,
                    const double *xref, const double *x0ref, int nref)
{
    acc a = {NAN, 0, 0};
    double *x = NULL, *x0 = NULL;
    int n = 0;
    eo_solve_result res;
    if (eo_test_solve_first(ctx, scene, scene_ov, solver_ov, &x, &x0, &n, &res, NULL) < 0 || n != nref) {
        free(x), free(x0);
        return a;
    }
    double e2 = 0, m2 = 0;
    for (int i = 0; i < n; i++) {
        e2 += (x[i] - xref[i]) * (x[i] - xref[i]);
        m2 += (xref[i] - x0ref[i]) * (xref[i] - x0ref[i]);
    }
    a.err = sqrt(e2 / m2);
    a.reason = res.reason;
    a.iters = res.iterations;
    free(x), free(x0);
    return a;
}


static void same_accuracy(eo_ctx *ctx, const char *label, const char *scene, const char *const *scene_ov, double tol,
                          const char *const solvers[][5], int nsolvers, double bound)
{
    double *xref = NULL, *x0 = NULL;
    int n = 0;
    eo_solve_result rr;
    if (eo_test_solve_first(ctx, scene, scene_ov, eo_test_newton_ref, &xref, &x0, &n, &rr, NULL) < 0) {
        CHECK(0, "%s: reference solve", label);
        return;
    }
    char tolkey[64];
    snprintf(tolkey, sizeof tolkey, "solver.tol=%g", tol);
    for (int i = 0; i < nsolvers; i++) {
        const char *ov[8];
        int j = 0;
        for (int q = 0; solvers[i][q]; q++) ov[j++] = solvers[i][q];
        ov[j++] = tolkey;
        ov[j++] = "solver.max_iters=20000";
        ov[j] = NULL;
        acc a = accuracy(ctx, scene, scene_ov, ov, xref, x0, n);
        printf("%s, tol %g, %s: %s after %d iterations, error %.3g of the motion\n", label, tol, solvers[i][0],
               eo_reason_string(a.reason), a.iters, a.err);
        CHECK(isfinite(a.err), "%s %s: solved", label, solvers[i][0]);
        if (a.reason > 0)
            CHECK(a.err <= bound, "%s %s: reported converged, so within %g of the motion: %.3g", label,
                  solvers[i][0], bound, a.err);
    }
    free(xref);
    free(x0);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    no_false_failures(ctx);
    /* soft backward-Euler cantilever (E = 1e5): large motion in one step */
    const char *soft[] = {"time.integrator=backward_euler", "material.E=1e5", "time.dt=0.05", NULL};
    static const char *const fp[][5] = {
        {"solver.optimizer=fixed_point", NULL},
        {"solver.optimizer=newton_tr", NULL},
    };
    same_accuracy(ctx, "soft backward-Euler cantilever", "cantilever", soft, 1e-10, fp, 2, 1e-6);
    static const char *const all[][5] = {
        {"solver.optimizer=newton", NULL},
        {"solver.optimizer=newton_tr", NULL},
        {"solver.optimizer=lbfgs", NULL},
        {"solver.optimizer=ncg", NULL},
        {"solver.optimizer=gradient_descent", NULL},
        {"solver.optimizer=projective_dynamics", NULL},
    };
    const char *dyn[] = {NULL};
    same_accuracy(ctx, "dynamic cantilever", "cantilever", dyn, 1e-8, all, 6, 1e-6);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_converge");
}
