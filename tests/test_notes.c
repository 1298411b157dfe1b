/* The worked examples of notes 002 as tests (issue 12 item 8).
 *
 *   test_notes          (no argument) the four examples that need no optional backend:
 *   - corotated volume term (002 §4.4.3–4.4.4): through the material registry, with
 *     λ = 0 (no volume term) ψ(1.5 I) = ψ(diag(1.5, 0.5, 0.5)) = 0.75 μ to 1e-12; with
 *     λ > 0 they differ, by exactly (λ/2)(1.5² − 0.5²) = λ;
 *   - StVK's reflection problem (002 §4.4.2): ψ(I) = ψ(diag(1, 1, −1)) = 0 (StVK sees only
 *     FᵀF), while stable_neo_hookean tells them apart (ψ(diag(1,1,−1)) > ψ(I) + 1);
 *   - Newton's affine invariance (002 Note 3, corrected in ERRATA: ∇g̃ = Tᵀ∇g,
 *     ∇²g̃ = Tᵀ∇²g T, Δy = T⁻¹Δx): the `newton` optimizer with hessian_fix none and
 *     linesearch none on g(x) = ½xᵀQx + Σ log cosh(xᵢ − sᵢ) (n = 4) and on
 *     g̃(y) = g(Ty) (T random, cond ≈ 10): the same number of iterations, every iterate
 *     x_k = T y_k to 1e-9 relative, and the same g_k;
 *   - CG's termination (002 §3.3.2 / 001 §4.2): the registry's `cg` on n×n SPD systems
 *     (n = 8, 16, 30; eigenvalues evenly spaced in [1, 10], random orthogonal basis):
 *     relative residual after n iterations ≤ 1e-10 (rounding level, not a tolerance
 *     stop), while after n/2 it is still ≥ 1e-7.
 *   test_notes ipopt    002 Example 1: min ½‖Ax‖² subject to ‖x‖² = 1 through Ipopt WITH
 *     the equality constraint (eo_ipopt_minimize_constrained), A random 6×6: x is the
 *     eigenvector of the smallest eigenvalue of AᵀA (LAPACKE dsyev): |xᵀv| = 1 to 1e-8,
 *     ‖x‖ = 1 to 1e-9, g = λ_min/2 to 1e-10, multiplier = −λ_min/2 to 1e-8.
 *     Exit 77 when Ipopt is not built. */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "eo_build_config.h"
#include "elastopt/linsolve.h"
#include "elastopt/material.h"
#include "elastopt/registry.h"
#include "elastopt/impl/method.h"
#include "testutil.h"
#if EO_HAVE_IPOPT
#include "elastopt/ipopt.h"
#endif

#define N_MAX 32

/* ---- a small dense objective: value/gradient/dense Hessian callback, upper CSC ---- */
typedef struct dense_obj {
    int n;
    void (*eval)(const struct dense_obj *d, const double *x, double *g, double *grad, double *H);
    double Q[N_MAX * N_MAX], T[N_MAX * N_MAX], s[N_MAX];  /* problem data */
    int transformed;                                       /* 1: g̃(y) = g(Ty) */
    eo_csc *H;
    double Hd[N_MAX * N_MAX], tmp[N_MAX], tg[N_MAX], tH[N_MAX * N_MAX];
    eo_objective obj;
} dense_obj;

/* g(x) = ½xᵀQx + Σ log cosh(xᵢ − sᵢ) */
static void base_eval(const dense_obj *d, const double *x, double *g, double *grad, double *H)
{
    const int n = d->n;
    double v = 0;
    for (int i = 0; i < n; i++) {
        double Qx = 0;
        for (int j = 0; j < n; j++) Qx += d->Q[i * n + j] * x[j];
        double z = x[i] - d->s[i];
        v += 0.5 * x[i] * Qx + (fabs(z) + log1p(exp(-2 * fabs(z))) - log(2.0));
        if (grad) grad[i] = Qx + tanh(z);
        if (H)
            for (int j = 0; j < n; j++) H[i * n + j] = d->Q[i * n + j] + (i == j ? 1 - tanh(z) * tanh(z) : 0);
    }
    *g = v;
}

