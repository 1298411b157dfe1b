/* Suite 'engine': the default stopping rule (relative_decrement) gives answers a user can
 * trust, and the rules behave as documented.
 *
 *  1. Static StVK cantilever (E = 1e7, built-in cantilever_static with material stvk) and
 *     the dynamic cantilever after 50 Newmark steps: the tip with every default is within
 *     1e-8 relative of the converged answer (tight tolerance, no line search); with the
 *     old default (newton_decrement, λ²/2 ≤ 1e-10 absolute) it is not (> 1e-7).
 *  2. relative_decrement on one step: stops at the first iterate with λ_k ≤ tol·λ_0, and
 *     a step that starts at its minimizer converges by the floor, not stagnation.
 *  3. backtracking at rounding level: on the static cantilever the full Newton step is
 *     accepted (α = 1) in every iteration after the first once λ²/2 < ε|g|. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine_util.h"

typedef struct rec {
    int n, rejected_tiny, k0_alpha_half;
    double dec[256], alpha[256], g[256];
    int reason[256];
} rec;

static int record(const eo_iter_info *info, void *user)
{
    rec *r = user;
    if (r->n < 256) {
        r->dec[r->n] = info->decrement;
        r->alpha[r->n] = info->alpha;
        r->g[r->n] = info->g;
        r->reason[r->n] = info->reason;
        r->n++;
    }
    return 0;
}

/* tip z displacement after `steps` steps; *conv = every step converged; *iters summed */
static double tip(eo_ctx *ctx, const char *scene, const char *const *ov, int steps, int *conv, int *iters,
                  rec *r)
{
    eo_sim *s = NULL;
    *conv = 1;
    *iters = 0;
    if (eo_test_sim_open(&s, ctx, scene, NULL, ov) < 0) return NAN;
    for (int k = 0; k < steps; k++) {
        eo_sim_step_result sr;
        if (r) r->n = 0;
        if (eo_test_sim_step(s, r ? record : NULL, r, &sr) < 0) {
            *conv = 0;
            break;
        }
        if (sr.reason <= 0) *conv = 0;
        *iters += sr.iterations;
    }
    double t = eo_test_tip_dz(s, 1.0 - 1e-9);
    eo_sim_destroy(&s);
    return t;
}

static void tip_accuracy(eo_ctx *ctx, const char *label, const char *scene, const char *material, int steps)
{
    char st[64], mat[64];
    snprintf(st, sizeof st, "time.steps=%d", steps);
    snprintf(mat, sizeof mat, "material.model=%s", material);
    /* converged: Newton without line search to the rounding floor of the decrement */
    const char *ref[] = {st, mat, "solver.linesearch=none", "solver.tol=1e-15", "solver.relative_decrement.plateau=1e-30",
                         "solver.max_iters=60", NULL};
    const char *def[] = {st, mat, NULL};
    const char *old[] = {st, mat, "solver.stop=newton_decrement", NULL};
    int conv, it_ref, it_def, it_old;
    double t_ref = tip(ctx, scene, ref, steps, &conv, &it_ref, NULL);
    double t_def = tip(ctx, scene, def, steps, &conv, &it_def, NULL);
    CHECK(conv, "%s: default run converged every step", label);
    double t_old = tip(ctx, scene, old, steps, &conv, &it_old, NULL);
    double e_def = fabs(t_def - t_ref) / fabs(t_ref), e_old = fabs(t_old - t_ref) / fabs(t_ref);
    printf("%s: tip %.12g m (converged, %d iterations); default relative_decrement: rel. error %.3g (%d "
           "iterations); old newton_decrement 1e-10: %.3g (%d iterations)\n",
           label, t_ref, it_ref, e_def, it_def, e_old, it_old);
    CHECK(isfinite(t_ref) && fabs(t_ref) > 1e-4, "%s: the tip moved: %g", label, t_ref);
    CHECK(e_def <= 1e-8, "%s: default stop within 1e-8 of the converged tip: %.3g", label, e_def);
    CHECK(e_old > 1e-7, "%s: the old absolute default is measurably worse: %.3g", label, e_old);
}

