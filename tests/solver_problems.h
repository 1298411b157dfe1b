/* Small analytic test problems shared by the optimizer suites (test_solvers,
 * test_external_optim): convex quadratic, the notes' ill-conditioned quadratic, extended
 * Rosenbrock, a −log barrier that is +∞ outside its domain, separable double wells.
 * Each is an eo_objective (prob_objective) whose Hessian goes through the fixed-pattern
 * assembler (prob_init builds it; prob_done frees it). Header-only like engine_util.h. */
#ifndef EO_TESTS_SOLVER_PROBLEMS_H
#define EO_TESTS_SOLVER_PROBLEMS_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/objective.h"
#include "testutil.h"

enum { P_QUAD, P_ILL, P_ROSEN, P_BARRIER, P_DWELL, P_COUNT };
#define NMAX 8

typedef struct tprob {
    int kind, n;
    const char *name;
    double x0[NMAX], xstar[NMAX], gstar;
    double A[NMAX * NMAX], b[NMAX];  /* quad */
    double gamma;                      /* ill */
    double a[NMAX];                    /* barrier, dwell coefficients */
    int with_metric;
    /* runtime: Hessian assembled per element (quad, ill: one dense element; Rosenbrock:
     * one 2×2 element per pair, projected as asked; barrier, wells: 1×1 elements whose
     * projection is ignored, as for terms without per-element structure) */
    eo_assembler *as;
    int hgroup, ne, ke;
    eo_csc *H;
    double Hd[NMAX * NMAX], gs[NMAX];
    long n_inf;
} tprob;

/* value, gradient (if grad), dense Hessian (if Hd); +INFINITY outside the domain */
static inline double peval(tprob *p, const double *x, double *grad, double *Hd)
{
    const int n = p->n;
    double g = 0;
    if (grad) memset(grad, 0, sizeof(double) * n);
    if (Hd) memset(Hd, 0, sizeof(double) * n * n);
    switch (p->kind) {
    case P_QUAD:
        for (int i = 0; i < n; i++) {
            double Ax = 0;
            for (int j = 0; j < n; j++) Ax += p->A[i * n + j] * x[j];
            g += 0.5 * x[i] * Ax - p->b[i] * x[i];
            if (grad) grad[i] = Ax - p->b[i];
            if (Hd)
                for (int j = 0; j < n; j++) Hd[i * n + j] = p->A[i * n + j];
        }
        break;
    case P_ILL:
        g = 0.5 * (x[0] * x[0] + p->gamma * x[1] * x[1]);
        if (grad) grad[0] = x[0], grad[1] = p->gamma * x[1];
        if (Hd) Hd[0] = 1, Hd[3] = p->gamma;
        break;
    case P_ROSEN:
        for (int i = 0; i < n; i += 2) {
            double u = x[i], v = x[i + 1], r = v - u * u;
            g += 100 * r * r + (1 - u) * (1 - u);
            if (grad) grad[i] = -400 * r * u - 2 * (1 - u), grad[i + 1] = 200 * r;
            if (Hd) {
                Hd[i * n + i] = 1200 * u * u - 400 * v + 2;
                Hd[i * n + i + 1] = Hd[(i + 1) * n + i] = -400 * u;
                Hd[(i + 1) * n + i + 1] = 200;
            }
        }
        break;
    case P_BARRIER:
        for (int i = 0; i < n; i++) {
            if (!(x[i] > 0)) {
                p->n_inf++;
                return INFINITY;
            }
            g += p->a[i] * x[i] - log(x[i]) + 0.5 * (x[i] - 1 / p->a[i]) * (x[i] - 1 / p->a[i]);
            if (grad) grad[i] = p->a[i] - 1 / x[i] + (x[i] - 1 / p->a[i]);
            if (Hd) Hd[i * n + i] = 1 / (x[i] * x[i]) + 1;
        }
        break;
    case P_DWELL:
        for (int i = 0; i < n; i++) {
            double t = x[i];
            g += t * t * t * t / 4 - t * t / 2 + p->a[i] * t;
            if (grad) grad[i] = t * t * t - t + p->a[i];
            if (Hd) Hd[i * n + i] = 3 * t * t - 1;
        }
        break;
    }
    return g;
}

