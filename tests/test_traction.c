/* The surface traction term (problems/term_traction.c, scene section `tractions`):
 *  - the consistent nodal loads sum to t·A (the rest area of the selected faces) for the
 *    3-node (p1) and the 6-node (p2) face, read from the step gradient at rest (a linear
 *    material: the elastic gradient at rest is exactly zero, so ∇g = −f);
 *  - a bar under an end traction in the linear regime against the analytic elongation
 *    δ = FL/(EA): exact for p1 at ν = 0 (a linear field), within 1% for p2 at ν = 0.3
 *    with the linear and the stable neo-Hookean material (the clamped root holds the
 *    Poisson contraction locally: 0.9948 of FL/(EA));
 *  - load stepping ramps the traction like gravity (half the load after one of two steps);
 *  - bad sections: no selector, two selectors, a box that selects nothing. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "elastopt/scene.h"
#include "elastopt/step.h"
#include "engine_util.h"

static const char *bar_json =
    "{\"mesh\": {\"generate\": {\"size\": [1, 0.1, 0.1], \"cells\": [%d, 2, 2], \"split\": 5}},"
    " \"material\": {\"model\": \"%s\", \"E\": 1e9, \"nu\": %g, \"density\": 1000},"
    " \"element\": \"%s\", \"gravity\": [0, 0, 0],"
    " \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true}],"
    " \"tractions\": [{\"box\": [[0.999999, -1, -1], [2, 1, 1]], \"t\": [%g, %g, %g]}],"
    " \"time\": {\"integrator\": \"static\", \"dt\": 1, \"steps\": %d, \"load_steps\": %d},"
    " \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"tol\": 1e-12}}";

static eo_sim *open_bar(eo_ctx *ctx, int nx, const char *model, double nu, const char *el, const double t[3],
                        int steps, int load_steps)
{
    char json[2048];
    snprintf(json, sizeof json, bar_json, nx, model, nu, el, t[0], t[1], t[2], steps, load_steps);
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, NULL, json, NULL) < 0) return NULL;
    return s;
}

/* Σ f over the free coordinates per axis, from ∇g at the rest state (static: w = 1). */
static void total_force(eo_ctx *ctx, const char *el, double F[3])
{
    const double t[3] = {1.5e5, -2.5e5, 4e5};
    F[0] = F[1] = F[2] = NAN;
    eo_sim *s = open_bar(ctx, 4, "linear", 0.3, el, t, 1, 0);
    CHECK(s != NULL, "%s: scene with tractions opens", el);
    if (!s) return;
    eo_objective *obj = eo_test_sim_obj(s);
    const eo_step *st = eo_sim_step_problem(s);
    const double *x0 = eo_step_x0(st);
    double *x = malloc((size_t)obj->n * sizeof *x), *gr = malloc((size_t)obj->n * sizeof *gr), g;
    for (int i = 0; i < obj->n; i++) x[i] = x0[eo_step_free_to_full(st, i)];
    int rc = obj->ops->gradient(obj->data, x, &g, gr);
    CHECK(rc == EO_OK, "%s: gradient", el);
    F[0] = F[1] = F[2] = 0;
    for (int i = 0; i < obj->n; i++) F[eo_step_free_to_full(st, i) % 3] -= gr[i];
    const double A = 0.1 * 0.1;
    for (int c = 0; c < 3; c++)
        CHECK(fabs(F[c] - t[c] * A) <= 1e-12 * fabs(t[c] * A), "%s: total force %c %.17g, t·A = %.17g", el, "xyz"[c],
              F[c], t[c] * A);
    printf("%-4s total traction force [%.15g, %.15g, %.15g] N, t·A = [%g, %g, %g] N\n", el, F[0], F[1], F[2],
           t[0] * A, t[1] * A, t[2] * A);
    /* the potential reported by the statistics: −fᵀX at rest (elastic 0) */
    eo_step_stats ss;
    eo_step_stats_compute(eo_sim_step_problem(s), &ss);
    double fx = 0;
    for (int i = 0; i < obj->n; i++) fx -= gr[i] * x[i];
    CHECK(fabs(ss.potential + fx) <= 1e-9 * fabs(fx) + 1e-12, "%s: stats potential %.12g = −fᵀX %.12g", el,
          ss.potential, -fx);
    free(x);
    free(gr);
    eo_sim_destroy(&s);
}

/* mean x displacement of the end face x = 1 */
static double end_dx(const eo_sim *s)
{
    const eo_step *st = eo_sim_step_problem(s);
    const eo_mesh *m = eo_step_mesh(st);
    const double *x = eo_step_x(st);
    double sum = 0;
    int n = 0;
    for (int v = 0; v < m->nv; v++)
        if (m->X[3 * v] >= 1 - 1e-9) sum += x[3 * v] - m->X[3 * v], n++;
    return n ? sum / n : NAN;
}

