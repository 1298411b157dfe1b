/* Suite 'solvers': the non-monotone line search (solvers/linesearch/nonmonotone.c).
 *
 * On φ(α) = g(x + αp) with g(x) = (x − 1)², x = 0, p = 2 (an overshooting step: g(x + p)
 * = g(x) = 1, so Armijo rejects α = 1 and takes α = 1/2):
 *   - no history / history {g0}: Armijo, α = 1/2 (as backtracking);
 *   - max (GLL) with history {5, 3, 1}: R = 5, α = 1 accepted (g rises to 1 = g0 is fine,
 *     the test is against R − c1·|φ'(0)|), and with memory = 0 it is Armijo again;
 *   - max with a history whose large value is older than memory + 1: not used;
 *   - average (Zhang–Hager) with history {1.0004, 1}: C = (0.85·1.0004 + 1)/1.85 =
 *     1.000184 < 1 + c1·4 = 1.0004 — rejected, α = 1/2; with {3, 1}: C = 1.919 — accepted.
 *   - Newton + nonmonotone on the static StVK cantilever reaches the same minimizer as
 *     backtracking (1e-9 of the tip).
 * Values of C checked against the recursion by hand. */
#include "elastopt/impl/method.h"
#include "elastopt/impl/params.h"
#include <math.h>
#include <string.h>

#include "engine_util.h"

static int val(void *d, const double *x, double *g)
{
    (void)d;
    *g = (x[0] - 1) * (x[0] - 1);
    return EO_OK;
}
static int grad(void *d, const double *x, double *g, double *gr)
{
    (void)d;
    *g = (x[0] - 1) * (x[0] - 1);
    gr[0] = 2 * (x[0] - 1);
    return EO_OK;
}
static const eo_objective_ops ops = {.value = val, .gradient = grad};

static double search(const eo_linesearch_type *t, const char *ref, int memory, const double *h, int nh)
{
    eo_nonmonotone_params p;
    eo_params_default(t->info.params, &p);
    snprintf(p.reference, sizeof p.reference, "%s", ref);
    p.memory = memory;
    eo_objective obj = {.n = 1, .ops = &ops};
    double x = 0, dir = 2, xn, gn, a = -1, w, gnew[1];
    int nev = 0;
    eo_ls_extra ex = {.grad_new = gnew, .g_hist = h, .n_hist = nh};
    int rc = t->search(&p, &obj, &x, &dir, 1.0, -4.0, 1.0, &xn, &gn, &a, &nev, &w, NULL, h ? &ex : NULL);
    return rc == EO_OK ? a : -rc;
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    const eo_linesearch_type *t = NULL;
    CHECK(eo_registry_find(ctx, EO_KIND_LINESEARCH, "nonmonotone", (const void **)&t) == EO_OK && t, "registered");
    if (t) {
        const double h3[] = {5, 3, 1}, h1[] = {1}, hold[] = {5, 1, 1, 1}, za[] = {1.0004, 1}, zb[] = {3, 1};
        CHECK(search(t, "max", 10, NULL, 0) == 0.5, "no history: Armijo");
        CHECK(search(t, "max", 10, h1, 1) == 0.5, "k = 0: Armijo");
        CHECK(search(t, "max", 10, h3, 3) == 1, "GLL: R = max{5, 3, 1}, full step");
        CHECK(search(t, "max", 0, h3, 3) == 0.5, "GLL memory 0: Armijo");
        CHECK(search(t, "max", 2, hold, 4) == 0.5, "GLL: a value older than memory + 1 is not used");
        CHECK(search(t, "max", 3, hold, 4) == 1, "GLL: memory 3 reaches it");
        CHECK(search(t, "average", 10, za, 2) == 0.5, "Zhang-Hager: C = 1.000184 rejects the full step");
        CHECK(search(t, "average", 10, zb, 2) == 1, "Zhang-Hager: C = 1.919 accepts it");
    }
    /* Newton + nonmonotone on the static StVK cantilever: same tip as backtracking */
    double tipv[2];
    for (int k = 0; k < 2; k++) {
        const char *ov[] = {"material.model=stvk", k ? "solver.linesearch=nonmonotone" : "solver.linesearch=backtracking",
                            NULL};
        eo_sim *s = NULL;
        eo_sim_step_result r = {0};
        int rc = eo_test_sim_open(&s, ctx, "cantilever_static", NULL, ov);
        if (rc == 0) rc = eo_test_sim_step(s, NULL, NULL, &r);
        CHECK(rc == 0 && r.reason > 0, "%s: converged (%s)", ov[1], eo_reason_name(r.reason));
        tipv[k] = s ? eo_test_tip_dz(s, 1 - 1e-9) : NAN;
        printf("%s: %d iterations, tip %.15g\n", ov[1], r.iterations, tipv[k]);
        eo_sim_destroy(&s);
    }
    CHECK(fabs(tipv[1] - tipv[0]) <= 1e-9 * fabs(tipv[0]), "same tip: %.15g vs %.15g", tipv[1], tipv[0]);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_nonmonotone");
}
