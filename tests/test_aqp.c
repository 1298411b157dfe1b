/* Accelerated Quadratic Proxy (suite 'solvers'): the optimizer aqp (solvers/optim/aqp.c).
 *
 *  - it converges to Newton's minimizer: first steps of cantilever and twist with
 *    stable_neo_hookean, solver.tol = 1e-10 (the default), within 1e-8 of the step's
 *    motion ‖x* − x₀‖, one factorization; with neo_hookean (a barrier) on the twist the
 *    line search stops resolving g near 2e-7 of the gradient: aqp stops by itself
 *    (stagnation guard) within 1e-6 of the motion;
 *  - the acceleration pays: with the momentum (κ = 100, θ = 0.818) the cantilever's first
 *    step takes fewer than half the iterations of the plain proxy iteration (θ = 0,
 *    accelerate = false), which must still make progress (or converge);
 *  - the plain proxy iteration is a monotone descent method (g never rises). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"


/* ‖x − x*‖/‖x* − x₀‖ of aqp against Newton on the first step */
static double check_converges(eo_ctx *ctx, const char *scene, const char *material, const char *const *extra,
                              int *iters)
{
    char mkey[64];
    snprintf(mkey, sizeof mkey, "material.model=%s", material);
    const char *ov[] = {mkey, NULL};
    const char *aqp[12] = {"solver.optimizer=aqp", "solver.max_iters=20000", "solver.fallback=[]", NULL};
    int j = 3;
    for (const char *const *o = extra; o && *o; o++) aqp[j++] = *o;
    aqp[j] = NULL;
    double *xr = NULL, *x0 = NULL, *x = NULL, *x0b = NULL, err = NAN;
    int n = 0, nb = 0;
    eo_solve_result rr, ra;
    long nf = 0;
    *iters = -1;
    if (eo_test_solve_first(ctx, scene, ov, eo_test_newton_ref, &xr, &x0, &n, &rr, NULL) < 0 || rr.reason <= 0) {
        CHECK(0, "%s %s: Newton reference (%s)", scene, material, eo_reason_string(rr.reason));
        goto out;
    }
    if (eo_test_solve_first(ctx, scene, ov, aqp, &x, &x0b, &nb, &ra, &nf) < 0 || nb != n) {
        CHECK(0, "%s %s: aqp ran", scene, material);
        goto out;
    }
    double e2 = 0, m2 = 0;
    for (int i = 0; i < n; i++) {
        e2 += (x[i] - xr[i]) * (x[i] - xr[i]);
        m2 += (xr[i] - x0[i]) * (xr[i] - x0[i]);
    }
    err = sqrt(e2 / m2);
    *iters = ra.reason > 0 ? ra.iterations : -ra.iterations;
    printf("%-10s %-18s %-24s: aqp %s after %d iterations (%ld factorizations), error %.2e of the motion "
           "(newton %d iterations)\n",
           scene, material, extra && extra[0] ? extra[0] : "", eo_reason_string(ra.reason), ra.iterations, nf, err,
           rr.iterations);
    CHECK(nf <= 1, "%s %s: one factorization: %ld", scene, material, nf);
out:
    free(xr), free(x0), free(x), free(x0b);
    return err;
}

static void converges(eo_ctx *ctx, const char *scene, const char *material)
{
    int it;
    double err = check_converges(ctx, scene, material, NULL, &it);
    CHECK(it > 0, "%s %s: aqp converged (%d)", scene, material, it);
    CHECK(err <= 1e-8, "%s %s: within 1e-8 of the motion of Newton's minimizer: %.2e", scene, material, err);
}

/* g at the accepted iterates: count rises and rises twice in a row */
typedef struct trace {
    int n, rises, double_rises, last_rose;
    double prev;
} trace;

static int on_iter(const eo_iter_info *info, void *user)
{
    trace *t = user;
    /* the record's g is at y_k; with accelerate = false y_k = x_k */
    if (t->n > 0 && isfinite(info->g)) {
        const int rose = info->g > t->prev + 1e-13 * fabs(t->prev);
        t->rises += rose;
        t->double_rises += rose && t->last_rose;
        t->last_rose = rose;
    }
    t->prev = info->g;
    t->n++;
    return 0;
}

static void acceleration(eo_ctx *ctx)
{
    const char *acc[] = {NULL};
    const char *plain[] = {"solver.aqp.accelerate=false", "solver.max_iters=3000", NULL};
    int ia, ip;
    double ea = check_converges(ctx, "cantilever", "stable_neo_hookean", acc, &ia);
    double ep = check_converges(ctx, "cantilever", "stable_neo_hookean", plain, &ip);
    printf("cantilever first step: accelerated %d iterations (error %.2e), plain proxy %d (error %.2e; negative: "
           "did not converge)\n",
           ia, ea, ip, ep);
    CHECK(ia > 0 && (ip < 0 || 2 * ia < ip), "acceleration: fewer than half the iterations: %d vs %d", ia, ip);
    /* the plain iteration is a monotone descent method: g falls at every iterate */
    const char *ov[] = {"material.model=stable_neo_hookean", "solver.optimizer=aqp", "solver.aqp.accelerate=false",
                        "solver.max_iters=300", "solver.fallback=[]", NULL};
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) < 0) {
        CHECK(0, "cantilever opens");
        return;
    }
    trace tr = {0};
    eo_sim_step_result r;
    eo_test_sim_step(s, on_iter, &tr, &r);
    printf("plain proxy iteration: %d records, g rose %d times\n", tr.n, tr.rises);
    CHECK(tr.n > 10 && tr.rises == 0, "plain proxy iteration: g monotone (%d rises in %d)", tr.rises, tr.n);
    eo_sim_destroy(&s);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    converges(ctx, "cantilever", "stable_neo_hookean");
    converges(ctx, "twist", "stable_neo_hookean");
    /* a barrier material: g's rounding (log J terms) stops the line search's progress
     * before tol = 1e-10; aqp must stop by itself (stagnation) close to Newton's answer */
    int it;
    double err = check_converges(ctx, "twist", "neo_hookean", NULL, &it);
    CHECK(err <= 1e-6, "twist neo_hookean: within 1e-6 of the motion: %.2e (%d iterations)", err, it);
    CHECK(abs(it) < 2000, "twist neo_hookean: stops within 2000 iterations (%d)", it);
    acceleration(ctx);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_aqp");
}