/* g or g̃ */
static void obj_eval(dense_obj *d, const double *y, double *g, double *grad, double *H)
{
    const int n = d->n;
    if (!d->transformed) {
        base_eval(d, y, g, grad, H);
        return;
    }
    for (int i = 0; i < n; i++) {
        d->tmp[i] = 0;
        for (int j = 0; j < n; j++) d->tmp[i] += d->T[i * n + j] * y[j];
    }
    base_eval(d, d->tmp, g, grad ? d->tg : NULL, H ? d->tH : NULL);
    if (grad) /* Tᵀ∇g */
        for (int i = 0; i < n; i++) {
            grad[i] = 0;
            for (int k = 0; k < n; k++) grad[i] += d->T[k * n + i] * d->tg[k];
        }
    if (H) /* Tᵀ ∇²g T */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double a = 0;
                for (int k = 0; k < n; k++)
                    for (int l = 0; l < n; l++) a += d->T[k * n + i] * d->tH[k * n + l] * d->T[l * n + j];
                H[i * n + j] = a;
            }
}

static int op_value(void *data, const double *x, double *g)
{
    obj_eval(data, x, g, NULL, NULL);
    return EO_OK;
}
static int op_gradient(void *data, const double *x, double *g, double *grad)
{
    obj_eval(data, x, g, grad, NULL);
    return EO_OK;
}
static int op_hessian(void *data, const double *x, eo_proj proj, eo_csc **H)
{
    (void)proj;
    dense_obj *d = data;
    double g;
    obj_eval(d, x, &g, NULL, d->Hd);
    for (int j = 0, q = 0; j < d->n; j++)
        for (int i = 0; i <= j; i++, q++) d->H->val[q] = 0.5 * (d->Hd[i * d->n + j] + d->Hd[j * d->n + i]);
    *H = d->H;
    return EO_OK;
}
static const eo_objective_ops dense_ops = {.value = op_value, .gradient = op_gradient, .hessian = op_hessian};

static int dense_init(eo_ctx *ctx, dense_obj *d, int n)
{
    d->n = n;
    int rc = eo_csc_create(ctx, n, n * (n + 1) / 2, &d->H);
    if (rc < 0) return rc;
    for (int j = 0, q = 0; j < n; j++) {
        d->H->colptr[j] = q;
        for (int i = 0; i <= j; i++, q++) d->H->rowind[q] = i;
    }
    d->H->colptr[n] = n * (n + 1) / 2;
    d->H->nnz = n * (n + 1) / 2;
    d->obj = (eo_objective){.n = n, .ops = &dense_ops, .data = d};
    return EO_OK;
}

/* ---- solver helper ---- */
typedef struct {
    int n, k;
    double x[64][N_MAX], g[64];
} trace;

static int record(const eo_iter_info *info, void *user)
{
    trace *t = user;
    if (t->k < 64) {
        memcpy(t->x[t->k], info->x, sizeof(double) * (size_t)t->n);
        t->g[t->k] = info->g;
        t->k++;
    }
    return 0;
}

static int minimize(eo_ctx *ctx, eo_objective *obj, const char *const *ov, double *x, trace *tr, eo_solve_result *r)
{
    eo_cfg *cfg = NULL;
    eo_solver *s = NULL;
    eo_solver_opts so;
    eo_solver_opts_default(&so);
    int rc = eo_cfg_create_empty(ctx, &cfg);
    for (const char *const *o = ov; rc >= 0 && *o; o++) rc = eo_cfg_override(ctx, cfg, *o);
    static const char *const top[] = {"solver", NULL};
    if (rc >= 0) eo_cfg_expect(cfg, "", top);
    if (rc >= 0) rc = eo_solver_opts_load(ctx, cfg, &so);
    if (rc >= 0) rc = eo_solver_create(ctx, &so, cfg, &s);
    if (rc >= 0) rc = eo_cfg_finish(ctx, cfg);
    memset(r, 0, sizeof *r);
    if (rc >= 0) rc = eo_solver_minimize(s, obj, x, tr ? record : NULL, tr, r);
    if (rc < 0) fprintf(stderr, "minimize: %s\n", eo_ctx_message(ctx));
    eo_solver_destroy(&s);
    eo_cfg_destroy(&cfg);
    return rc;
}

