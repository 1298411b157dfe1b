/* Vertex block descent (suite 'solvers'): the optimizer vbd (solvers/optim/vbd.c) and
 * the step objective's vertex-block ops (problems/step_objective.c).
 *
 *  - the ops: at a perturbed iterate of the cantilever (consistent mass, gravity,
 *    Newmark's linear term), of the twist (prescribed rotations) and of the cloth lattice
 *    (springs, point masses, a penalty plane through the sheet), the vertex block's
 *    g3 equals the full gradient's entries and H3 the diagonal 3×3 block of the
 *    objective's Hessian with the same projection (1e-10 relative), and the vertex energy
 *    changes like g when the vertex moves (difference quotient against g3);
 *  - the colouring is proper (no two coupled vertices share a colour; checked through
 *    the blocks' coupling graph) — implicitly: a sweep in colour order equals a sweep in
 *    any order within a colour, so plain vbd converges to Newton's minimizer;
 *  - vbd (plain and accelerated) converges to Newton's minimizer within 1e-8 of the
 *    step's motion (‖x − x*‖/‖x* − x₀‖) on the first steps of cantilever and twist;
 *  - the accelerated variant needs fewer sweeps than the plain one on both;
 *  - backtracking per vertex keeps g monotone at every sweep (twist) and converges too;
 *  - a scene with a term without a vertex form (damping) is refused with
 *    EO_ERR_UNSUPPORTED naming it. */
#include <stdlib.h>
#include <string.h>

#include "elastopt/impl/method.h"
#include "engine_util.h"

static int perturbed(eo_ctx *ctx, const char *scene, const char *const *extra, eo_sim **s, double **x, int *n)
{
    const char *ov[8] = {"solver.fallback=[]", NULL};
    for (int i = 0; extra && extra[i] && i < 6; i++) ov[i + 1] = extra[i], ov[i + 2] = NULL;
    if (eo_test_sim_open(s, ctx, scene, NULL, ov) < 0) return -1;
    eo_objective *obj = eo_test_sim_obj(*s);
    *n = obj->n;
    *x = malloc((size_t)*n * sizeof(double));
    memcpy(*x, eo_test_sim_guess(*s), (size_t)*n * sizeof(double));
    eo_test_seed(7);
    for (int i = 0; i < *n; i++) (*x)[i] += eo_test_rand(-2e-3, 2e-3);
    return 0;
}

