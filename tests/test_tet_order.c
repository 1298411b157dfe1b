/* The element loops' visit order (suite 'engine', eo_step_set_tet_order, problems/step.c):
 * by default the tets are visited in the Morton order of their rest centroids, which only
 * changes the summation order. Per built-in scene, at the step's starting guess and at a
 * perturbed point (every free coordinate moved by up to 2% of the mesh size, so that F is
 * far from I and some elements are projected), with the Morton order and with the mesh
 * order:
 *  1. g agrees to 1e-12 relative, ∇g entry by entry to 1e-12·‖∇g‖∞, and the
 *     clamp-projected Hessian (the same pattern) entry by entry to 1e-12·max|H|
 *     (measured: at most 6e-16 relative);
 *  2. the order is really different from the mesh order on these scenes: the Morton path
 *     is the default (eo_step_set_tet_order returns 1 when turned back on) and at least
 *     one gradient entry differs in its last bits on the larger scenes (else the test
 *     would compare a path with itself). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/step.h"
#include "engine_util.h"

typedef struct eval {
    double g;
    double *grad, *hval;
    int nnz;
} eval;

static int evaluate(eo_objective *obj, const double *x, eval *e)
{
    const int n = obj->n;
    e->grad = malloc((size_t)n * sizeof(double));
    int rc = eo_objective_gradient(obj, x, &e->g, e->grad);
    eo_csc *H = NULL;
    if (rc >= 0) rc = eo_objective_hessian(obj, x, EO_PROJ_CLAMP, &H);
    if (rc >= 0) {
        e->nnz = H->nnz;
        e->hval = malloc((size_t)H->nnz * sizeof(double));
        memcpy(e->hval, H->val, (size_t)H->nnz * sizeof(double));
    }
    return rc;
}

static void scene(const char *name, int *n_differ)
{
    eo_ctx *ctx = eo_test_ctx();
    eo_sim *s = NULL;
    int rc = eo_test_sim_open(&s, ctx, name, NULL, NULL);
    CHECK(rc == 0, "%s: open", name);
    if (rc) {
        eo_test_ctx_done(&ctx);
        return;
    }
    eo_step *st = eo_sim_step_problem(s);
    eo_objective *obj = NULL;
    double *guess = NULL;
    CHECK(eo_sim_prepare(s, &obj, &guess) == EO_OK, "%s: prepare", name);
    const int n = obj->n;
    double *x = malloc((size_t)n * sizeof(double));
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < n; i++) lo = fmin(lo, guess[i]), hi = fmax(hi, guess[i]);
    srand(7);
    for (int pt = 0; pt < 2; pt++) {
        for (int i = 0; i < n; i++)
            x[i] = guess[i] + (pt ? 0.02 * (hi - lo) * (2.0 * rand() / RAND_MAX - 1) : 0);
        eval a = {0}, b = {0};
        CHECK(eo_step_set_tet_order(st, 1) == 1, "%s: Morton order available", name);
        rc = evaluate(obj, x, &a);
        CHECK(eo_step_set_tet_order(st, 0) == 0, "%s: mesh order", name);
        if (rc >= 0) rc = evaluate(obj, x, &b);
        CHECK(eo_step_set_tet_order(st, 1) == 1, "%s: back to the Morton order", name);
        CHECK(rc >= 0 && a.nnz == b.nnz, "%s: evaluate (rc %d)", name, rc);
        if (rc >= 0 && a.nnz == b.nnz) {
            double gmax = 0, gdiff = 0, hmax = 0, hdiff = 0;
            int differ = 0;
            for (int i = 0; i < n; i++) {
                gmax = fmax(gmax, fabs(a.grad[i]));
                gdiff = fmax(gdiff, fabs(a.grad[i] - b.grad[i]));
                differ |= a.grad[i] != b.grad[i];
            }
            for (int q = 0; q < a.nnz; q++) {
                hmax = fmax(hmax, fabs(a.hval[q]));
                hdiff = fmax(hdiff, fabs(a.hval[q] - b.hval[q]));
            }
            const double gerr = fabs(a.g - b.g) / fabs(a.g);
            printf("  %-18s %s: n = %6d  g %.16e |dg| %.1e  grad %.1e of %.1e  H %.1e of %.1e  %s\n", name,
                   pt ? "perturbed" : "guess    ", n, a.g, gerr, gdiff, gmax, hdiff, hmax,
                   differ ? "(summation order differs)" : "(bitwise equal)");
            CHECK(isfinite(a.g) && gerr <= 1e-12, "%s: g %.17g vs %.17g", name, a.g, b.g);
            CHECK(gdiff <= 1e-12 * gmax, "%s: gradient differs by %.3e (max %.3e)", name, gdiff, gmax);
            CHECK(hdiff <= 1e-12 * hmax && hmax > 0, "%s: Hessian differs by %.3e (max %.3e)", name, hdiff, hmax);
            *n_differ += differ;
        }
        free(a.grad), free(a.hval), free(b.grad), free(b.hval);
    }
    free(x);
    eo_sim_destroy(&s);
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    int n_differ = 0;
    const char *scenes[] = {"cantilever", "twist", "stretch", "drop", "inverted", "cantilever_static"};
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) scene(scenes[i], &n_differ);
    printf("%d evaluations with a different summation order\n", n_differ);
    CHECK(n_differ >= 2, "only %d evaluations differ in the last bits: the orders are the same?", n_differ);
    return eo_test_finish("test_tet_order");
}