/* random orthogonal matrix (row-major) from Householder reflections */
static void random_orthogonal(int n, double *Q)
{
    for (int i = 0; i < n * n; i++) Q[i] = i % (n + 1) == 0;
    for (int r = 0; r < 3; r++) {
        double v[N_MAX], vv = 0;
        for (int i = 0; i < n; i++) {
            v[i] = eo_test_rand(-1, 1);
            vv += v[i] * v[i];
        }
        for (int j = 0; j < n; j++) { /* Q ← (I − 2vvᵀ/vᵀv) Q */
            double d = 0;
            for (int i = 0; i < n; i++) d += v[i] * Q[i * n + j];
            for (int i = 0; i < n; i++) Q[i * n + j] -= 2 * v[i] * d / vv;
        }
    }
}

/* ---- corotated volume term, StVK reflection ---- */
static double psi_of(eo_ctx *ctx, const char *model, double E, double nu, const double d[3], double *mu, double *la)
{
    const eo_material_type *mt;
    if (eo_registry_find(ctx, EO_KIND_MATERIAL, model, (const void **)&mt) < 0) return NAN;
    eo_material_coef c = eo_material_coef_from(E, nu, 1000, 1000);
    if (mu) *mu = c.mu;
    if (la) *la = c.lambda;
    double F[9] = {d[0], 0, 0, 0, d[1], 0, 0, 0, d[2]};
    eo_material_eval out;
    if (eo_material_evaluate(mt, &c, F, EO_EVAL_ENERGY, EO_PROJ_NONE, &out) < 0) return NAN;
    return out.psi;
}

static void test_materials(eo_ctx *ctx)
{
    const double F1[3] = {1.5, 1.5, 1.5}, F2[3] = {1.5, 0.5, 0.5}, I3[3] = {1, 1, 1}, R[3] = {1, 1, -1};
    double mu, la;
    /* ν = 0: λ = 0, the corotated energy without its volume term */
    double a = psi_of(ctx, "corotated", 1e5, 0, F1, &mu, &la), b = psi_of(ctx, "corotated", 1e5, 0, F2, NULL, NULL);
    CHECK(la == 0, "nu = 0 gives lambda = %g", la);
    CHECK(fabs(a - b) <= 1e-12 * fabs(a) && fabs(a - 0.75 * mu) <= 1e-12 * a,
          "corotated without volume term: psi(1.5 I) = %.17g, psi(diag(1.5,.5,.5)) = %.17g, 0.75 mu = %.17g", a, b,
          0.75 * mu);
    a = psi_of(ctx, "corotated", 1e5, 0.3, F1, &mu, &la);
    b = psi_of(ctx, "corotated", 1e5, 0.3, F2, NULL, NULL);
    CHECK(fabs((a - b) - la) <= 1e-10 * la, "with volume term: psi difference %.17g = lambda %.17g", a - b, la);
    printf("corotated: psi(1.5I) - psi(diag(1.5,.5,.5)) = %.6g (lambda = %.6g); without volume term 0\n", a - b, la);
    /* StVK reflection */
    a = psi_of(ctx, "stvk", 1e5, 0.3, I3, NULL, NULL);
    b = psi_of(ctx, "stvk", 1e5, 0.3, R, NULL, NULL);
    CHECK(fabs(a) <= 1e-12 && fabs(b) <= 1e-12, "StVK reflection: psi(I) = %g, psi(diag(1,1,-1)) = %g", a, b);
    a = psi_of(ctx, "stable_neo_hookean", 1e5, 0.3, I3, NULL, NULL);
    b = psi_of(ctx, "stable_neo_hookean", 1e5, 0.3, R, NULL, NULL);
    CHECK(isfinite(b) && b > a + 1, "stable_neo_hookean tells them apart: %g vs %g", a, b);
}