static inline int op_value(void *d, const double *x, double *g)
{
    *g = peval(d, x, NULL, NULL);
    return EO_OK;
}
static inline int op_gradient(void *d, const double *x, double *g, double *grad)
{
    *g = peval(d, x, grad, NULL);
    return EO_OK;
}
/* Ke ← Q f(Λ) Qᵀ for a symmetric 2×2 Ke, f = max(·, 0) (clamp) or |·| (abs) */
static inline void proj2(double *K, eo_proj proj)
{
    double a = K[0], b = K[1], c = K[3];
    double m = 0.5 * (a + c), r = sqrt(0.25 * (a - c) * (a - c) + b * b);
    double l[2] = {m + r, m - r}, v[2][2];
    if (r == 0) {
        v[0][0] = 1, v[0][1] = 0, v[1][0] = 0, v[1][1] = 1;
    } else {
        double x = b, y = l[0] - a; /* eigenvector of l0: (b, l0 - a) or (l0 - c, b) */
        if (fabs(x) + fabs(y) < 1e-300) x = l[0] - c, y = b;
        double nn = sqrt(x * x + y * y);
        v[0][0] = x / nn, v[0][1] = y / nn, v[1][0] = -y / nn, v[1][1] = x / nn;
    }
    for (int i = 0; i < 2; i++) l[i] = proj == EO_PROJ_CLAMP ? fmax(l[i], 0) : fabs(l[i]);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) K[i * 2 + j] = l[0] * v[0][i] * v[0][j] + l[1] * v[1][i] * v[1][j];
}

static inline int op_hessian(void *d, const double *x, eo_proj proj, eo_csc **H)
{
    tprob *p = d;
    const int n = p->n, k = p->ke;
    double Ke[NMAX * NMAX];
    peval(p, x, p->gs, p->Hd);
    eo_assembler_zero(p->as);
    for (int e = 0; e < p->ne; e++) {
        int o = e * k;
        for (int i = 0; i < k; i++)
            for (int j = 0; j < k; j++) Ke[i * k + j] = p->Hd[(o + i) * n + o + j];
        if (p->kind == P_ROSEN && proj != EO_PROJ_NONE) proj2(Ke, proj);
        eo_assembler_add(p->as, p->hgroup, e, Ke);
    }
    *H = p->H;
    return EO_OK;
}

static inline int op_metric(void *d, double *m)
{
    tprob *p = d;
    for (int i = 0; i < p->n; i++) m[i] = p->A[i * p->n + i];
    return EO_OK;
}
static inline int op_inverted(void *d, const double *x)
{
    tprob *p = d;
    int c = 0;
    for (int i = 0; i < p->n; i++) c += x[i] <= 0;
    return c;
}

static const eo_objective_ops ops_plain = {.value = op_value, .gradient = op_gradient,
                                           .hessian = op_hessian};
static const eo_objective_ops ops_metric = {.value = op_value, .gradient = op_gradient,
                                            .hessian = op_hessian, .metric_diag = op_metric};
static const eo_objective_ops ops_barrier = {.value = op_value, .gradient = op_gradient,
                                             .hessian = op_hessian, .inverted_count = op_inverted};

/* local minimizer of t⁴/4 − t²/2 + c t nearest to t (Newton from the right well) */
static inline double dwell_min(double c, double t)
{
    double r = t >= 0 ? 1.5 : -1.5;
    for (int k = 0; k < 100; k++) r -= (r * r * r - r + c) / (3 * r * r - 1);
    return r;
}