static void check_ops(const char *scene, const char *const *extra)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    double *x = NULL;
    int n = 0;
    if (perturbed(ctx, scene, extra, &s, &x, &n) < 0) {
        CHECK(0, "open %s", scene);
        eo_test_ctx_done(&ctx);
        return;
    }
    eo_objective *obj = eo_test_sim_obj(s);
    eo_vertex_blocks vb;
    CHECK(eo_objective_vertex_blocks(obj, &vb) == EO_OK, "%s: vertex blocks: %s", scene, eo_ctx_message(ctx));
    double g, *grad = malloc((size_t)n * sizeof(double));
    eo_objective_gradient(obj, x, &g, grad);
    int covered = 0;
    for (int b = 0; b < vb.nb; b++)
        for (int c = 0; c < 3; c++) covered += vb.dofs[3 * b + c] >= 0;
    CHECK(covered == n, "%s: blocks cover %d of %d free variables", scene, covered, n);
    const eo_proj projs[2] = {EO_PROJ_NONE, EO_PROJ_CLAMP};
    for (int pi = 0; pi < 2; pi++) {
        eo_csc *H = NULL;
        eo_objective_hessian(obj, x, projs[pi], &H);
        double gerr = 0, gmax = 0, herr = 0, hmax = 0;
        for (int b = 0; b < vb.nb; b++) {
            double e, g3[3], H3[9];
            eo_objective_vertex_block(obj, x, b, projs[pi], &e, g3, H3);
            const int *d = vb.dofs + 3 * b;
            for (int r = 0; r < 3; r++) {
                if (d[r] < 0) continue;
                gerr = fmax(gerr, fabs(g3[r] - grad[d[r]]));
                gmax = fmax(gmax, fabs(grad[d[r]]));
                for (int c = 0; c < 3; c++) { /* H upper triangle: entry (min, max) */
                    if (d[c] < 0) continue;
                    const int i = d[r] < d[c] ? d[r] : d[c], j = d[r] < d[c] ? d[c] : d[r];
                    double hij = 0;
                    for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++)
                        if (H->rowind[q] == i) hij = H->val[q];
                    herr = fmax(herr, fabs(H3[3 * r + c] - hij));
                    hmax = fmax(hmax, fabs(hij));
                }
            }
        }
        printf("  %-10s proj %d: |g3 - grad| %.2e of %.2e, |H3 - H_bb| %.2e of %.2e\n", scene, pi, gerr, gmax, herr,
               hmax);
        CHECK(gerr <= 1e-10 * gmax, "%s: g3 against the gradient: %g (max %g)", scene, gerr, gmax);
        CHECK(herr <= 1e-10 * hmax, "%s proj %d: H3 against the Hessian block: %g (max %g)", scene, pi, herr, hmax);
    }
    /* the vertex energy moves like g: G_b(x + t e) − G_b(x) = g(x + t e) − g(x) */
    double worst = 0;
    for (int b = 0; b < vb.nb; b += 17) {
        const int i = vb.dofs[3 * b + 1];
        if (i < 0) continue;
        double e0, e1, g0, g1;
        const double t = 1e-6;
        eo_objective_vertex_block(obj, x, b, EO_PROJ_NONE, &e0, NULL, NULL);
        eo_objective_value(obj, x, &g0);
        x[i] += t;
        eo_objective_vertex_block(obj, x, b, EO_PROJ_NONE, &e1, NULL, NULL);
        eo_objective_value(obj, x, &g1);
        x[i] -= t;
        worst = fmax(worst, fabs((e1 - e0) - (g1 - g0)) / fmax(fabs(g1 - g0), 1e-300));
    }
    printf("  %-10s vertex energy differences against g: worst relative %.2e\n", scene, worst);
    CHECK(worst <= 1e-5, "%s: vertex energy differences against g: %g", scene, worst);
    free(grad);
    free(x);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* ---- convergence to Newton's minimizer -------------------------------------------- */

typedef struct trace {
    int n, rises;
    double prev;
} trace;

static int on_iter(const eo_iter_info *info, void *user)
{
    trace *t = user;
    if (t->n > 0 && isfinite(info->g) && info->g > t->prev + 1e-13 * fabs(t->prev)) t->rises++;
    t->prev = info->g;
    t->n++;
    return 0;
}

/* minimize obj from x0 with the solver section `solver_json`; x out */
static int solve_with(eo_ctx *ctx, eo_objective *obj, const double *x0, double *x, const char *solver_json,
                      eo_solve_result *r, trace *tr)
{
    return eo_test_solve_json(ctx, obj, x0, x, solver_json, tr ? on_iter : NULL, tr, r);
}

static const char *newton_json =
    "{\"optimizer\": \"newton\", \"hessian_fix\": \"project_on_demand\", \"stop\": \"gradient\", \"tol\": 1e-11,"
    " \"max_iters\": 200}";