/* ---- Newton's affine invariance ---- */
static void test_affine_invariance(eo_ctx *ctx)
{
    const int n = 4;
    dense_obj *A = calloc(1, sizeof *A), *B = calloc(1, sizeof *B);
    CHECK(dense_init(ctx, A, n) == 0 && dense_init(ctx, B, n) == 0, "init");
    eo_test_seed(3);
    double M[N_MAX * N_MAX], O[N_MAX * N_MAX];
    for (int i = 0; i < n * n; i++) M[i] = eo_test_rand(-1, 1);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double q = 0;
            for (int k = 0; k < n; k++) q += M[k * n + i] * M[k * n + j];
            A->Q[i * n + j] = q + (i == j ? 0.5 : 0);
        }
    for (int i = 0; i < n; i++) A->s[i] = eo_test_rand(-2, 2);
    random_orthogonal(n, O);
    for (int i = 0; i < n; i++) /* T = O diag(1..10) (cond 10, not orthogonal) */
        for (int j = 0; j < n; j++) A->T[i * n + j] = O[i * n + j] * (1 + 9.0 * j / (n - 1));
    memcpy(B->Q, A->Q, sizeof A->Q);
    memcpy(B->s, A->s, sizeof A->s);
    memcpy(B->T, A->T, sizeof A->T);
    B->transformed = 1;
    /* x0 and y0 = T⁻¹x0: pick y0, set x0 = T y0 */
    double x[N_MAX], y[N_MAX];
    for (int i = 0; i < n; i++) y[i] = eo_test_rand(-1, 1);
    for (int i = 0; i < n; i++) {
        x[i] = 0;
        for (int j = 0; j < n; j++) x[i] += A->T[i * n + j] * y[j];
    }
    const char *ov[] = {"solver.optimizer=newton", "solver.hessian_fix=none", "solver.linesearch=none",
                        "solver.linear=lapack", "solver.tol=1e-20", "solver.max_iters=40", NULL};
    trace *ta = calloc(1, sizeof *ta), *tb = calloc(1, sizeof *tb);
    ta->n = tb->n = n;
    eo_solve_result ra, rb;
    CHECK(minimize(ctx, &A->obj, ov, x, ta, &ra) == 0 && minimize(ctx, &B->obj, ov, y, tb, &rb) == 0, "minimize");
    CHECK(ra.reason > 0 && rb.reason > 0, "converged: %s, %s", eo_reason_name(ra.reason), eo_reason_name(rb.reason));
    CHECK(ta->k == tb->k && ta->k >= 4, "same iterations: %d vs %d records", ta->k, tb->k);
    double worst = 0;
    for (int k = 0; k < ta->k && k < tb->k; k++) {
        double d = 0, s = 0;
        for (int i = 0; i < n; i++) {
            double Ty = 0;
            for (int j = 0; j < n; j++) Ty += A->T[i * n + j] * tb->x[k][j];
            d = fmax(d, fabs(ta->x[k][i] - Ty));
            s = fmax(s, fabs(ta->x[k][i]));
        }
        worst = fmax(worst, d / fmax(1, s));
        CHECK(d <= 1e-9 * fmax(1, s), "iterate %d: |x_k - T y_k| = %g", k, d);
        CHECK(fabs(ta->g[k] - tb->g[k]) <= 1e-10 * fmax(1, fabs(ta->g[k])), "g_%d: %.17g vs %.17g", k, ta->g[k],
              tb->g[k]);
    }
    printf("newton affine invariance: %d iterates, max |x_k - T y_k| / max(1,|x_k|) = %.2e\n", ta->k, worst);
    eo_csc_destroy(&A->H);
    eo_csc_destroy(&B->H);
    free(A);
    free(B);
    free(ta);
    free(tb);
}

/* ---- CG terminates in n steps ---- */
static double cg_residual(eo_ctx *ctx, const eo_csc *K, const double *b, int iters)
{
    const eo_linsolve_type *t;
    if (eo_linsolve_find(ctx, "cg", &t) < 0) return NAN;
    const eo_param_desc *d = t->info.params;
    void *par = calloc(1, t->info.params_size);
    eo_params_default(d, par);
    *(int *)((char *)par + eo_params_find(d, "max_iters")->offset) = iters;
    *(double *)((char *)par + eo_params_find(d, "tol")->offset) = 1e-300;
    eo_linsolve *ls = NULL;
    double res = NAN, x[N_MAX] = {0};
    if (eo_linsolve_create(ctx, t, par, &ls) == 0 && eo_linsolve_analyze(ls, K) == 0 && eo_linsolve_factor(ls, K) == 0 &&
        eo_linsolve_solve(ls, b, x) >= 0) {
        CHECK(eo_linsolve_get_stats(ls)->iterations <= iters, "iterations %d", eo_linsolve_get_stats(ls)->iterations);
        /* the true residual ‖b − Kx‖/‖b‖ */
        double Kx[N_MAX], r2 = 0, b2 = 0;
        eo_csc_symv(K, x, Kx);
        for (int i = 0; i < K->n; i++) r2 += (b[i] - Kx[i]) * (b[i] - Kx[i]), b2 += b[i] * b[i];
        res = sqrt(r2 / b2);
    }
    eo_linsolve_destroy(&ls);
    free(par);
    return res;
}

