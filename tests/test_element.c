/* Elements (element.h): the per-element kernel against finite differences and against the
 * linear tet's own kernel, the patch tests (a linear field is an equilibrium of every
 * element and material; a quadratic field under a constant body force is reproduced
 * exactly by p2 and not by p1), the L2 convergence rates of a manufactured solution
 * (≈ 2 for p1, ≈ 3 for p2) and the locking of the nearly incompressible cantilever. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/element.h"
#include "elastopt/mesh.h"
#include "elastopt/registry.h"
#include "engine_util.h"
#include "testutil.h"

static const eo_element_type *element(eo_ctx *ctx, const char *name)
{
    const eo_element_type *el = NULL;
    int rc = eo_registry_find(ctx, EO_KIND_ELEMENT, name, (const void **)&el);
    CHECK(rc == EO_OK && el, "element %s registered", name);
    return el;
}

/* a P2 element on a random tet: X (30), Dminv, V */
static void random_p2(double *X, double Dminv[9], double *V)
{
    static const int edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
    for (;;) {
        static const double ref[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
        for (int i = 0; i < 12; i++) X[i] = ref[i] + 0.3 * (eo_test_rand(-0.5, 0.5));
        if (eo_tet_rest(X, Dminv, V) == EO_OK && *V > 0.05) break;
    }
    for (int e = 0; e < 6; e++)
        for (int c = 0; c < 3; c++) X[3 * (4 + e) + c] = 0.5 * (X[3 * edge[e][0] + c] + X[3 * edge[e][1] + c]);
}

/* Kernel: FD gradient and Hessian of p2 for every tet material; p1 through the generic
 * kernel equals eo_tet_evaluate; an affine field gives V ψ(A) on p2. */
static void test_kernel(eo_ctx *ctx)
{
    const eo_element_type *p1 = element(ctx, "p1"), *p2e = element(ctx, "p2"), *p2p0 = element(ctx, "p2p0");
    if (!p1 || !p2e || !p2p0) return;
    int nmat = 0;
    for (int variant = 0; variant < 2; variant++) {
    const eo_element_type *p2 = variant ? p2p0 : p2e;
    for (const void *const *t = eo_registry_list(EO_KIND_MATERIAL); *t; t++) {
        const eo_material_type *mt = *t;
        if (mt->flags & EO_MATERIAL_EDGE) continue;
        nmat++;
        eo_material_coef c = eo_material_coef_from(1e5, 0.4, 1000, 1);
        double X[30], Dminv[9], V, x[30];
        random_p2(X, Dminv, &V);
        for (int i = 0; i < 30; i++) x[i] = X[i] + 0.08 * (eo_test_rand(-0.5, 0.5));
        double e, g[30], H[900], minJ;
        int rc = eo_element_evaluate(p2, mt, &c, Dminv, V, x, EO_EVAL_HESS, EO_PROJ_NONE, &e, g, H, &minJ);
        CHECK(rc == EO_OK && isfinite(e) && minJ > 0, "%s: p2 evaluation (rc %d, minJ %g)", mt->info.name, rc, minJ);
        double gerr = 0, gmax = 0, herr = 0, hmax = 0;
        for (int i = 0; i < 30; i++) {
            const double h = 1e-6;
            double xp[30], xm[30], ep, em, gp[30], gm[30];
            memcpy(xp, x, sizeof xp), memcpy(xm, x, sizeof xm);
            xp[i] += h, xm[i] -= h;
            eo_element_evaluate(p2, mt, &c, Dminv, V, xp, EO_EVAL_GRAD, EO_PROJ_NONE, &ep, gp, NULL, NULL);
            eo_element_evaluate(p2, mt, &c, Dminv, V, xm, EO_EVAL_GRAD, EO_PROJ_NONE, &em, gm, NULL, NULL);
            gerr = fmax(gerr, fabs((ep - em) / (2 * h) - g[i]));
            gmax = fmax(gmax, fabs(g[i]));
            for (int j = 0; j < 30; j++) {
                herr = fmax(herr, fabs((gp[j] - gm[j]) / (2 * h) - H[30 * j + i]));
                hmax = fmax(hmax, fabs(H[30 * j + i]));
            }
        }
        CHECK(gerr <= 1e-6 * gmax, "%s %s: gradient vs FD: %g of %g", p2->info.name, mt->info.name, gerr, gmax);
        CHECK(herr <= 1e-5 * hmax, "%s %s: Hessian vs FD: %g of %g", p2->info.name, mt->info.name, herr, hmax);
        /* the Hessian alone (grad NULL: the analytic-mode path of isotropic models) equals
         * the one through ∂P/∂F, for every projection */
        for (int pj = 0; pj < 3; pj++) {
            const eo_proj proj = pj == 0 ? EO_PROJ_NONE : pj == 1 ? EO_PROJ_CLAMP : EO_PROJ_ABS;
            double Ha[900], Hb[900], ea, eb, d = 0, m = 0;
            eo_element_evaluate(p2, mt, &c, Dminv, V, x, EO_EVAL_HESS, proj, &ea, g, Ha, NULL);
            eo_element_evaluate(p2, mt, &c, Dminv, V, x, EO_EVAL_HESS, proj, &eb, NULL, Hb, NULL);
            for (int i = 0; i < 900; i++) d = fmax(d, fabs(Ha[i] - Hb[i])), m = fmax(m, fabs(Ha[i]));
            CHECK(d <= 1e-12 * m && fabs(ea - eb) <= 1e-13 * fabs(ea) + 1e-14,
                  "%s %s proj %d: Hessian alone vs through dP/dF: %g of %g", p2->info.name, mt->info.name, pj, d, m);
        }
        /* the projected Hessian is PSD: vᵀHv >= 0 on random directions */
        double Hc[900], worst = 0;
        eo_element_evaluate(p2, mt, &c, Dminv, V, x, EO_EVAL_HESS, EO_PROJ_CLAMP, &e, g, Hc, NULL);
        for (int k = 0; k < 50; k++) {
            double v[30], q = 0, n2 = 0;
            for (int i = 0; i < 30; i++) v[i] = eo_test_rand(-0.5, 0.5), n2 += v[i] * v[i];
            for (int i = 0; i < 30; i++)
                for (int j = 0; j < 30; j++) q += v[i] * Hc[30 * i + j] * v[j];
            worst = fmin(worst, q / n2);
        }
        CHECK(worst >= -1e-9 * hmax, "%s: clamped p2 Hessian PSD on random directions (%g)", mt->info.name, worst);
        /* p1 through the generic kernel = the linear tet's kernel */
        eo_tet_out out;
        eo_tet_evaluate(mt, &c, Dminv, V, x, EO_EVAL_HESS, EO_PROJ_NONE, &out);
        double e1, g1[12], H1[144], d = 0, s = 0;
        eo_element_evaluate(p1, mt, &c, Dminv, V, x, EO_EVAL_HESS, EO_PROJ_NONE, &e1, g1, H1, NULL);
        for (int i = 0; i < 12; i++) d = fmax(d, fabs(g1[i] - out.grad[i])), s = fmax(s, fabs(out.grad[i]));
        for (int i = 0; i < 144; i++) d = fmax(d, fabs(H1[i] - out.hess[i]) * 1e-3);
        CHECK(fabs(e1 - out.energy) <= 1e-12 * fabs(out.energy) + 1e-14 && d <= 1e-10 * s,
              "%s: p1 generic kernel vs eo_tet_evaluate (energy %g vs %g, max diff %g)", mt->info.name, e1, out.energy, d);
        /* an affine field x = A X + b: every point has F = A */
        double A[9] = {1.05, 0.02, -0.01, 0.03, 0.97, 0.04, -0.02, 0.01, 1.02}, xa[30];
        for (int a = 0; a < 10; a++)
            for (int i = 0; i < 3; i++)
                xa[3 * a + i] = A[3 * i] * X[3 * a] + A[3 * i + 1] * X[3 * a + 1] + A[3 * i + 2] * X[3 * a + 2] + 0.1 * i;
        eo_material_eval me;
        eo_material_evaluate(mt, &c, A, EO_EVAL_ENERGY, EO_PROJ_NONE, &me);
        double ea;
        eo_element_evaluate(p2, mt, &c, Dminv, V, xa, EO_EVAL_ENERGY, EO_PROJ_NONE, &ea, NULL, NULL, NULL);
        if (!variant)
            CHECK(fabs(ea - V * me.psi) <= 1e-12 * fabs(V * me.psi) + 1e-12, "%s: p2 affine energy %g vs Vψ(A) %g",
                  mt->info.name, ea, V * me.psi);
    }
    }
    CHECK(nmat >= 12, "tet materials tested (p2, p2p0): %d", nmat);
}


/* The whole step objective of every element (the nodal part of p1anp included) against
 * finite differences: gradient by central differences of g, Hessian (unprojected) by
 * forward differences of ∇g, at a random state of a small clamped bar, per material. */
static void test_objective_fd(eo_ctx *ctx)
{
    const char *els[] = {"p1", "p1anp", "p2", "p2p0"};
    const char *mats[] = {"stable_neo_hookean", "neo_hookean", "fixed_corotated", "stvk"};
    for (int e = 0; e < 4; e++)
        for (int k = 0; k < 4; k++) {
            char json[1024];
            snprintf(json, sizeof json,
                     "{\"mesh\": {\"generate\": {\"size\": [1, 0.3, 0.3], \"cells\": [3, 1, 1], \"split\": 5}},"
                     " \"material\": {\"model\": \"%s\", \"E\": 1e5, \"nu\": 0.49, \"density\": 1000},"
                     " \"element\": \"%s\", \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true}]}",
                     mats[k], els[e]);
            eo_sim *s = NULL;
            if (eo_test_sim_open(&s, ctx, NULL, json, NULL) < 0) {
                CHECK(0, "open %s %s", els[e], mats[k]);
                continue;
            }
            eo_objective *obj = eo_test_sim_obj(s);
            const int n = obj->n;
            double *x = malloc((size_t)n * sizeof *x), *g = malloc((size_t)n * sizeof *g),
                   *g2 = malloc((size_t)n * sizeof *g2), *col = malloc((size_t)n * sizeof *col);
            memcpy(x, eo_test_sim_guess(s), (size_t)n * sizeof *x);
            for (int i = 0; i < n; i++) x[i] += 0.03 * eo_test_rand(-0.5, 0.5);
            double f0, gerr = 0, gmax = 0, herr = 0, hmax = 0;
            eo_objective_gradient(obj, x, &f0, g);
            for (int i = 0; i < n; i++) {
                const double h = 1e-6, xi = x[i];
                double fp, fm;
                x[i] = xi + h, eo_objective_value(obj, x, &fp);
                x[i] = xi - h, eo_objective_value(obj, x, &fm);
                x[i] = xi;
                gerr = fmax(gerr, fabs((fp - fm) / (2 * h) - g[i])), gmax = fmax(gmax, fabs(g[i]));
            }
            eo_csc *H = NULL;
            eo_objective_hessian(obj, x, EO_PROJ_NONE, &H);
            for (int j = 0; j < n && H; j++) {
                const double h = 1e-7, xj = x[j];
                double ff;
                x[j] = xj + h, eo_objective_gradient(obj, x, &ff, g2);
                x[j] = xj;
                memset(col, 0, (size_t)n * sizeof *col);
                for (int c = 0; c < n; c++) /* column j of the symmetric H from its upper triangle */
                    for (int q = H->colptr[c]; q < H->colptr[c + 1]; q++) {
                        if (c == j) col[H->rowind[q]] += H->val[q];
                        else if (H->rowind[q] == j) col[c] += H->val[q];
                    }
                for (int i = 0; i < n; i++)
                    herr = fmax(herr, fabs((g2[i] - g[i]) / h - col[i])), hmax = fmax(hmax, fabs(col[i]));
            }
            CHECK(gerr <= 1e-7 * gmax, "%s %s: objective gradient vs FD %g of %g", els[e], mats[k], gerr, gmax);
            CHECK(herr <= 2e-5 * hmax, "%s %s: objective Hessian vs FD %g of %g", els[e], mats[k], herr, hmax);
            free(x), free(g), free(g2), free(col);
            eo_sim_destroy(&s);
        }
}

/* ---- sim-level: a static box with every surface node prescribed */

static const char *box_json =
    "{\"mesh\": {\"generate\": {\"size\": [1, 1, 1], \"cells\": [%d, %d, %d], \"split\": 6}},"
    " \"material\": {\"model\": \"%s\", \"E\": 1e6, \"nu\": %g, \"density\": 1000},"
    " \"gravity\": [%.17g, %.17g, %.17g], \"element\": \"%s\","
    " \"boundary\": [{\"surface\": true, \"fixed\": true}],"
    " \"time\": {\"integrator\": \"static\", \"dt\": 1, \"steps\": 1},"
    " \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"none\", \"tol\": 1e-13, \"max_iters\": 50,"
    " \"fallback\": []}}";

typedef void (*field_fn)(const double X[3], void *u, double out[3]);

/* Open the box (n cells a side), start from x = X + u(X) on every node (interior nodes
 * perturbed by `perturb` so that the solver has work to do), solve the static step. */
static eo_sim *solve_box(eo_ctx *ctx, int n, const char *material, double nu, double gx, const char *el,
                         field_fn u, void *ud, double perturb)
{
    char json[1024];
    snprintf(json, sizeof json, box_json, n, n, n, material, nu, gx, gx, gx, el);
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, NULL, json, NULL) < 0) return NULL;
    eo_step *st = eo_sim_step_problem(s);
    const eo_mesh *m = eo_step_mesh(st);
    double *x = calloc((size_t)3 * m->nv, sizeof *x), *v = calloc((size_t)3 * m->nv, sizeof *v);
    unsigned char *surf = calloc((size_t)m->nv, 1);
    int ns = 0;
    eo_mesh_surface_vertices(ctx, m, surf, &ns);
    for (int i = 0; i < m->nv; i++) {
        double d[3];
        u(m->X + 3 * i, ud, d);
        for (int c = 0; c < 3; c++)
            x[3 * i + c] = m->X[3 * i + c] + d[c] + (surf[i] ? 0 : perturb * (eo_test_rand(-0.5, 0.5)));
    }
    eo_sim_set_state(s, x, v, 0, 0);
    eo_sim_step_result r;
    int rc = eo_test_sim_step(s, NULL, NULL, &r);
    CHECK(rc == EO_OK && r.reason > 0, "box n=%d %s %s: static solve (rc %d, reason %d)", n, el, material, rc, r.reason);
    free(x), free(v), free(surf);
    return s;
}