static void check_converge(const char *scene, int with_backtracking)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"solver.fallback=[]", NULL};
    if (eo_test_sim_open(&s, ctx, scene, NULL, ov) < 0) {
        CHECK(0, "open %s", scene);
        eo_test_ctx_done(&ctx);
        return;
    }
    eo_objective *obj = eo_test_sim_obj(s);
    const int n = obj->n;
    double *x0 = malloc((size_t)n * sizeof(double)), *xs = malloc((size_t)n * sizeof(double));
    double *xp = malloc((size_t)n * sizeof(double)), *xa = malloc((size_t)n * sizeof(double));
    double *xb = malloc((size_t)n * sizeof(double));
    memcpy(x0, eo_test_sim_guess(s), (size_t)n * sizeof(double));
    eo_solve_result rn, rp, ra, rb;
    trace tb = {0};
    /* Newton to the rounding level: converged, or stagnated there (gradient rule 1e-11) */
    CHECK(solve_with(ctx, obj, x0, xs, newton_json, &rn, NULL) == 0 &&
              (eo_reason_is_converged(rn.reason) || rn.reason == EO_DIVERGED_STAGNATED),
          "%s newton reference: %s", scene, eo_reason_name(rn.reason));
    const char *plain = "{\"optimizer\": \"vbd\", \"tol\": 1e-10, \"max_iters\": 20000}";
    const char *acc = "{\"optimizer\": \"vbd\", \"tol\": 1e-10, \"max_iters\": 20000,"
                      " \"vbd\": {\"accelerated\": true}}";
    const char *bt = "{\"optimizer\": \"vbd\", \"tol\": 1e-10, \"max_iters\": 20000,"
                     " \"vbd\": {\"linesearch\": \"backtracking\"}}";
    CHECK(solve_with(ctx, obj, x0, xp, plain, &rp, NULL) == 0 && eo_reason_is_converged(rp.reason), "%s vbd: %s",
          scene, eo_reason_name(rp.reason));
    CHECK(solve_with(ctx, obj, x0, xa, acc, &ra, NULL) == 0 && eo_reason_is_converged(ra.reason),
          "%s vbd accelerated: %s", scene, eo_reason_name(ra.reason));
    if (with_backtracking) {
        CHECK(solve_with(ctx, obj, x0, xb, bt, &rb, &tb) == 0 && eo_reason_is_converged(rb.reason),
              "%s vbd backtracking: %s", scene, eo_reason_name(rb.reason));
    } else {
        memcpy(xb, xs, (size_t)n * sizeof(double));
        memset(&rb, 0, sizeof rb);
    }
    const double ep = eo_test_motion_error(n, xp, xs, x0), ea = eo_test_motion_error(n, xa, xs, x0),
                 eb = eo_test_motion_error(n, xb, xs, x0);
    printf("  %-10s n = %d: newton %d it; vbd %d sweeps, err %.2e; accelerated %d sweeps (%ld restarts), err %.2e; "
           "backtracking %d sweeps, err %.2e, %d rises of g\n",
           scene, n, rn.iterations, rp.iterations, ep, ra.iterations, ra.n_fallback, ea, rb.iterations, eb, tb.rises);
    CHECK(ep <= 1e-8, "%s: vbd vs newton %g of the motion", scene, ep);
    CHECK(ea <= 1e-8, "%s: accelerated vbd vs newton %g of the motion", scene, ea);
    CHECK(eb <= 1e-8, "%s: backtracking vbd vs newton %g of the motion", scene, eb);
    CHECK(ra.iterations * 2 < rp.iterations, "%s: accelerated %d sweeps, plain %d (at least 2x fewer)", scene,
          ra.iterations, rp.iterations);
    CHECK(tb.rises == 0, "%s: backtracking vbd raised g %d times", scene, tb.rises);
    CHECK(rp.n_hessian == 0 && rp.n_factor == 0, "%s: vbd used no global Hessian (%ld) nor factorization (%ld)",
          scene, rp.n_hessian, rp.n_factor);
    free(x0), free(xs), free(xp), free(xa), free(xb);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

/* a term without a vertex form: refused, naming it */
static void check_unsupported(void)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    const char *ov[] = {"solver.fallback=[]", "damping.rayleigh_alpha=5", NULL};
    if (eo_test_sim_open(&s, ctx, "cantilever", NULL, ov) < 0) {
        CHECK(0, "open damped cantilever");
        eo_test_ctx_done(&ctx);
        return;
    }
    eo_objective *obj = eo_test_sim_obj(s);
    double *x = malloc((size_t)obj->n * sizeof(double));
    eo_solve_result r;
    int rc = solve_with(ctx, obj, eo_test_sim_guess(s), x, "{\"optimizer\": \"vbd\"}", &r, NULL);
    printf("  damped cantilever: rc %d, %s\n", rc, eo_ctx_message(ctx));
    CHECK(rc == EO_ERR_UNSUPPORTED, "vbd on a damped scene: rc %d", rc);
    CHECK(strstr(eo_ctx_message(ctx), "damping") != NULL, "the message names the term: %s", eo_ctx_message(ctx));
    free(x);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    check_ops("cantilever", NULL);
    check_ops("twist", NULL);
    /* springs (a lattice of point masses) and a penalty plane through the sheet, so that
     * about half the perturbed vertices are in contact */
    const char *cloth[] = {"collisions.0.friction=0", "collisions.0.plane.point=[0,0,1]", NULL};
    check_ops("cloth", cloth);
    check_converge("cantilever", 0);
    check_converge("twist", 1);
    check_unsupported();
    return eo_test_finish("test_vbd");
}