static inline void prob_init(eo_ctx *ctx, tprob *p, int kind)
{
    memset(p, 0, sizeof *p);
    p->kind = kind;
    switch (kind) {
    case P_QUAD: {
        p->name = "quad";
        p->n = 5;
        p->with_metric = 1;
        double B[25];
        eo_test_seed(7);
        for (int i = 0; i < 25; i++) B[i] = eo_test_rand(-1, 1);
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 5; j++) {
                double s = i == j ? 1 + i : 0; /* diag spread: A = BᵀB + diag(1..5) */
                for (int k = 0; k < 5; k++) s += B[k * 5 + i] * B[k * 5 + j];
                p->A[i * 5 + j] = s;
            }
        for (int i = 0; i < 5; i++) p->b[i] = eo_test_rand(-2, 2), p->x0[i] = eo_test_rand(-3, 3);
        /* x* = A⁻¹b by Gaussian elimination */
        double M[25], y[5];
        memcpy(M, p->A, sizeof M);
        memcpy(y, p->b, sizeof y);
        for (int k = 0; k < 5; k++)
            for (int i = k + 1; i < 5; i++) {
                double f = M[i * 5 + k] / M[k * 5 + k];
                for (int j = k; j < 5; j++) M[i * 5 + j] -= f * M[k * 5 + j];
                y[i] -= f * y[k];
            }
        for (int i = 4; i >= 0; i--) {
            double s = y[i];
            for (int j = i + 1; j < 5; j++) s -= M[i * 5 + j] * p->xstar[j];
            p->xstar[i] = s / M[i * 5 + i];
        }
        p->gstar = peval(p, p->xstar, NULL, NULL);
        break;
    }
    case P_ILL:
        p->name = "ill";
        p->n = 2;
        p->gamma = 10;
        p->x0[0] = 10, p->x0[1] = 1;
        break;
    case P_ROSEN:
        p->name = "rosenbrock";
        p->n = 4;
        p->x0[0] = -1.2, p->x0[1] = 1, p->x0[2] = 0.5, p->x0[3] = 1; /* (0.5,1): H indefinite */
        for (int i = 0; i < 4; i++) p->xstar[i] = 1;
        break;
    case P_BARRIER: {
        p->name = "barrier";
        p->n = 4;
        const double a[4] = {1, 2, 5, 10};
        for (int i = 0; i < 4; i++) p->a[i] = a[i], p->x0[i] = 3, p->xstar[i] = 1 / a[i];
        p->gstar = peval(p, p->xstar, NULL, NULL);
        break;
    }
    case P_DWELL: {
        p->name = "double_well";
        p->n = 3;
        const double c[3] = {0.1, -0.2, 0.05}, t0[3] = {0.05, -0.1, 0.2};
        for (int i = 0; i < 3; i++) p->a[i] = c[i], p->x0[i] = t0[i];
        break;
    }
    }
    int n = p->n, dofs[NMAX];
    p->ke = kind == P_QUAD || kind == P_ILL ? n : kind == P_ROSEN ? 2 : 1;
    p->ne = n / p->ke;
    for (int i = 0; i < n; i++) dofs[i] = i;
    if (eo_assembler_create(ctx, n, &p->as) < 0) abort();
    p->hgroup = eo_assembler_add_elements(ctx, p->as, p->ne, p->ke, dofs);
    if (p->hgroup < 0 || eo_assembler_finalize(ctx, p->as) < 0) abort();
    p->H = eo_assembler_matrix(p->as);
}

static inline void prob_done(eo_ctx *ctx, tprob *p)
{
    (void)ctx;
    eo_assembler_destroy(&p->as);
}

static inline eo_objective prob_objective(tprob *p)
{
    eo_objective o = {.n = p->n, .data = p,
                      .ops = p->with_metric ? &ops_metric
                             : p->kind == P_BARRIER ? &ops_barrier
                                                    : &ops_plain};
    return o;
}

/* ‖x − x*‖∞, x* the reference (double wells: the local minimizer of each term nearest x) */
static inline double prob_error(const tprob *p, const double *x)
{
    double e = 0;
    for (int i = 0; i < p->n; i++) {
        double r = p->kind == P_DWELL ? dwell_min(p->a[i], x[i]) : p->xstar[i];
        e = fmax(e, fabs(x[i] - r));
    }
    return isfinite(e) ? e : INFINITY;
}

#endif