/* max over nodes of |x − X − u(X)| */
static double nodal_error(eo_sim *s, field_fn u, void *ud)
{
    const eo_step *st = eo_sim_step_problem(s);
    const eo_mesh *m = eo_step_mesh(st);
    const double *x = eo_step_x(st);
    double err = 0;
    for (int i = 0; i < m->nv; i++) {
        double d[3];
        u(m->X + 3 * i, ud, d);
        for (int c = 0; c < 3; c++) err = fmax(err, fabs(x[3 * i + c] - m->X[3 * i + c] - d[c]));
    }
    return err;
}

static double l2_error(eo_sim *s, const eo_element_type *el, field_fn f, void *ud);

static void affine(const double X[3], void *ud, double out[3])
{
    (void)ud;
    static const double A[9] = {0.02, 0.01, -0.015, 0.005, -0.01, 0.02, 0.01, 0.0, 0.03};
    for (int i = 0; i < 3; i++) out[i] = A[3 * i] * X[0] + A[3 * i + 1] * X[1] + A[3 * i + 2] * X[2] + 0.01 * i;
}

static void quadratic(const double X[3], void *ud, double out[3])
{
    const double a = *(const double *)ud;
    out[0] = a * X[1] * X[1], out[1] = a * X[2] * X[2], out[2] = a * X[0] * X[0];
}