static void rule_semantics(eo_ctx *ctx)
{
    /* first step of the dynamic cantilever: the stop is at the first k with
     * λ_k²/2 ≤ tol²·λ_0²/2, and not earlier */
    const double tol = 1e-6;
    const char *ov[] = {"solver.tol=1e-6", "solver.linesearch=none", NULL};
    rec r;
    int conv, it;
    memset(&r, 0, sizeof r);
    tip(ctx, "cantilever", ov, 1, &conv, &it, &r);
    CHECK(conv && r.n >= 3, "relative_decrement: converged in %d records", r.n);
    const int last = r.n - 1;
    CHECK(r.reason[last] == EO_CONVERGED_DECREMENT, "reason %d", r.reason[last]);
    CHECK(r.dec[last] <= tol * tol * r.dec[0], "stops below tol^2 lambda_0^2: %.3g vs %.3g", r.dec[last],
          tol * tol * r.dec[0]);
    for (int k = 1; k < last; k++)
        CHECK(r.dec[k] > tol * tol * r.dec[0], "does not stop earlier: k %d %.3g", k, r.dec[k]);
    /* a step that starts at its minimizer: after a converged static solve, solve again
     * from the solution (eo_sim_trial from the accepted state) */
    const char *st[] = {"solver.linesearch=none", NULL};
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, "cantilever_static", NULL, st) >= 0) {
        eo_sim_step_result sr;
        eo_test_sim_step(s, NULL, NULL, &sr);
        eo_objective *obj = NULL;
        eo_solve_result res;
        const eo_step *sp = eo_sim_step_problem(s);
        (void)sp;
        eo_sim_prepare(s, &obj, NULL);
        double *x = malloc((size_t)obj->n * sizeof(double));
        double *x0 = eo_test_sim_guess(s); /* static: the guess is the accepted state */
        int rc = eo_sim_trial(s, NULL, x0, x, NULL, NULL, &obj, &res);
        printf("static cantilever solved again from its solution: %d iterations, %s, lambda^2/2 = %.3g, |g| = %.3g\n",
               res.iterations, eo_reason_string(res.reason), res.decrement, fabs(res.g));
        CHECK(rc >= 0 && res.reason > 0 && res.iterations <= 4, "from the minimizer: converged at once (%d, %s)",
              res.iterations, eo_reason_string(res.reason));
        free(x);
        eo_sim_destroy(&s);
    }
}

static void backtracking_rounding(eo_ctx *ctx)
{
    const char *ov[] = {"material.model=stable_neo_hookean", NULL};
    rec r;
    int conv, it;
    memset(&r, 0, sizeof r);
    tip(ctx, "cantilever_static", ov, 1, &conv, &it, &r);
    int cut = 0, tiny = 0;
    for (int k = 1; k + 1 < r.n; k++)
        if (r.dec[k] < DBL_EPSILON * fabs(r.g[k])) {
            tiny++;
            if (r.alpha[k] != 1) cut++;
        }
    printf("static cantilever, backtracking: %d iterations, %d at rounding level (lambda^2/2 < eps|g|), %d cut\n",
           r.n - 1, tiny, cut);
    CHECK(conv && tiny >= 2 && cut == 0, "full steps at rounding level: %d of %d cut", cut, tiny);
    CHECK(r.n - 1 <= 20, "static cantilever converges in <= 20 iterations: %d", r.n - 1);
}

/* eo_solver_set_reference (the fallback chain's continuation from the best iterate): on
 * the static cantilever's first step a run stopped after 3 iterations is continued (a)
 * without a reference: its tolerance is relative to its own, smaller first decrement, and
 * (b) with the uninterrupted run's references: it stops at the first iterate whose
 * decrement is below tol²·λ₀² of the uninterrupted run (not earlier, not later), in no more
 * iterations than (a), and eo_solver_get_reference reports the references it used. */