static double elongation_ratio(eo_ctx *ctx, const char *model, double nu, const char *el, int steps, int load_steps,
                               double *first)
{
    const double E = 1e9, tx = 1e5, L = 1; /* strain 1e-4 */
    const double t[3] = {tx, 0, 0};
    eo_sim *s = open_bar(ctx, 10, model, nu, el, t, steps, load_steps);
    if (!s) return NAN;
    double d = NAN;
    for (int k = 0; k < steps; k++) {
        eo_sim_step_result r;
        int rc = eo_test_sim_step(s, NULL, NULL, &r);
        CHECK(rc == EO_OK && r.reason > 0, "bar %s %s nu %g: step %d converged (reason %d)", model, el, nu, k,
              r.reason);
        d = end_dx(s);
        if (k == 0 && first) *first = d / (tx * L / E);
    }
    eo_sim_destroy(&s);
    return d / (tx * L / E);
}

static void test_bar(eo_ctx *ctx)
{
    double r = elongation_ratio(ctx, "linear", 0, "p1", 1, 0, NULL);
    printf("bar under end traction, linear nu 0, p1: elongation / (FL/EA) = %.10f\n", r);
    CHECK(fabs(r - 1) < 1e-6, "p1, nu = 0: a linear field, exact (ratio %.10f)", r);
    static const char *models[] = {"linear", "stable_neo_hookean"};
    for (int i = 0; i < 2; i++) {
        r = elongation_ratio(ctx, models[i], 0.3, "p2", 1, 0, NULL);
        printf("bar under end traction, %s nu 0.3, p2: elongation / (FL/EA) = %.6f\n", models[i], r);
        CHECK(fabs(r - 1) < 0.01, "p2 %s nu 0.3: within 1%% of FL/(EA) (ratio %.6f)", models[i], r);
    }
    double first = NAN;
    r = elongation_ratio(ctx, "linear", 0, "p1", 2, 2, &first);
    printf("load stepping (2 steps): after step 1 %.10f, after step 2 %.10f of FL/(EA)\n", first, r);
    CHECK(fabs(first - 0.5) < 1e-6 && fabs(r - 1) < 1e-6, "load stepping ramps the traction (%.10f, %.10f)", first,
          r);
}

static void test_errors(eo_ctx *ctx)
{
    static const char *bad[] = {
        "[{\"t\": [1, 0, 0]}]",
        "[{\"tag\": 3, \"box\": [[0, 0, 0], [1, 1, 1]], \"t\": [1, 0, 0]}]",
        "[{\"box\": [[5, 5, 5], [6, 6, 6]], \"t\": [1, 0, 0]}]",
        "[{\"box\": [[0, 0, 0], [1, 1, 1]]}]",
        "[{\"plane\": {\"point\": [1, 0, 0], \"normal\": [0, 0, 0]}, \"t\": [1, 0, 0]}]",
        "[{\"box\": [[0, 0, 0], [1, 1, 1]], \"t\": [1, 0, 0], \"color\": 1}]",
        "{\"t\": [1, 0, 0]}",
    };
    static const char *want[] = {"exactly one of", "exactly one of", "selects no boundary face", "needs \"t\"",
                                 "zero normal", "color", "expected a list"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char json[1024];
        snprintf(json, sizeof json,
                 "{\"mesh\": {\"generate\": {\"size\": [1, 0.1, 0.1], \"cells\": [4, 1, 1]}},"
                 " \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true}], \"tractions\": %s}",
                 bad[i]);
        eo_cfg *cfg = NULL;
        eo_scene *sc = NULL;
        int rc = eo_cfg_load(ctx, NULL, json, &cfg);
        if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
        if (rc >= 0) rc = eo_cfg_finish(ctx, cfg);
        const char *msg = eo_ctx_message(ctx);
        CHECK(rc < 0 && strstr(msg, want[i]) != NULL, "bad tractions %s refused: %s", bad[i], msg);
        eo_scene_destroy(&sc);
        eo_cfg_destroy(&cfg);
    }
    /* the plane selector: the end face, same loads as the box */
    char json[1024];
    snprintf(json, sizeof json,
             "{\"mesh\": {\"generate\": {\"size\": [1, 0.1, 0.1], \"cells\": [4, 1, 1]}},"
             " \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true}],"
             " \"tractions\": [{\"plane\": {\"point\": [1, 0, 0], \"normal\": [1, 0, 0]}, \"t\": [1, 0, 0]}]}");
    eo_cfg *cfg = NULL;
    eo_scene *sc = NULL;
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    if (rc >= 0) rc = eo_scene_load(ctx, cfg, &sc);
    if (rc >= 0) rc = eo_cfg_finish(ctx, cfg);
    CHECK(rc >= 0, "plane selector accepted: %s", rc < 0 ? eo_ctx_message(ctx) : "");
    eo_scene_destroy(&sc);
    eo_cfg_destroy(&cfg);
}

int main(void)
{
    eo_ctx *ctx = NULL;
    eo_ctx_create(NULL, &ctx);
    double F[3];
    total_force(ctx, "p1", F);
    total_force(ctx, "p2", F);
    test_bar(ctx);
    test_errors(ctx);
    eo_ctx_destroy(&ctx);
    return eo_test_finish("test_traction");
}