/* Patch tests. Linear: x = A X + b on the boundary is an equilibrium (constant F), so the
 * interior nodes return to it exactly for every material and element. Quadratic:
 * u = a (y², z², x²) under linear elasticity has div u = 0 and Δu = 2a (1, 1, 1), so
 * div σ = μΔu + (λ + μ)∇div u = 2aμ (1, 1, 1), balanced by the body force
 * ρg = −2aμ (1, 1, 1); it lies in the p2 space, so p2 reproduces it exactly (the
 * consistent load is exact), while p1 does not. */
static void test_patch(eo_ctx *ctx)
{
    const char *mats[] = {"linear", "stable_neo_hookean", "neo_hookean", "fixed_corotated"};
    const char *els[] = {"p1", "p2", "p2p0", "p1anp"};
    for (int e = 0; e < 4; e++)
        for (int k = 0; k < 4; k++) {
            eo_sim *s = solve_box(ctx, 2, mats[k], 0.45, 0, els[e], affine, NULL, 0.02);
            if (!s) continue;
            double err = nodal_error(s, affine, NULL);
            CHECK(err < 1e-10, "linear patch test, %s %s: max nodal error %.3g", els[e], mats[k], err);
            eo_sim_destroy(&s);
        }
    const double E = 1e6, nu = 0.3, mu = E / (2 * (1 + nu)), lam = E * nu / ((1 + nu) * (1 - 2 * nu)), a = 0.01;
    const double gx = -2 * a * mu / 1000;
    (void)lam;
    double err[2] = {0, 0};
    for (int e = 0; e < 2; e++) {
        double ad = a;
        eo_sim *s = solve_box(ctx, 3, "linear", nu, gx, els[e], quadratic, &ad, 0.02);
        if (!s) continue;
        err[e] = l2_error(s, element(ctx, els[e]), quadratic, &ad);
        CHECK(nodal_error(s, quadratic, &ad) < 1e-10, "quadratic field, %s: nodal values exact (%.3g)", els[e],
              nodal_error(s, quadratic, &ad)); /* p1 too: its stencil on a uniform mesh is exact for quadratics */
        eo_sim_destroy(&s);
    }
    CHECK(err[1] < 1e-12, "quadratic patch test, p2: L2 error %.3g", err[1]);
    CHECK(err[0] > 1e-5, "quadratic patch test, p1 is not exact: L2 error %.3g", err[0]);
    printf("quadratic patch (u = 0.01 (y^2, z^2, x^2)): L2 error p1 %.3g, p2 %.3g\n", err[0], err[1]);
}