static void reference(eo_ctx *ctx)
{
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, "cantilever_static", NULL, NULL) < 0) return;
    eo_solver_opts o;
    eo_solver_opts_default(&o);
    eo_solver *full = NULL, *part = NULL, *cont = NULL;
    CHECK(eo_solver_create(ctx, &o, NULL, &full) == 0 && eo_solver_create(ctx, &o, NULL, &cont) == 0, "solvers");
    o.max_iters = 3;
    CHECK(eo_solver_create(ctx, &o, NULL, &part) == 0, "solver with 3 iterations");
    eo_objective *obj = NULL;
    eo_solve_result rf, rp, ra, rb;
    eo_sim_prepare(s, &obj, NULL);
    const int n = obj->n;
    double *x = malloc((size_t)n * sizeof(double)), *x3 = malloc((size_t)n * sizeof(double));
    static rec r;
    memset(&r, 0, sizeof r);
    eo_sim_trial(s, full, NULL, x, record, &r, NULL, &rf);
    double d0 = NAN, gm0 = NAN, d, gm;
    eo_solver_get_reference(full, &d0, &gm0);
    CHECK(rf.reason > 0 && r.n > 4 && d0 == r.dec[0] && gm0 > 0, "uninterrupted: %s in %d, lambda_0^2/2 %.3g (first %.3g)",
          eo_reason_string(rf.reason), rf.iterations, d0, r.dec[0]);
    eo_sim_trial(s, part, NULL, x3, NULL, NULL, NULL, &rp);
    CHECK(rp.reason == EO_DIVERGED_MAX_ITERS && rp.iterations == 3, "3 iterations: %s", eo_reason_string(rp.reason));
    memset(&r, 0, sizeof r);
    eo_sim_trial(s, cont, x3, x, record, &r, NULL, &ra);
    eo_solver_get_reference(cont, &d, &gm);
    const double own = r.dec[0], own_gm = gm;
    CHECK(ra.reason > 0 && d == own && d < d0, "(a) own reference %.3g (< %.3g)", d, d0);
    memset(&r, 0, sizeof r);
    eo_solver_set_reference(cont, d0, gm0);
    eo_sim_trial(s, cont, x3, x, record, &r, NULL, &rb);
    eo_solver_get_reference(cont, &d, &gm);
    printf("continued after 3 of %d iterations: own reference %d iterations, the run's %d\n", rf.iterations,
           ra.iterations, rb.iterations);
    CHECK(rb.reason > 0 && d == d0 && gm == fmax(gm0, own_gm), "(b) references used %.3g %.3g (given %.3g %.3g, own %.3g)",
          d, gm, d0, gm0, own_gm);
    CHECK(rb.iterations <= ra.iterations, "(b) %d iterations <= (a) %d", rb.iterations, ra.iterations);
    const double tol = o.tol;
    CHECK(r.dec[r.n - 1] <= tol * tol * d0, "(b) stops below tol^2 lambda_0^2 of the run: %.3g vs %.3g",
          r.dec[r.n - 1], tol * tol * d0);
    for (int k = 0; k + 1 < r.n; k++)
        CHECK(!(r.dec[k] <= tol * tol * d0), "(b) not later than that: k %d %.3g", k, r.dec[k]);
    eo_sim_trial(s, cont, x3, x, NULL, NULL, NULL, &ra);
    eo_solver_get_reference(cont, &d, &gm);
    CHECK(d == own, "the reference is for one minimization only (%.3g, own %.3g)", d, own);
    free(x);
    free(x3);
    eo_solver_destroy(&full);
    eo_solver_destroy(&part);
    eo_solver_destroy(&cont);
    eo_sim_destroy(&s);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    tip_accuracy(ctx, "static StVK cantilever E=1e7", "cantilever_static", "stvk", 1);
    tip_accuracy(ctx, "dynamic cantilever 50 steps", "cantilever", "stable_neo_hookean", 50);
    rule_semantics(ctx);
    backtracking_rounding(ctx);
    reference(ctx);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_stop");
}