static void test_cg(eo_ctx *ctx)
{
    const int ns[3] = {8, 16, 30};
    eo_test_seed(5);
    for (int c = 0; c < 3; c++) {
        const int n = ns[c];
        double Q[N_MAX * N_MAX], b[N_MAX];
        random_orthogonal(n, Q);
        eo_csc *K = NULL;
        CHECK(eo_csc_create(ctx, n, n * (n + 1) / 2, &K) == 0, "csc");
        for (int j = 0, q = 0; j < n; j++) {
            K->colptr[j] = q;
            for (int i = 0; i <= j; i++, q++) {
                double a = 0;
                for (int k = 0; k < n; k++) a += Q[i * n + k] * (1 + 9.0 * k / (n - 1)) * Q[j * n + k];
                K->rowind[q] = i;
                K->val[q] = a;
            }
        }
        K->colptr[n] = K->nnz = n * (n + 1) / 2;
        for (int i = 0; i < n; i++) b[i] = eo_test_rand(-1, 1);
        double rh = cg_residual(ctx, K, b, n / 2), rn = cg_residual(ctx, K, b, n);
        printf("cg n = %d: relative residual after n/2 = %d iterations %.3e, after n: %.3e\n", n, n / 2, rh, rn);
        CHECK(rn <= 1e-10, "n = %d: residual after n iterations %g", n, rn);
        CHECK(rh >= 1e-7, "n = %d: residual after n/2 iterations %g (not yet converged)", n, rh);
        eo_csc_destroy(&K);
    }
}

/* ---- Example 1 through Ipopt with the constraint ---- */
#if EO_HAVE_IPOPT
typedef struct {
    int n;
    double A[N_MAX * N_MAX], AtA[N_MAX * N_MAX];
    eo_csc *H;
    eo_objective obj;
} ex1;

static int ex1_value(void *data, const double *x, double *g)
{
    ex1 *e = data;
    double v = 0;
    for (int i = 0; i < e->n; i++) {
        double Ax = 0;
        for (int j = 0; j < e->n; j++) Ax += e->A[i * e->n + j] * x[j];
        v += 0.5 * Ax * Ax;
    }
    *g = v;
    return EO_OK;
}
static int ex1_gradient(void *data, const double *x, double *g, double *grad)
{
    ex1 *e = data;
    ex1_value(data, x, g);
    for (int i = 0; i < e->n; i++) {
        grad[i] = 0;
        for (int j = 0; j < e->n; j++) grad[i] += e->AtA[i * e->n + j] * x[j];
    }
    return EO_OK;
}
static int ex1_hessian(void *data, const double *x, eo_proj proj, eo_csc **H)
{
    (void)x, (void)proj;
    ex1 *e = data;
    *H = e->H;
    return EO_OK;
}
static const eo_objective_ops ex1_ops = {.value = ex1_value, .gradient = ex1_gradient, .hessian = ex1_hessian};

/* c(x) = xᵀx, ∇c = 2x, ∇²c = 2I */
static int c_value(void *data, const double *x, double *c)
{
    const int n = *(const int *)data;
    c[0] = 0;
    for (int i = 0; i < n; i++) c[0] += x[i] * x[i];
    return EO_OK;
}
static int c_jac(void *data, const double *x, double *J)
{
    const int n = *(const int *)data;
    for (int i = 0; i < n; i++) J[i] = 2 * x[i];
    return EO_OK;
}
static int c_hess(void *data, const double *x, const double *lambda, double *H)
{
    (void)x;
    const int n = *(const int *)data;
    for (int i = 0; i < n * n; i++) H[i] = i % (n + 1) == 0 ? 2 * lambda[0] : 0;
    return EO_OK;
}