/* ---- manufactured solution: u = ε∇φ, φ = eˣ cos y harmonic, so div u = 0 and Δu = 0:
 * an equilibrium of linear elasticity for every λ, μ with no body force. Dirichlet data
 * on the whole surface; L2 error by a 64-point collapsed Gauss rule per tet. */

static void harmonic(const double X[3], void *ud, double out[3])
{
    (void)ud;
    const double eps = 0.01;
    out[0] = eps * exp(X[0]) * cos(X[1]);
    out[1] = -eps * exp(X[0]) * sin(X[1]);
    out[2] = 0;
}

static double l2_error(eo_sim *s, const eo_element_type *el, field_fn f, void *ud)
{
    static const double gx[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
    static const double gw[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269};
    const eo_step *st = eo_sim_step_problem(s);
    const eo_mesh *m = eo_step_mesh(st);
    const double *x = eo_step_x(st);
    const int n = el->nodes;
    double sum = 0;
    for (int t = 0; t < m->nt; t++) {
        const int *en = n == 10 ? m->tet10 + 10 * t : m->tets + 4 * t;
        const double V = fabs(eo_tet_volume(m->X, m->tets + 4 * t));
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                for (int k = 0; k < 4; k++) { /* Duffy: (u, v, w) in the cube -> barycentric */
                    const double u = gx[i], v = gx[j], w = gx[k];
                    const double l1 = u, l2 = (1 - u) * v, l3 = (1 - u) * (1 - v) * w, l0 = 1 - l1 - l2 - l3;
                    const double wt = gw[i] * gw[j] * gw[k] * (1 - u) * (1 - u) * (1 - v) * 6 * V;
                    const double lam[4] = {l0, l1, l2, l3};
                    double N[EO_ELEMENT_MAX_NODES], X[3] = {0, 0, 0}, uh[3] = {0, 0, 0}, ue[3];
                    el->shape(lam, N, NULL);
                    for (int a = 0; a < 4; a++)
                        for (int c = 0; c < 3; c++) X[c] += lam[a] * m->X[3 * m->tets[4 * t + a] + c];
                    for (int a = 0; a < n; a++)
                        for (int c = 0; c < 3; c++) uh[c] += N[a] * (x[3 * en[a] + c] - m->X[3 * en[a] + c]);
                    f(X, ud, ue);
                    for (int c = 0; c < 3; c++) sum += wt * (uh[c] - ue[c]) * (uh[c] - ue[c]);
                }
    }
    return sqrt(sum);
}

static void test_rates(eo_ctx *ctx)
{
    const char *els[] = {"p1", "p2"};
    const int ns[3] = {2, 4, 8};
    for (int e = 0; e < 2; e++) {
        const eo_element_type *el = element(ctx, els[e]);
        double err[3] = {0, 0, 0};
        for (int q = 0; q < 3; q++) {
            eo_sim *s = solve_box(ctx, ns[q], "linear", 0.3, 0, els[e], harmonic, NULL, 0.0);
            if (!s || !el) continue;
            err[q] = l2_error(s, el, harmonic, NULL);
            eo_sim_destroy(&s);
        }
        const double r1 = log2(err[0] / err[1]), r2 = log2(err[1] / err[2]);
        printf("manufactured solution, %s: L2 error %.3e %.3e %.3e (n = 2, 4, 8), rates %.2f %.2f\n", els[e], err[0],
               err[1], err[2], r1, r2);
        const double want = e == 0 ? 2 : 3;
        CHECK(fabs(r2 - want) < 0.3, "%s: L2 rate %.2f, expected about %g", els[e], r2, want);
    }
}


/* The nearly incompressible cantilever (1 × 0.1 × 0.1 m, clamped face, gravity,
 * stable neo-Hookean E = 1e9: the linear regime) against Timoshenko beam theory,
 * δ = qL⁴/(8EI) + qL²/(2κGA), κ = 10(1 + ν)/(12 + 11ν) (Cowper 1966). The fully clamped
 * face also holds the root's Poisson contraction, which beam theory leaves free: the
 * mesh-converged 3D answer (p2p0, 10.8k tets) is 0.991 of δ at ν = 0.3, 0.9744 at 0.49
 * and 0.9725 at 0.4999; the elements are held to that. Two meshes: the generated
 * 20×2×2 bar (400 tets, always) and an unstructured TetGen bar (11.7k tets, when the
 * TetGen library is built in), on which the linear tet locks completely. */
/* beam_root: instead of the fully clamped face, the root of beam theory: u_x held on the
 * face (which is free to contract), the rigid modes removed by one full vertex at the
 * face's centre and u_y at one more ("components", scene.h) */
static double cantilever_ratio_root(eo_ctx *ctx, const char *el, double nu, const char *mesh, int beam_root);

static double cantilever_ratio(eo_ctx *ctx, const char *el, double nu, const char *mesh)
{
    return cantilever_ratio_root(ctx, el, nu, mesh, 0);
}

static double cantilever_ratio_root(eo_ctx *ctx, const char *el, double nu, const char *mesh, int beam_root)
{
    char json[1536];
    snprintf(json, sizeof json,
             "{\"mesh\": %s, \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e9, \"nu\": %g, \"density\": 1000},"
             " \"gravity\": [0, 0, -9.81], \"element\": \"%s\","
             " \"boundary\": %s,"
             " \"time\": {\"integrator\": \"static\", \"dt\": 1, \"steps\": 1},"
             " \"solver\": {\"optimizer\": \"newton\", \"hessian_fix\": \"clamp\", \"tol\": 1e-10}}",
             mesh, nu, el,
             beam_root ? "[{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true, \"components\": \"x\"},"
                         " {\"nearest\": [0, 0.05, 0.05], \"fixed\": true},"
                         " {\"nearest\": [0, 0.05, 0.1], \"fixed\": true, \"components\": \"y\"}]"
                       : "[{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true}]");
    eo_sim *s = NULL;
    if (eo_test_sim_open(&s, ctx, NULL, json, NULL) < 0) return NAN;
    eo_sim_step_result r;
    int rc = eo_test_sim_step(s, NULL, NULL, &r);
    CHECK(rc == EO_OK && r.reason > 0 && r.iterations >= 2, "cantilever %s nu %g: converged (reason %d, %d iterations)",
          el, nu, r.reason, r.iterations);
    const double tip = -eo_test_tip_dz(s, 1 - 1e-9);
    eo_sim_destroy(&s);
    const double E = 1e9, q = 1000 * 9.81 * 0.01, I = 0.1 * 0.001 / 12, G = E / (2 * (1 + nu));
    const double kap = 10 * (1 + nu) / (12 + 11 * nu), d = q / (8 * E * I) + q / (2 * kap * G * 0.01);
    return tip / d;
}

static void test_cantilever(eo_ctx *ctx)
{
    static const char *gen = "{\"generate\": {\"size\": [1, 0.1, 0.1], \"cells\": [20, 2, 2], \"split\": 5}}";
    const double nus[3] = {0.3, 0.49, 0.4999}, conv[3] = {0.991, 0.9744, 0.9725};
    const char *els[4] = {"p1", "p1anp", "p2", "p2p0"};
    for (int i = 0; i < 3; i++) {
        double r[4];
        for (int e = 0; e < 4; e++) r[e] = cantilever_ratio(ctx, els[e], nus[i], gen);
        printf("cantilever nu = %g, 400 tets: tip / Timoshenko  p1 %.4f  p1anp %.4f  p2 %.4f  p2p0 %.4f  (3D %.4f)\n",
               nus[i], r[0], r[1], r[2], r[3], conv[i]);
        CHECK(fabs(r[3] / conv[i] - 1) < 0.01, "p2p0 at nu %g: %.4f vs converged %.4f", nus[i], r[3], conv[i]);
        CHECK(fabs(r[2] / conv[i] - 1) < 0.05, "p2 at nu %g: %.4f vs converged %.4f", nus[i], r[2], conv[i]);
        CHECK(r[0] < 0.7 && r[1] < 0.7, "the linear tets are stiff in bending on this mesh at nu %g: %.4f %.4f", nus[i],
              r[0], r[1]);
    }
    if (!eo_mesh_have_tetgen()) {
        printf("cantilever on an unstructured mesh skipped: built without the TetGen library (-Dtetgen)\n");
        return;
    }
    static const char *obj =
        "v 0 0 0\nv 1 0 0\nv 1 0.1 0\nv 0 0.1 0\nv 0 0 0.1\nv 1 0 0.1\nv 1 0.1 0.1\nv 0 0.1 0.1\n"
        "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    char path[512], mesh[700];
    snprintf(path, sizeof path, "%s/bar.obj", eo_test_tmpdir("test_element"));
    FILE *f = fopen(path, "w");
    if (!f) {
        CHECK(0, "cannot write %s", path);
        return;
    }
    fputs(obj, f);
    fclose(f);
    snprintf(mesh, sizeof mesh, "{\"file\": \"%s\", \"tetgen\": {\"max_volume\": 2e-6}}", path);
    for (int i = 1; i < 3; i++) {
        double r[4];
        for (int e = 0; e < 4; e++) r[e] = cantilever_ratio(ctx, els[e], nus[i], mesh);
        printf("cantilever nu = %g, TetGen 11.7k tets: tip / Timoshenko  p1 %.4f  p1anp %.4f  p2 %.4f  p2p0 %.4f\n",
               nus[i], r[0], r[1], r[2], r[3]);
        CHECK(fabs(r[3] / conv[i] - 1) < 0.01, "p2p0 (TetGen) at nu %g: %.4f vs converged %.4f", nus[i], r[3], conv[i]);
        CHECK(fabs(r[2] / conv[i] - 1) < 0.02, "p2 (TetGen) at nu %g: %.4f vs converged %.4f", nus[i], r[2], conv[i]);
        CHECK(r[1] > 0.8, "p1anp (TetGen) does not lock at nu %g: %.4f", nus[i], r[1]);
        if (i == 2) CHECK(r[0] < 0.1, "p1 (TetGen) locks at nu 0.4999: %.4f", r[0]);
    }
    /* the root of beam theory (u_x held, the face free to contract): p2 and p2p0 within 2%
     * of Timoshenko on the unstructured bar, p1 locked */
    for (int i = 1; i < 3; i++) {
        double r[4];
        for (int e = 0; e < 4; e++) r[e] = cantilever_ratio_root(ctx, els[e], nus[i], mesh, 1);
        printf("cantilever nu = %g, TetGen 11.7k tets, beam-theory root: tip / Timoshenko  p1 %.4f  p1anp %.4f  p2 %.4f  "
               "p2p0 %.4f\n", nus[i], r[0], r[1], r[2], r[3]);
        CHECK(fabs(r[2] - 1) < 0.02, "p2 (TetGen, beam root) at nu %g within 2%% of beam theory: %.4f", nus[i], r[2]);
        CHECK(fabs(r[3] - 1) < 0.02, "p2p0 (TetGen, beam root) at nu %g within 2%% of beam theory: %.4f", nus[i], r[3]);
        CHECK(r[1] > 0.85, "p1anp (TetGen, beam root) at nu %g: %.4f", nus[i], r[1]);
        if (i == 2) CHECK(r[0] < 0.1, "p1 (TetGen, beam root) locks at nu 0.4999: %.4f", r[0]);
    }
}

/* Boundary entries that hold some components only ("components"): a box whose every
 * vertex has u_z held falls freely in y under gravity (0, −9.81, −9.81), with implicit and
 * explicit integrators and both masses: u_z stays exactly 0, the centre of mass follows
 * −g t²/2 (backward Euler lags by its O(h) damping of the start). */
static void test_components(eo_ctx *ctx)
{
    const char *integ[3] = {"newmark", "backward_euler", "rk4"};
    const char *mass[2] = {"consistent", "lumped"};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 2; k++) {
            const double dt = i == 2 ? 1e-4 : 1e-3;
            char json[1024];
            snprintf(json, sizeof json,
                     "{\"mesh\": {\"generate\": {\"size\": [1, 1, 1], \"cells\": [2, 2, 2], \"split\": 5}},"
                     " \"material\": {\"model\": \"stable_neo_hookean\", \"E\": 1e5, \"nu\": 0.3, \"density\": 1000},"
                     " \"mass\": \"%s\", \"gravity\": [0, -9.81, -9.81], \"element\": \"p2\","
                     " \"boundary\": [{\"box\": [[-1, -1, -1], [2, 2, 2]], \"fixed\": true, \"components\": \"z\"}],"
                     " \"time\": {\"integrator\": \"%s\", \"dt\": %g, \"steps\": 4}}",
                     mass[k], integ[i], dt);
            eo_sim *s = NULL;
            if (eo_test_sim_open(&s, ctx, NULL, json, NULL) < 0) {
                CHECK(0, "components: open %s %s", integ[i], mass[k]);
                continue;
            }
            int ok = 1;
            for (int n = 0; n < 4 && ok; n++) ok = eo_test_sim_step(s, NULL, NULL, NULL) >= 0;
            const eo_step *st = eo_sim_step_problem(s);
            const eo_mesh *m = eo_step_mesh(st);
            const double *x = eo_step_x(st);
            double uz = 0, uy = 0, mt = 0; /* the mass-weighted mean: the centre of mass */
            const double *mv = eo_step_vertex_mass(st);
            for (int v = 0; v < m->nv; v++) {
                uz = fmax(uz, fabs(x[3 * v + 2] - m->X[3 * v + 2]));
                uy += mv[v] * (x[3 * v + 1] - m->X[3 * v + 1]);
                mt += mv[v];
            }
            uy /= mt;
            const double t = 4 * dt, free_fall = -9.81 * t * t / 2;
            CHECK(ok && uz == 0, "components z, %s %s: u_z held exactly (%g)", integ[i], mass[k], uz);
            CHECK(fabs(uy / free_fall - 1) < (i == 1 ? 0.6 : 0.05), "components z, %s %s: mean u_y %g vs free fall %g",
                  integ[i], mass[k], uy, free_fall);
            eo_sim_destroy(&s);
        }
}

/* Refusals at load (exit 2 in the CLI, nothing built): optimizers that need the linear
 * tet's per-tet operations on other elements; a curved 10-node mesh for the straight-sided
 * elements; a 10-node mesh with the 4-node element. */
static int open_fails(eo_ctx *ctx, const char *json, const char *const *ov, const char *needle)
{
    eo_cfg *cfg = NULL;
    eo_sim *s = NULL;
    int rc = eo_cfg_load(ctx, NULL, json, &cfg);
    for (const char *const *o = ov; rc >= 0 && o && *o; o++) rc = eo_cfg_override(ctx, cfg, *o);
    if (rc >= 0) {
        rc = eo_sim_create(ctx, cfg, &s);
        cfg = NULL;
    }
    eo_cfg_destroy(&cfg);
    const int ok = rc < 0 && strstr(eo_ctx_message(ctx), needle) != NULL;
    if (!ok) fprintf(stderr, "open_fails: rc %d, message: %s\n", rc, eo_ctx_message(ctx));
    eo_sim_destroy(&s);
    return ok;
}

static void test_refusals(eo_ctx *ctx)
{
    static const char *bar = "{\"mesh\": {\"generate\": {\"size\": [1, 0.1, 0.1], \"cells\": [4, 1, 1]}},"
                             " \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 1, 1]], \"fixed\": true}]}";
    const char *admm[] = {"element=p2", "solver.optimizer=admm_pd", NULL};
    const char *vbd[] = {"element=p1anp", "solver.optimizer=vbd", NULL};
    const char *fb[] = {"element=p2p0", "solver.fallback=[{\"optimizer\": \"mixed_fem\"}]", NULL};
    CHECK(open_fails(ctx, bar, admm, "optimizer admm_pd needs the per-tet split"), "admm_pd refused on p2");
    CHECK(open_fails(ctx, bar, vbd, "optimizer vbd needs per-vertex blocks"), "vbd refused on p1anp");
    CHECK(open_fails(ctx, bar, fb, "solver.fallback.0: optimizer mixed_fem"), "mixed_fem refused in a fallback on p2p0");
    /* a quadratic Gmsh file with one midside node moved off its edge */
    eo_mesh *m = NULL, *q = NULL;
    eo_mesh_gen_opts go = eo_mesh_gen_opts_default();
    go.cells[0] = 3, go.cells[1] = go.cells[2] = 1;
    if (eo_mesh_generate_box(ctx, &go, &m) < 0 || eo_mesh_to_quadratic(ctx, m, &q) < 0) {
        CHECK(0, "quadratic box: %s", eo_ctx_message(ctx));
        eo_mesh_destroy(&m);
        return;
    }
    char straight[512], curved[512], json[1024];
    snprintf(straight, sizeof straight, "%s/straight.msh", eo_test_tmpdir("test_element_refusals"));
    snprintf(curved, sizeof curved, "%s/curved.msh", eo_test_tmpdir("test_element_refusals"));
    CHECK(eo_mesh_write(ctx, q, straight, EO_MESH_AUTO) == EO_OK, "write %s", straight);
    q->X[3 * q->tet10[4] + 1] += 0.05; /* the midside node of tet 0's edge 01 */
    CHECK(eo_mesh_write(ctx, q, curved, EO_MESH_AUTO) == EO_OK, "write %s", curved);
    snprintf(json, sizeof json,
             "{\"mesh\": {\"file\": \"%s\"}, \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 2, 2]], \"fixed\": true}]}",
             curved);
    const char *p2[] = {"element=p2", NULL};
    CHECK(open_fails(ctx, json, p2, "off the edge's midpoint"), "a curved 10-node mesh refused by p2");
    snprintf(json, sizeof json,
             "{\"mesh\": {\"file\": \"%s\"}, \"boundary\": [{\"box\": [[-1, -1, -1], [1e-9, 2, 2]], \"fixed\": true}]}",
             straight);
    CHECK(open_fails(ctx, json, NULL, "the mesh has 10-node (quadratic) tets"), "a 10-node mesh refused by p1");
    eo_sim *s = NULL;
    CHECK(eo_test_sim_open(&s, ctx, NULL, json, p2) == EO_OK, "the straight 10-node file runs as p2");
    eo_sim_destroy(&s);
    eo_mesh_destroy(&q);
    eo_mesh_destroy(&m);
}

int main(void)
{
    eo_ctx *ctx = eo_test_ctx();
    test_kernel(ctx);
    test_objective_fd(ctx);
    test_patch(ctx);
    test_rates(ctx);
    test_cantilever(ctx);
    test_components(ctx);
    test_refusals(ctx);
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_element");
}