static void test_example1(eo_ctx *ctx)
{
    const int n = 6;
    ex1 *e = calloc(1, sizeof *e);
    e->n = n;
    eo_test_seed(17);
    for (int i = 0; i < n * n; i++) e->A[i] = eo_test_rand(-1, 1);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double a = 0;
            for (int k = 0; k < n; k++) a += e->A[k * n + i] * e->A[k * n + j];
            e->AtA[i * n + j] = a;
        }
    CHECK(eo_csc_create(ctx, n, n * (n + 1) / 2, &e->H) == 0, "csc");
    for (int j = 0, q = 0; j < n; j++) {
        e->H->colptr[j] = q;
        for (int i = 0; i <= j; i++, q++) e->H->rowind[q] = i, e->H->val[q] = e->AtA[i * n + j];
    }
    e->H->colptr[n] = e->H->nnz = n * (n + 1) / 2;
    e->obj = (eo_objective){.n = n, .ops = &ex1_ops, .data = e};
    /* reference: eigenvalues ascending, eigenvectors in the columns */
    double W[N_MAX], V[N_MAX * N_MAX];
    memcpy(V, e->AtA, sizeof(double) * n * n);
    CHECK(LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'V', 'U', n, V, n, W) == 0, "dsyev");
    static const double one = 1;
    int nn = n;
    eo_constraints con = {.m = 1, .lower = &one, .upper = &one, .value = c_value, .jacobian = c_jac,
                          .hessian = c_hess, .data = &nn};
    double x[N_MAX], lam = NAN;
    for (int i = 0; i < n; i++) x[i] = 1 / sqrt((double)n);
    eo_solve_result r;
    CHECK(eo_ipopt_minimize_constrained(ctx, &e->obj, &con, NULL, x, &lam, &r) == 0, "ipopt: %s", eo_ctx_message(ctx));
    CHECK(r.reason > 0, "reason %s", eo_reason_name(r.reason));
    double dot = 0, nx = 0;
    for (int i = 0; i < n; i++) dot += x[i] * V[i * n + 0], nx += x[i] * x[i];
    printf("example 1 (ipopt, %d iterations): g = %.15g, lambda_min/2 = %.15g, |x.v| = %.15f, |x| = %.15f, "
           "multiplier %.12g\n",
           r.iterations, r.g, W[0] / 2, fabs(dot), sqrt(nx), lam);
    CHECK(fabs(fabs(dot) - 1) <= 1e-8, "|x.v_min| = %.17g", fabs(dot));
    CHECK(fabs(sqrt(nx) - 1) <= 1e-9, "|x| = %.17g", sqrt(nx));
    CHECK(fabs(r.g - W[0] / 2) <= 1e-10, "g = %.17g, lambda_min/2 = %.17g", r.g, W[0] / 2);
    CHECK(fabs(lam + W[0] / 2) <= 1e-8, "multiplier %.17g, expected %.17g", lam, -W[0] / 2);
    CHECK(W[1] - W[0] > 1e-2, "smallest eigenvalue separated: %g %g", W[0], W[1]);
    /* bad input */
    eo_constraints bad = {.m = 1, .lower = &one, .upper = &one};
    CHECK(eo_ipopt_minimize_constrained(ctx, &e->obj, &bad, NULL, x, NULL, &r) == EO_ERR_INVALID, "missing callbacks");
    eo_csc_destroy(&e->H);
    free(e);
}
#endif

int main(int argc, char **argv)
{
    eo_ctx *ctx = eo_test_ctx();
    if (argc > 1 && strcmp(argv[1], "ipopt") == 0) {
#if EO_HAVE_IPOPT
        test_example1(ctx);
#else
        printf("test_notes ipopt: Ipopt is not built; skipped\n");
        eo_test_ctx_done(&ctx);
        return 77;
#endif
    } else {
        test_materials(ctx);
        test_affine_invariance(ctx);
        test_cg(ctx);
    }
    eo_test_ctx_done(&ctx);
    return eo_test_finish("test_notes");
}
