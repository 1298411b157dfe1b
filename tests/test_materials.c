/* Materials contract suite, run over every registered material:
 *  - finite differences ψ → P and P → ∂P/∂F with a step sweep (1e-3 … 1e-10, pass at the
 *    best step, central differences, relative error ≤ 1e-6) on ≥ 50 deformation gradients
 *    per model (identity, near identity, random, ×5 stretch, ×0.2 compression, nearly flat,
 *    two small σ, repeated σ, rotations, inverted where defined);
 *  - rotation invariance, P(I) = 0, agreement with `linear` to second order;
 *  - clamp/abs projections: symmetric PSD, equal to the true Hessian where it is PSD, and
 *    their eigenvalues equal max(λ,0)/|λ| of a LAPACKE_dsyev eigendecomposition of the true
 *    Hessian (1e-9 relative); the analytic eigenvalues equal the numeric ones;
 *  - tet element gradient/Hessian by finite differences, rest data, spring edge model;
 *  - fast SVD vs LAPACKE SVD; barrier +INFINITY and no NaN anywhere;
 *  - the fast path (F_psi_grad: ψ, P from invariants / polar decomposition) against the
 *    SVD path (eo_material_evaluate_svd) on random F in five families, 1e-12 relative;
 *    eo_polar3 against U Vᵀ of the SVD; the element energy/gradient of both paths;
 *  - the structured 12×12 element Hessian against a copy of the previous kernel (nine
 *    analytic modes, Jacobi 3×3 eigensolve, nine rank-1 12×12 updates), 1e-12 relative;
 *  - the inversion rule (issue 15's F with J = −1.4e-17): ψ = +∞ for the barrier model in
 *    every path, finite at −F (J > 0) in every path. */
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/material.h"
#include "elastopt/registry.h"
#include "testutil.h"

#define NF_MAX 128
static double Fs[NF_MAX][9];
static const char *Fkind[NF_MAX];
static int nF;

static const eo_material_coef *coef;

/* ---------------------------------------------------------------- small helpers */
static void mul3(const double A[9], const double B[9], double C[9])
{
    double T[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) T[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
    memcpy(C, T, sizeof T);
}
static void transpose3(const double A[9], double T[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) T[3 * j + i] = A[3 * i + j];
}
static double det3(const double M[9])
{
    return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
           M[2] * (M[3] * M[7] - M[4] * M[6]);
}
static double norm(const double *a, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += a[i] * a[i];
    return sqrt(s);
}
static double diffnorm(const double *a, const double *b, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += (a[i] - b[i]) * (a[i] - b[i]);
    return sqrt(s);
}
static void rand_rot(double R[9])
{
    double q[4], n;
    do {
        for (int i = 0; i < 4; i++) q[i] = eo_test_rand(-1, 1);
        n = norm(q, 4);
    } while (n < 0.1 || n > 1);
    for (int i = 0; i < 4; i++) q[i] /= n;
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double M[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
    memcpy(R, M, sizeof M);
}
/* F = R1 diag(s) R2ᵀ with random rotations */
static void make_F(double s0, double s1, double s2, double F[9])
{
    double R1[9], R2[9], R2T[9], D[9] = {s0, 0, 0, 0, s1, 0, 0, 0, s2};
    rand_rot(R1);
    rand_rot(R2);
    transpose3(R2, R2T);
    mul3(R1, D, F);
    mul3(F, R2T, F);
}
static void add_F(const double F[9], const char *kind)
{
    if (nF >= NF_MAX) return;
    memcpy(Fs[nF], F, 9 * sizeof(double));
    Fkind[nF++] = kind;
}
static void build_F_list(void)
{
    eo_test_seed(12345);
    double F[9];
    double Id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    add_F(Id, "identity");
    for (int k = 0; k < 8; k++) {
        for (int i = 0; i < 9; i++) F[i] = Id[i] + eo_test_rand(-1e-3, 1e-3);
        add_F(F, "near identity");
    }
    for (int k = 0; k < 10; k++) {
        make_F(eo_test_rand(0.5, 2), eo_test_rand(0.5, 2), eo_test_rand(0.5, 2), F);
        add_F(F, "random");
    }
    for (int k = 0; k < 6; k++) {
        do
            for (int i = 0; i < 9; i++) F[i] = Id[i] + eo_test_rand(-0.6, 0.6);
        while (det3(F) < 0.2);
        add_F(F, "random entries");
    }
    make_F(5, 1, 1, F), add_F(F, "stretch x5");
    make_F(5, 5, 5, F), add_F(F, "stretch x5");
    make_F(5, 1.3, 0.8, F), add_F(F, "stretch x5");
    make_F(5, 4, 0.5, F), add_F(F, "stretch x5");
    make_F(0.2, 0.2, 0.2, F), add_F(F, "compression x0.2");
    make_F(1, 1, 0.2, F), add_F(F, "compression x0.2");
    make_F(1.1, 0.2, 0.2, F), add_F(F, "compression x0.2");
    make_F(0.9, 0.7, 0.2, F), add_F(F, "compression x0.2");
    make_F(1, 1, 1e-6, F), add_F(F, "nearly flat");
    make_F(1.3, 0.7, 1e-6, F), add_F(F, "nearly flat");
    make_F(2, 2, 1e-6, F), add_F(F, "nearly flat");
    make_F(0.8, 0.5, 1e-6, F), add_F(F, "nearly flat");
    make_F(1, 1e-3, 5e-4, F), add_F(F, "two small");
    make_F(1.5, 2e-3, 2e-3, F), add_F(F, "two small");
    make_F(0.7, 1e-2, 1e-3, F), add_F(F, "two small");
    make_F(1.5, 1.5, 0.6, F), add_F(F, "repeated");
    make_F(1.4, 0.8, 0.8, F), add_F(F, "repeated");
    make_F(1.3, 1.3, 1.3, F), add_F(F, "repeated");
    make_F(0.7, 0.7, 0.7, F), add_F(F, "repeated");
    make_F(1.2, 1.2, 1.0, F), add_F(F, "repeated");
    double D[9] = {1.5, 0, 0, 0, 1.5, 0, 0, 0, 0.8};
    add_F(D, "repeated (diagonal)");
    for (int k = 0; k < 4; k++) {
        rand_rot(F);
        add_F(F, "rotation");
    }
    double Rpi[9] = {-1, 0, 0, 0, -1, 0, 0, 0, 1};
    add_F(Rpi, "rotation");
    /* inverted: det F < 0 (never |σ3| = σ2, where corotated models are not differentiable) */
    make_F(1.3, 0.9, -0.4, F), add_F(F, "inverted");
    make_F(1, 1, -0.5, F), add_F(F, "inverted");
    make_F(1.1, 0.8, -1e-3, F), add_F(F, "inverted");
    make_F(1.2, 1.0, -0.7, F), add_F(F, "inverted");
    make_F(2, 0.9, -0.3, F), add_F(F, "inverted");
    make_F(1.1, 1.1, -0.6, F), add_F(F, "inverted");
    make_F(0.6, 0.5, -0.1, F), add_F(F, "inverted");
    make_F(1, 0.3, -0.05, F), add_F(F, "inverted");
    double Dinv[9] = {1.2, 0, 0, 0, 0.9, 0, 0, 0, -0.3};
    add_F(Dinv, "inverted (diagonal)");
    make_F(1.4, 1.0, -0.2, F), add_F(F, "inverted");
}

static double psi_at(const eo_material_type *mt, const double F[9])
{
    eo_material_eval e;
    eo_material_evaluate(mt, coef, F, EO_EVAL_ENERGY, EO_PROJ_NONE, &e);
    return e.psi;
}
static int defined_at(const eo_material_type *mt, const double F[9])
{
    return !((mt->flags & EO_MATERIAL_BARRIER) && det3(F) <= 0);
}

static const double steps[] = {1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 1e-9, 1e-10};
#define NSTEPS (int)(sizeof steps / sizeof steps[0])

/* ---------------------------------------------------------------- FD: ψ → P, P → ∂P/∂F */
static void test_fd_material(const eo_material_type *mt)
{
    int ntested = 0;
    double worstP = 0, worstH = 0;
    for (int f = 0; f < nF; f++) {
        const double *F = Fs[f];
        if (!defined_at(mt, F)) continue;
        ntested++;
        eo_material_eval e;
        eo_material_evaluate(mt, coef, F, EO_EVAL_HESS, EO_PROJ_NONE, &e);
        int finite = isfinite(e.psi);
        for (int i = 0; i < 9; i++) finite &= isfinite(e.P[i]);
        for (int i = 0; i < 81; i++) finite &= isfinite(e.dPdF[i]);
        CHECK(finite, "%s: non-finite output at F #%d (%s)", mt->info.name, f, Fkind[f]);
        double bestP = INFINITY, bestH = INFINITY, hP = 0, hH = 0;
        double scaleP = fmax(norm(e.P, 9), coef->mu), scaleH = fmax(norm(e.dPdF, 81), coef->mu);
        for (int si = 0; si < NSTEPS; si++) {
            double h = steps[si], Pfd[9], Dfd[81];
            for (int kl = 0; kl < 9; kl++) {
                double Fp[9], Fm[9];
                memcpy(Fp, F, sizeof Fp), memcpy(Fm, F, sizeof Fm);
                Fp[kl] += h, Fm[kl] -= h;
                eo_material_eval ep, em;
                eo_material_evaluate(mt, coef, Fp, EO_EVAL_GRAD, EO_PROJ_NONE, &ep);
                eo_material_evaluate(mt, coef, Fm, EO_EVAL_GRAD, EO_PROJ_NONE, &em);
                Pfd[kl] = (ep.psi - em.psi) / (2 * h);
                for (int ij = 0; ij < 9; ij++) Dfd[9 * ij + kl] = (ep.P[ij] - em.P[ij]) / (2 * h);
            }
            double eP = diffnorm(Pfd, e.P, 9) / scaleP, eH = diffnorm(Dfd, e.dPdF, 81) / scaleH;
            if (eP < bestP) bestP = eP, hP = h;
            if (eH < bestH) bestH = eH, hH = h;
        }
        CHECK(bestP <= 1e-6, "%s: dpsi/dF FD error %.3g (best step %g) at F #%d (%s)", mt->info.name, bestP, hP, f, Fkind[f]);
        CHECK(bestH <= 1e-6, "%s: dP/dF FD error %.3g (best step %g) at F #%d (%s)", mt->info.name, bestH, hH, f, Fkind[f]);
        worstP = fmax(worstP, bestP), worstH = fmax(worstH, bestH);
    }
    CHECK(ntested >= 50, "%s: only %d deformation gradients tested", mt->info.name, ntested);
    printf("  %-20s FD on %d F: worst rel. error P %.2e, dPdF %.2e\n", mt->info.name, ntested, worstP, worstH);
}

/* ---------------------------------------------------------------- invariance, rest, small strain */
static void test_invariance(const eo_material_type *mt, const eo_material_type *lin)
{
    static const double Id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    eo_material_eval e;
    eo_material_evaluate(mt, coef, Id, EO_EVAL_HESS, EO_PROJ_NONE, &e);
    double psiI = e.psi;
    CHECK(isfinite(psiI), "%s: psi(I) = %g", mt->info.name, psiI);
    CHECK(norm(e.P, 9) <= 1e-9 * coef->mu, "%s: |P(I)| = %g", mt->info.name, norm(e.P, 9));
    /* the rest Hessian equals linear elasticity's for every model (with λ = 0 for the
     * models without a volume term) */
    eo_material_coef c0 = *coef;
    if (mt->flags & EO_MATERIAL_NO_VOLUME) c0.lambda = 0;
    eo_material_eval el;
    eo_material_evaluate(lin, &c0, Id, EO_EVAL_HESS, EO_PROJ_NONE, &el);
    CHECK(diffnorm(e.dPdF, el.dPdF, 81) <= 1e-9 * norm(el.dPdF, 81), "%s: rest Hessian differs from linear by %g",
          mt->info.name, diffnorm(e.dPdF, el.dPdF, 81));
    if (mt->sigma_eval) {
        for (int f = 0; f < nF; f++) {
            if (!defined_at(mt, Fs[f])) continue;
            double Q[9], QF[9], FQ[9];
            rand_rot(Q);
            mul3(Q, Fs[f], QF);
            mul3(Fs[f], Q, FQ);
            double p = psi_at(mt, Fs[f]), pq = psi_at(mt, QF), pf = psi_at(mt, FQ);
            double tol = 1e-10 * (fabs(p) + coef->mu);
            CHECK(fabs(pq - p) <= tol && fabs(pf - p) <= tol, "%s: psi(QF) %.17g psi(FQ) %.17g psi(F) %.17g (%s)",
                  mt->info.name, pq, pf, p, Fkind[f]);
        }
    }
    /* small strain: (psi(I+eG) - psi(I)) / psi_lin(I+eG) = 1 + O(e) */
    for (int trial = 0; trial < 5; trial++) {
        double G[9], prev = INFINITY;
        for (int i = 0; i < 9; i++) G[i] = eo_test_rand(-1, 1);
        for (double eps = 1e-2; eps >= 1e-4; eps /= 10) {
            double F[9];
            for (int i = 0; i < 9; i++) F[i] = Id[i] + eps * G[i];
            eo_material_eval ev;
            eo_material_evaluate(lin, &c0, F, EO_EVAL_ENERGY, EO_PROJ_NONE, &ev);
            double pl = ev.psi, p = psi_at(mt, F) - psiI;
            double rel = fabs(p - pl) / pl;
            CHECK(rel <= 20 * eps, "%s: small strain eps=%g: relative difference to linear %g", mt->info.name, eps, rel);
            CHECK(rel <= prev, "%s: small strain difference not decreasing (%g after %g)", mt->info.name, rel, prev);
            prev = rel;
        }
    }
}

/* ---------------------------------------------------------------- projections vs dsyev */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static void sym_eig(const double *A, int n, double *w)
{
    double M[144];
    memcpy(M, A, (size_t)(n * n) * sizeof(double));
    int info = LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'N', 'U', n, M, n, w);
    CHECK(info == 0, "dsyev info %d", info);
}
static void test_projection(const eo_material_type *mt)
{
    double worst = 0;
    for (int f = 0; f < nF; f++) {
        const double *F = Fs[f];
        if (!defined_at(mt, F)) continue;
        eo_material_eval en, ec, ea;
        eo_material_evaluate(mt, coef, F, EO_EVAL_HESS, EO_PROJ_NONE, &en);
        eo_material_evaluate(mt, coef, F, EO_EVAL_HESS, EO_PROJ_CLAMP, &ec);
        eo_material_evaluate(mt, coef, F, EO_EVAL_HESS, EO_PROJ_ABS, &ea);
        double ln[9], lc[9], la[9], an[9], tc[9], ta[9];
        sym_eig(en.dPdF, 9, ln);
        sym_eig(ec.dPdF, 9, lc);
        sym_eig(ea.dPdF, 9, la);
        memcpy(an, en.eig, sizeof an);
        qsort(an, 9, sizeof(double), cmp_double);
        for (int k = 0; k < 9; k++) tc[k] = fmax(ln[k], 0), ta[k] = fabs(ln[k]);
        qsort(tc, 9, sizeof(double), cmp_double);
        qsort(ta, 9, sizeof(double), cmp_double);
        double scale = fmax(fabs(ln[0]), fabs(ln[8]));
        double e1 = diffnorm(an, ln, 9) / scale, e2 = diffnorm(lc, tc, 9) / scale, e3 = diffnorm(la, ta, 9) / scale;
        worst = fmax(worst, fmax(e1, fmax(e2, e3)));
        CHECK(e1 <= 1e-9, "%s: analytic eigenvalues differ from dsyev by %g (%s)", mt->info.name, e1, Fkind[f]);
        CHECK(e2 <= 1e-9, "%s: clamp eigenvalues differ by %g (%s)", mt->info.name, e2, Fkind[f]);
        CHECK(e3 <= 1e-9, "%s: abs eigenvalues differ by %g (%s)", mt->info.name, e3, Fkind[f]);
        CHECK(lc[0] >= -1e-9 * scale && la[0] >= -1e-9 * scale, "%s: projection not PSD: %g %g (%s)", mt->info.name,
              lc[0], la[0], Fkind[f]);
        double asym = 0;
        for (int i = 0; i < 9; i++)
            for (int j = 0; j < 9; j++)
                asym = fmax(asym, fmax(fabs(ec.dPdF[9 * i + j] - ec.dPdF[9 * j + i]),
                                       fabs(ea.dPdF[9 * i + j] - ea.dPdF[9 * j + i])));
        CHECK(asym <= 1e-12 * scale, "%s: projection not symmetric (%g)", mt->info.name, asym);
        if (ln[0] > 1e-9 * scale) {
            CHECK(diffnorm(ec.dPdF, en.dPdF, 81) <= 1e-9 * scale && diffnorm(ea.dPdF, en.dPdF, 81) <= 1e-9 * scale,
                  "%s: projection changed a PSD Hessian (%s)", mt->info.name, Fkind[f]);
        }
    }
    printf("  %-20s projection: worst eigenvalue mismatch %.2e\n", mt->info.name, worst);
}

/* ---------------------------------------------------------------- tet element */
static void rand_tet(double X[12], int flip)
{
    static const double reg[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    double Dm[9];
    do {
        for (int i = 0; i < 12; i++) X[i] = reg[i] + eo_test_rand(-0.2, 0.2);
        for (int a = 0; a < 3; a++)
            for (int c = 0; c < 3; c++) Dm[3 * a + c] = X[3 * c + a] - X[9 + a];
    } while (det3(Dm) < 0.3);
    if (flip) /* mesh-layer orientation: swap vertices 1 and 2 */
        for (int a = 0; a < 3; a++) {
            double t = X[3 + a];
            X[3 + a] = X[6 + a], X[6 + a] = t;
        }
}
static void test_tet(const eo_material_type *mt)
{
    double worstg = 0, worsth = 0;
    for (int t = 0; t < 16; t++) {
        double X[12], x[12], Dminv[9], w;
        rand_tet(X, t & 1);
        CHECK(eo_tet_rest(X, Dminv, &w) == EO_OK, "rest");
        double F0[9];
        if (t < 12) {
            make_F(eo_test_rand(0.6, 1.5), eo_test_rand(0.6, 1.5), eo_test_rand(0.6, 1.5), F0);
        } else { /* slightly inverted */
            if (mt->flags & EO_MATERIAL_BARRIER) continue;
            make_F(1.1, 0.9, -0.15, F0);
        }
        for (int v = 0; v < 4; v++)
            for (int a = 0; a < 3; a++)
                x[3 * v + a] = F0[3 * a] * X[3 * v] + F0[3 * a + 1] * X[3 * v + 1] + F0[3 * a + 2] * X[3 * v + 2] +
                               eo_test_rand(-0.02, 0.02);
        eo_tet_out o;
        CHECK(eo_tet_evaluate(mt, coef, Dminv, w, x, EO_EVAL_HESS, EO_PROJ_NONE, &o) == EO_OK, "tet");
        double bg = INFINITY, bh = INFINITY;
        double sg = fmax(norm(o.grad, 12), w * coef->mu), sh = fmax(norm(o.hess, 144), w * coef->mu);
        for (int si = 0; si < NSTEPS; si++) {
            double h = steps[si], gfd[12], Hfd[144];
            for (int k = 0; k < 12; k++) {
                double xp[12], xm[12];
                memcpy(xp, x, sizeof xp), memcpy(xm, x, sizeof xm);
                xp[k] += h, xm[k] -= h;
                eo_tet_out op, om;
                eo_tet_evaluate(mt, coef, Dminv, w, xp, EO_EVAL_GRAD, EO_PROJ_NONE, &op);
                eo_tet_evaluate(mt, coef, Dminv, w, xm, EO_EVAL_GRAD, EO_PROJ_NONE, &om);
                gfd[k] = (op.energy - om.energy) / (2 * h);
                for (int i = 0; i < 12; i++) Hfd[12 * i + k] = (op.grad[i] - om.grad[i]) / (2 * h);
            }
            bg = fmin(bg, diffnorm(gfd, o.grad, 12) / sg);
            bh = fmin(bh, diffnorm(Hfd, o.hess, 144) / sh);
        }
        CHECK(bg <= 1e-6 && bh <= 1e-6, "%s: tet %d FD grad %g hess %g", mt->info.name, t, bg, bh);
        /* energy and gradient of the fast path (EO_EVAL_GRAD) equal the SVD path's (EO_EVAL_HESS) */
        eo_tet_out of;
        eo_tet_evaluate(mt, coef, Dminv, w, x, EO_EVAL_GRAD, EO_PROJ_NONE, &of);
        CHECK(fabs(of.energy - o.energy) <= 1e-12 * fmax(fabs(o.energy), 1e-3 * w * coef->mu) &&
                  diffnorm(of.grad, o.grad, 12) <= 1e-12 * sg && of.J == o.J,
              "%s: tet %d fast vs SVD path: energy %.17g vs %.17g, grad diff %.2e", mt->info.name, t, of.energy,
              o.energy, diffnorm(of.grad, o.grad, 12) / sg);
        worstg = fmax(worstg, bg), worsth = fmax(worsth, bh);
        /* energy = w psi(F) with the F recovered from the vertices */
        double Ds[9], F[9];
        for (int a = 0; a < 3; a++)
            for (int c = 0; c < 3; c++) Ds[3 * a + c] = x[3 * c + a] - x[9 + a];
        mul3(Ds, Dminv, F);
        CHECK_CLOSE(o.energy, w * psi_at(mt, F), 1e-12);
        CHECK_CLOSE(o.J, det3(F), 1e-12);
        /* projected element Hessian: symmetric PSD, translations in its null space */
        eo_tet_out oc;
        eo_tet_evaluate(mt, coef, Dminv, w, x, EO_EVAL_HESS, EO_PROJ_CLAMP, &oc);
        double lam[12];
        sym_eig(oc.hess, 12, lam);
        CHECK(lam[0] >= -1e-9 * fabs(lam[11]), "%s: projected tet Hessian eigenvalue %g", mt->info.name, lam[0]);
        double tsum = 0;
        for (int i = 0; i < 12; i++) {
            double r = 0;
            for (int v = 0; v < 4; v++) r += oc.hess[12 * i + 3 * v];
            tsum = fmax(tsum, fabs(r));
        }
        CHECK(tsum <= 1e-9 * fabs(lam[11]), "%s: translation not in null space (%g)", mt->info.name, tsum);
    }
    printf("  %-20s tet FD: worst rel. error grad %.2e, hess %.2e\n", mt->info.name, worstg, worsth);
}

static void test_tet_rest(void)
{
    double X[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, Dminv[9], w;
    CHECK(eo_tet_rest(X, Dminv, &w) == EO_OK, "rest");
    CHECK_CLOSE(w, 1.0 / 6.0, 1e-15);
    for (int i = 0; i < 9; i++) CHECK_CLOSE(Dminv[i], (i % 4 == 0), 1e-15);
    double Xs[12] = {2, 0, 0, 0, 3, 0, 0, 0, 4, 0.5, 0.5, 0.5};
    CHECK(eo_tet_rest(Xs, Dminv, &w) == EO_OK, "rest");
    double Dm[9] = {1.5, -0.5, -0.5, -0.5, 2.5, -0.5, -0.5, -0.5, 3.5}, P[9];
    mul3(Dm, Dminv, P);
    for (int i = 0; i < 9; i++) CHECK_CLOSE(P[i], (i % 4 == 0), 1e-14);
    CHECK_CLOSE(w, fabs(det3(Dm)) / 6, 1e-14);
    double flat[12] = {1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 0};
    CHECK(eo_tet_rest(flat, Dminv, &w) == EO_ERR_MESH, "degenerate rest tet");
    /* the mesh layer's orientation (det[x1-x0, x2-x0, x3-x0] > 0) has det Dm < 0: accepted, same F */
    double neg[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, Dn[9], wn, A[9] = {1.1, 0.2, 0, -0.1, 0.9, 0.3, 0, 0.1, 1.2};
    CHECK(eo_tet_rest(neg, Dn, &wn) == EO_OK, "positively oriented mesh tet");
    CHECK_CLOSE(wn, 1.0 / 6.0, 1e-15);
    double xn[12], Dsn[9], Fn[9];
    for (int v = 0; v < 4; v++)
        for (int a = 0; a < 3; a++) xn[3 * v + a] = A[3 * a] * neg[3 * v] + A[3 * a + 1] * neg[3 * v + 1] + A[3 * a + 2] * neg[3 * v + 2];
    for (int a = 0; a < 3; a++)
        for (int c = 0; c < 3; c++) Dsn[3 * a + c] = xn[3 * c + a] - xn[9 + a];
    mul3(Dsn, Dn, Fn);
    for (int i = 0; i < 9; i++) CHECK_CLOSE(Fn[i], A[i], 1e-14);
    double tiny[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5, 0.5, 1e-14};
    CHECK(eo_tet_rest(tiny, Dminv, &w) == EO_ERR_MESH, "nearly flat rest tet");
}

/* ---------------------------------------------------------------- spring */
static void test_spring(const eo_material_type *mt)
{
    CHECK(mt->edge_eval != NULL, "spring has edge_eval");
    if (!mt->edge_eval) return;
    eo_material_eval e;
    static const double Id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    CHECK(eo_material_evaluate(mt, coef, Id, EO_EVAL_HESS, EO_PROJ_NONE, &e) == EO_ERR_UNSUPPORTED, "edge model");
    double k = coef->k;
    for (int t = 0; t < 20; t++) {
        double p[6], L = eo_test_rand(0.5, 2), g[6], H[36];
        for (int i = 0; i < 6; i++) p[i] = eo_test_rand(-1, 1);
        double l = diffnorm(p, p + 3, 3);
        double psi = mt->edge_eval(coef, L, p, p + 3, EO_EVAL_HESS, EO_PROJ_NONE, g, H);
        CHECK_CLOSE(psi, 0.5 * k * (l - L) * (l - L), 1e-12);
        double bg = INFINITY, bh = INFINITY;
        for (int si = 0; si < NSTEPS; si++) {
            double h = steps[si], gfd[6], Hfd[36];
            for (int c = 0; c < 6; c++) {
                double pp[6], pm[6], gp[6], gm[6];
                memcpy(pp, p, sizeof pp), memcpy(pm, p, sizeof pm);
                pp[c] += h, pm[c] -= h;
                double ep = mt->edge_eval(coef, L, pp, pp + 3, EO_EVAL_GRAD, EO_PROJ_NONE, gp, NULL);
                double em = mt->edge_eval(coef, L, pm, pm + 3, EO_EVAL_GRAD, EO_PROJ_NONE, gm, NULL);
                gfd[c] = (ep - em) / (2 * h);
                for (int i = 0; i < 6; i++) Hfd[6 * i + c] = (gp[i] - gm[i]) / (2 * h);
            }
            bg = fmin(bg, diffnorm(gfd, g, 6) / fmax(norm(g, 6), k));
            bh = fmin(bh, diffnorm(Hfd, H, 36) / fmax(norm(H, 36), k));
        }
        CHECK(bg <= 1e-6 && bh <= 1e-6, "spring FD grad %g hess %g", bg, bh);
        /* eigenvalues: 2k, 2k(1 − L/l) twice, 0 three times; projections clamp/abs them */
        double ln[6], lc[6], la[6], Hc[36], Ha[36];
        sym_eig(H, 6, ln);
        mt->edge_eval(coef, L, p, p + 3, EO_EVAL_HESS, EO_PROJ_CLAMP, g, Hc);
        mt->edge_eval(coef, L, p, p + 3, EO_EVAL_HESS, EO_PROJ_ABS, g, Ha);
        sym_eig(Hc, 6, lc);
        sym_eig(Ha, 6, la);
        double ex[6] = {2 * k, 2 * k * (1 - L / l), 2 * k * (1 - L / l), 0, 0, 0}, tc[6], ta[6];
        qsort(ex, 6, sizeof(double), cmp_double);
        for (int i = 0; i < 6; i++) tc[i] = fmax(ex[i], 0), ta[i] = fabs(ex[i]);
        qsort(tc, 6, sizeof(double), cmp_double);
        qsort(ta, 6, sizeof(double), cmp_double);
        CHECK(diffnorm(ln, ex, 6) <= 1e-9 * 2 * k, "spring eigenvalues");
        CHECK(diffnorm(lc, tc, 6) <= 1e-9 * 2 * k && lc[0] >= -1e-9 * k, "spring clamp");
        CHECK(diffnorm(la, ta, 6) <= 1e-9 * 2 * k && la[0] >= -1e-9 * k, "spring abs");
    }
    double a[3] = {0.3, 0.3, 0.3}, g[6], H[36];
    double psi = mt->edge_eval(coef, 1.0, a, a, EO_EVAL_HESS, EO_PROJ_NONE, g, H);
    int finite = isfinite(psi);
    for (int i = 0; i < 36; i++) finite &= isfinite(H[i]);
    CHECK(finite && psi == 0.5 * k, "zero-length spring finite");
}

/* ---------------------------------------------------------------- SVD */
static void check_svd_one(const double F[9], const char *what, double *worst)
{
    double U[9], s[3], V[9], UL[9], sl[3], VL[9];
    eo_svd3(F, U, s, V);
    CHECK(eo_svd3_lapack(F, UL, sl, VL) == EO_OK, "lapack");
    double nF_ = norm(F, 9), R[9], VT[9], D[9] = {s[0], 0, 0, 0, s[1], 0, 0, 0, s[2]};
    transpose3(V, VT);
    mul3(U, D, R);
    mul3(R, VT, R);
    double es = diffnorm(s, sl, 3), er = diffnorm(R, F, 9);
    double UT[9], UU[9], VV[9], Id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    transpose3(U, UT);
    mul3(UT, U, UU);
    mul3(VT, V, VV);
    double eo = fmax(diffnorm(UU, Id, 9), diffnorm(VV, Id, 9));
    double ed = fmax(fabs(det3(U) - 1), fabs(det3(V) - 1));
    /* LAPACK's own factors obey the same convention */
    double DL[9] = {sl[0], 0, 0, 0, sl[1], 0, 0, 0, sl[2]}, RL[9], VLT[9];
    transpose3(VL, VLT);
    mul3(UL, DL, RL);
    mul3(RL, VLT, RL);
    CHECK(es <= 1e-12 * nF_ + 1e-300, "%s: sigma differs from LAPACK by %g (|F| %g)", what, es, nF_);
    CHECK(er <= 1e-13 * nF_ + 1e-300, "%s: reconstruction error %g (|F| %g)", what, er, nF_);
    CHECK(eo <= 1e-13, "%s: U or V not orthonormal (%g)", what, eo);
    CHECK(ed <= 1e-13 && det3(UL) > 0 && det3(VL) > 0, "%s: det U, det V not +1 (%g)", what, ed);
    CHECK(s[0] >= s[1] - 1e-14 * nF_ && s[1] >= fabs(s[2]) - 1e-14 * nF_ && s[1] >= 0, "%s: sigma not sorted %g %g %g", what, s[0], s[1], s[2]);
    CHECK(!(det3(F) < -1e-14 * nF_ * nF_ * nF_) || s[2] <= 0, "%s: inverted F must have sigma3 <= 0", what);
    CHECK(diffnorm(RL, F, 9) <= 1e-13 * nF_ + 1e-300, "%s: LAPACK reference reconstruction", what);
    *worst = fmax(*worst, nF_ > 0 ? fmax(es, er) / nF_ : 0);
}
static void test_svd(void)
{
    eo_test_seed(777);
    double F[9], worst = 0;
    int n = 0;
    for (int k = 0; k < 300; k++, n++) {
        for (int i = 0; i < 9; i++) F[i] = eo_test_rand(-2, 2);
        check_svd_one(F, "random", &worst);
    }
    static const double reps[][3] = {{2, 2, 1}, {1, 1, 1}, {1, 1, -1}, {3, 1, 1}, {2, 1, -1}, {1, 1, 0},
                                     {1, 1e-6, 1e-6}, {5, 5, -5}};
    for (int r = 0; r < 8; r++)
        for (int k = 0; k < 10; k++, n++) {
            make_F(reps[r][0], reps[r][1], reps[r][2], F);
            check_svd_one(F, "repeated", &worst);
        }
    static const double small[][3] = {{1, 0.5, 1e-6}, {1, 0.5, -1e-6}, {1, 1, 1e-12}, {2, 1e-3, 1e-6},
                                      {1, 1e-8, 1e-9}, {3, 2, 1e-15}};
    for (int r = 0; r < 6; r++)
        for (int k = 0; k < 10; k++, n++) {
            make_F(small[r][0], small[r][1], small[r][2], F);
            check_svd_one(F, "near zero", &worst);
        }
    for (int k = 0; k < 20; k++, n++) { /* rank 1 and rank 2, exactly */
        double u[3], v[3], w[3], z[3];
        for (int i = 0; i < 3; i++) u[i] = eo_test_rand(-1, 1), v[i] = eo_test_rand(-1, 1), w[i] = eo_test_rand(-1, 1), z[i] = eo_test_rand(-1, 1);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) F[3 * i + j] = u[i] * v[j] + (k & 1 ? w[i] * z[j] : 0);
        check_svd_one(F, k & 1 ? "rank 2" : "rank 1", &worst);
    }
    double Z[9] = {0};
    check_svd_one(Z, "rank 0", &worst), n++;
    double E1[9] = {0, 0, 0, 0, 0, 3, 0, 0, 0};
    check_svd_one(E1, "rank 1 axis", &worst), n++;
    double Pm[9] = {0, 1, 0, 1, 0, 0, 0, 0, 1};
    check_svd_one(Pm, "reflection", &worst), n++;
    for (int k = 0; k < 50; k++, n++) {
        make_F(eo_test_rand(0.5, 3), eo_test_rand(0.2, 0.5), -eo_test_rand(0.01, 0.2), F);
        check_svd_one(F, "inverted", &worst);
    }
    for (int k = 0; k < 10; k++, n++) {
        make_F(1e-100, 5e-101, 1e-101, F);
        check_svd_one(F, "tiny scale", &worst);
        make_F(1e100, 5e99, -1e99, F);
        check_svd_one(F, "huge scale", &worst);
    }
    printf("  svd3 vs LAPACKE on %d matrices: worst error relative to |F| %.2e\n", n, worst);
}

/* ---------------------------------------------------------------- barrier / NaN */
static void test_barrier_and_nan(const eo_material_type *mt)
{
    double bad[4][9];
    make_F(1, 1, -0.5, bad[0]);
    make_F(1, 1, 0, bad[1]);
    double Z[9] = {0}, R1[9] = {1, 2, 3, 2, 4, 6, 1, 2, 3};
    memcpy(bad[2], Z, sizeof Z);
    memcpy(bad[3], R1, sizeof R1);
    for (int b = 0; b < 4; b++) {
        eo_material_eval e;
        eo_material_evaluate(mt, coef, bad[b], EO_EVAL_HESS, EO_PROJ_CLAMP, &e);
        int nan = isnan(e.psi);
        for (int i = 0; i < 9; i++) nan |= isnan(e.P[i]);
        for (int i = 0; i < 81; i++) nan |= isnan(e.dPdF[i]);
        CHECK(!nan, "%s: NaN at degenerate F #%d", mt->info.name, b);
        /* the rule is J = det F ≤ 0 as computed: the rank-2 F #1 has |J| at the rounding level,
         * of either sign depending on its random rotations */
        if (mt->flags & EO_MATERIAL_BARRIER)
            CHECK(eo_tet_is_inverted(e.J) ? e.psi == INFINITY : e.psi > 0 && b == 1,
                  "%s: psi = %g at J = %g (F #%d)", mt->info.name, e.psi, e.J, b);
        else CHECK(isfinite(e.psi), "%s: psi = %g", mt->info.name, e.psi);
    }
    if (mt->flags & EO_MATERIAL_BARRIER) {
        double X[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, x[12], Dminv[9], w;
        eo_tet_rest(X, Dminv, &w);
        memcpy(x, X, sizeof x);
        x[0] = -0.1; /* vertex 0 pushed through the opposite face: J < 0 */
        eo_tet_out o;
        eo_tet_evaluate(mt, coef, Dminv, w, x, EO_EVAL_HESS, EO_PROJ_CLAMP, &o);
        CHECK(o.energy == INFINITY && o.J < 0, "%s: tet energy %g at J %g", mt->info.name, o.energy, o.J);
        int nan = 0;
        for (int i = 0; i < 144; i++) nan |= isnan(o.hess[i]);
        CHECK(!nan, "%s: NaN tet Hessian", mt->info.name);
    }
    for (int f = 0; f < nF; f++) {
        eo_material_eval e;
        eo_material_evaluate(mt, coef, Fs[f], EO_EVAL_HESS, EO_PROJ_ABS, &e);
        int nan = isnan(e.psi);
        for (int i = 0; i < 81; i++) nan |= isnan(e.dPdF[i]);
        CHECK(!nan, "%s: NaN at F #%d (%s)", mt->info.name, f, Fkind[f]);
    }
}

/* ---------------------------------------------------------------- fast path vs SVD path */
/* F = R1 diag(s) R2ᵀ for the five families; returns 0 when the corotated kinds are not
 * differentiable there (σ2 + σ3 small, the polar rotation is not unique). */
static const char *const fam_name[5] = {"well-conditioned", "near-singular", "inverted", "large stretch", "random entries"};
static void family_F(int fam, double F[9])
{
    double a, b, c;
    switch (fam) {
    case 0: make_F(eo_test_rand(0.5, 2), eo_test_rand(0.5, 2), eo_test_rand(0.5, 2), F); return;
    case 1:
        a = eo_test_rand(0.5, 2), b = eo_test_rand(0.5, 2);
        make_F(a, b, pow(10, eo_test_rand(-6, -2)), F);
        return;
    case 2:
        a = eo_test_rand(0.6, 2), b = eo_test_rand(0.5, 1) * a;
        make_F(a, b, -eo_test_rand(0.02, 0.8) * b, F);
        return;
    case 3:
        a = eo_test_rand(3, 20), b = eo_test_rand(0.3, 3), c = eo_test_rand(0.3, 3);
        make_F(a, b, c, F);
        return;
    default:
        for (int i = 0; i < 9; i++) F[i] = eo_test_rand(-1.5, 1.5);
    }
}
static void test_fast_path(const eo_material_type *mt)
{
    if (!mt->F_psi_grad) return;
    double worst_psi[5] = {0}, worst_P[5] = {0};
    int n[5] = {0}, ninf = 0;
    for (int fam = 0; fam < 5; fam++)
        for (int k = 0; k < 200; k++) {
            double F[9], U[9], sg[3], V[9];
            family_F(fam, F);
            eo_svd3(F, U, sg, V);
            int corot = strstr(mt->info.name, "corotated") != NULL;
            if (corot && !(sg[1] + sg[2] > 0.02 * sg[0])) continue;
            eo_material_eval ef, es;
            eo_material_evaluate(mt, coef, F, EO_EVAL_GRAD, EO_PROJ_NONE, &ef);
            eo_material_evaluate_svd(mt, coef, F, EO_EVAL_GRAD, EO_PROJ_NONE, &es);
            if ((mt->flags & EO_MATERIAL_BARRIER) && eo_tet_is_inverted(eo_det3(F))) {
                CHECK(ef.psi == INFINITY && es.psi == INFINITY && norm(ef.P, 9) == 0,
                      "%s: inverted F (%s) psi fast %g svd %g", mt->info.name, fam_name[fam], ef.psi, es.psi);
                ninf++;
                continue;
            }
            double ep = fabs(ef.psi - es.psi) / fmax(fabs(es.psi), 1e-3 * coef->mu);
            double eP = diffnorm(ef.P, es.P, 9) / fmax(norm(es.P, 9), 1e-3 * coef->mu);
            /* 1e-12, widened only by the conditioning of the data: the rounded entries of F
             * fix J (and F⁻ᵀ) to a relative accuracy of ~ε κ(F), κ = σ1/|σ3|, whichever way
             * it is computed (det F or σ1σ2σ3); it matters for neo_hookean's 1/J terms at
             * near-singular F (κ up to 2e6 here) and nowhere else */
            double kappa = sg[0] / fabs(sg[2]), tol = 1e-12 + 16 * DBL_EPSILON * kappa;
            CHECK(ep <= tol && eP <= tol, "%s: fast vs SVD path at %s F: psi %.17g vs %.17g (rel %.2e), P rel %.2e, tol %.1e",
                  mt->info.name, fam_name[fam], ef.psi, es.psi, ep, eP, tol);
            if (kappa < 1e3) CHECK(ep <= 1e-12 && eP <= 1e-12, "%s: kappa %g: 1e-12 expected", mt->info.name, kappa);
            /* the energy-only evaluation gives the same psi */
            eo_material_eval e0;
            eo_material_evaluate(mt, coef, F, EO_EVAL_ENERGY, EO_PROJ_NONE, &e0);
            CHECK(e0.psi == ef.psi, "%s: energy-only psi %.17g vs %.17g", mt->info.name, e0.psi, ef.psi);
            worst_psi[fam] = fmax(worst_psi[fam], ep), worst_P[fam] = fmax(worst_P[fam], eP);
            n[fam]++;
        }
    printf("  %-20s fast vs SVD path, worst rel. psi / P:", mt->info.name);
    for (int fam = 0; fam < 5; fam++) printf(" %s (%d) %.1e/%.1e;", fam_name[fam], n[fam], worst_psi[fam], worst_P[fam]);
    printf(" +inf at %d inverted\n", ninf);
    for (int fam = 0; fam < 5; fam++)
        CHECK(n[fam] >= 50 || (fam == 2 && (mt->flags & EO_MATERIAL_BARRIER)), "%s: only %d F in family %s",
              mt->info.name, n[fam], fam_name[fam]);
}

static void test_polar(void)
{
    eo_test_seed(4242);
    double worst = 0, worst_orth = 0;
    int n = 0, itmax = 0;
    long itsum = 0;
    for (int fam = 0; fam < 5; fam++)
        for (int k = 0; k < 300; k++) {
            double F[9], U[9], s[3], V[9], R[9], VT[9], UVt[9];
            family_F(fam, F);
            eo_svd3(F, U, s, V);
            double gap = (s[1] + s[2]) / s[0];
            if (!(gap > 1e-3)) continue;
            int it = eo_polar3(F, R);
            transpose3(V, VT);
            mul3(U, VT, UVt);
            double e = diffnorm(R, UVt, 9) * gap, RT[9], RR[9], Id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            transpose3(R, RT);
            mul3(RT, R, RR);
            double eo = fmax(diffnorm(RR, Id, 9), fabs(det3(R) - 1));
            CHECK(e <= 1e-13 && eo <= 1e-14, "polar3 (%s): |R - U V^T| (sigma2+sigma3)/sigma1 = %.2e, orthogonality %.2e",
                  fam_name[fam], e, eo);
            worst = fmax(worst, e), worst_orth = fmax(worst_orth, eo);
            itmax = it > itmax ? it : itmax, itsum += it, n++;
        }
    /* diagonal and exactly stationary starts, including a saddle of tr(R^T F) */
    static const double diag[][3] = {{1.2, 0.9, -0.3}, {-1.2, 0.9, 0.3}, {0.3, 0.9, -1.2}, {-0.3, -0.9, -1.2}, {2, 1, 1}};
    for (int k = 0; k < 5; k++) {
        double F[9] = {diag[k][0], 0, 0, 0, diag[k][1], 0, 0, 0, diag[k][2]}, R[9], U[9], s[3], V[9], VT[9], UVt[9];
        eo_polar3(F, R);
        eo_svd3(F, U, s, V);
        transpose3(V, VT);
        mul3(U, VT, UVt);
        CHECK(diffnorm(R, UVt, 9) <= 1e-14, "polar3 at diag(%g, %g, %g): |R - U V^T| = %.2e", diag[k][0], diag[k][1],
              diag[k][2], diffnorm(R, UVt, 9));
    }
    printf("  polar3 vs U V^T on %d F: worst |dR| (sigma2+sigma3)/sigma1 %.2e, orthogonality %.2e, iterations mean %.2f max %d\n",
           n, worst, worst_orth, (double)itsum / n, itmax);
}

/* ---------------------------------------------------------------- previous Hessian kernel (reference copy) */
/* The element Hessian as the kernel computed it before the structured assembly (commit
 * 0ecd213): SVD, nine analytic modes with a cyclic-Jacobi 3×3 eigensolve, and nine
 * rank-1 updates of the 12×12 matrix. Kept here verbatim in substance as the reference. */
static void old_eig_sym3(const double Ain[9], double d[3], double W[9])
{
    double A[9];
    memcpy(A, Ain, sizeof A);
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(W, I3, sizeof I3);
    static const int P[3] = {0, 0, 1}, Q[3] = {1, 2, 2};
    for (int sweep = 0; sweep < 30; sweep++) {
        double off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
        double dg = A[0] * A[0] + A[4] * A[4] + A[8] * A[8];
        if (!(off > 1e-36 * dg)) break;
        for (int k = 0; k < 3; k++) {
            int p = P[k], q = Q[k];
            double apq = A[3 * p + q];
            if (apq == 0) continue;
            double theta = (A[3 * q + q] - A[3 * p + p]) / (2 * apq);
            double t = fabs(theta) > 1e150 ? 0.5 / theta : copysign(1.0, theta) / (fabs(theta) + sqrt(theta * theta + 1));
            double c = 1 / sqrt(t * t + 1), sn = t * c;
            for (int r = 0; r < 3; r++) {
                double arp = A[3 * r + p], arq = A[3 * r + q];
                A[3 * r + p] = c * arp - sn * arq;
                A[3 * r + q] = sn * arp + c * arq;
            }
            for (int r = 0; r < 3; r++) {
                double apr = A[3 * p + r], aqr = A[3 * q + r];
                A[3 * p + r] = c * apr - sn * aqr;
                A[3 * q + r] = sn * apr + c * aqr;
            }
            A[3 * p + q] = A[3 * q + p] = 0;
            for (int r = 0; r < 3; r++) {
                double wrp = W[3 * r + p], wrq = W[3 * r + q];
                W[3 * r + p] = c * wrp - sn * wrq;
                W[3 * r + q] = sn * wrp + c * wrq;
            }
        }
    }
    d[0] = A[0], d[1] = A[4], d[2] = A[8];
}
static void old_adjoint_map(const double Dminv[9], const double Q[9], double g[12])
{
    for (int a = 0; a < 3; a++) {
        double sum = 0;
        for (int c = 0; c < 3; c++) {
            double v = Q[3 * a] * Dminv[3 * c] + Q[3 * a + 1] * Dminv[3 * c + 1] + Q[3 * a + 2] * Dminv[3 * c + 2];
            g[3 * c + a] = v;
            sum += v;
        }
        g[9 + a] = -sum;
    }
}
static double old_project(double l, eo_proj proj)
{
    return proj == EO_PROJ_CLAMP ? (l > 0 ? l : 0) : proj == EO_PROJ_ABS ? fabs(l) : l;
}
/* returns the number of negative scaling eigenvalues (to show the indefinite case is covered) */
static int old_tet_hess(const eo_material_type *mt, const double Dminv[9], double w, const double F[9], eo_proj proj,
                        double H[144])
{
    double U[9], s[3], V[9];
    eo_svd3(F, U, s, V);
    eo_sigma_eval se;
    memset(&se, 0, sizeof se);
    mt->sigma_eval(coef, s, EO_EVAL_HESS, &se);
    double lam[9], q[9][9], d[3], W[9];
    old_eig_sym3(se.H, d, W);
    int nneg = 0;
    for (int k = 0; k < 3; k++) {
        lam[k] = d[k];
        nneg += d[k] < 0;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                q[k][3 * a + b] = U[3 * a] * W[k] * V[3 * b] + U[3 * a + 1] * W[3 + k] * V[3 * b + 1] +
                                  U[3 * a + 2] * W[6 + k] * V[3 * b + 2];
    }
    static const int PI[3] = {0, 0, 1}, PJ[3] = {1, 2, 2};
    const double r2 = 0.70710678118654752440;
    for (int p = 0; p < 3; p++) {
        int i = PI[p], j = PJ[p];
        lam[3 + p] = se.twist[p];
        lam[6 + p] = se.flip[p];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double x = U[3 * a + i] * V[3 * b + j], y = U[3 * a + j] * V[3 * b + i];
                q[3 + p][3 * a + b] = r2 * (x + y);
                q[6 + p][3 * a + b] = r2 * (x - y);
            }
    }
    memset(H, 0, 144 * sizeof(double));
    for (int k = 0; k < 9; k++) {
        double l = w * old_project(lam[k], proj), g[12];
        if (l == 0) continue;
        old_adjoint_map(Dminv, q[k], g);
        for (int i = 0; i < 12; i++)
            for (int j = i; j < 12; j++) H[12 * i + j] += l * g[i] * g[j];
    }
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < i; j++) H[12 * i + j] = H[12 * j + i];
    return nneg;
}
/* Test tet f: the f-th F of the list (beyond it, a random F of family f % 5) applied to a
 * random rest tet (flipped orientation for odd f): Dm⁻¹, volume w and positions x. */
static void test_tet_of(int f, double Dminv[9], double *w, double x[12])
{
    double F0[9], X[12];
    if (f < nF) memcpy(F0, Fs[f], sizeof F0);
    else family_F(f % 5, F0);
    rand_tet(X, f & 1);
    eo_tet_rest(X, Dminv, w);
    for (int v = 0; v < 4; v++)
        for (int a = 0; a < 3; a++)
            x[3 * v + a] = F0[3 * a] * X[3 * v] + F0[3 * a + 1] * X[3 * v + 1] + F0[3 * a + 2] * X[3 * v + 2];
}

static void test_hess_vs_old(const eo_material_type *mt)
{
    if (!mt->sigma_eval) return;
    static const eo_proj projs[3] = {EO_PROJ_NONE, EO_PROJ_CLAMP, EO_PROJ_ABS};
    double worst = 0;
    int n = 0, nindef = 0;
    for (int f = 0; f < nF + 400; f++) {
        double Dminv[9], w, x[12];
        test_tet_of(f, Dminv, &w, x);
        double F[9];
        eo_tet_F(Dminv, x, F);
        if ((mt->flags & EO_MATERIAL_BARRIER) && eo_tet_is_inverted(eo_det3(F))) continue;
        double U[9], sg[3], V[9];
        eo_svd3(F, U, sg, V);
        if (strstr(mt->info.name, "corotated") && !(fabs(sg[1] + sg[2]) > 1e-6 * sg[0])) continue;
        for (int pi = 0; pi < 3; pi++) {
            eo_tet_out o;
            double Hold[144];
            eo_tet_evaluate(mt, coef, Dminv, w, x, EO_EVAL_HESS, projs[pi], &o);
            int neg = old_tet_hess(mt, Dminv, w, F, projs[pi], Hold);
            if (pi == 1) nindef += neg > 0;
            double e = diffnorm(o.hess, Hold, 144) / fmax(norm(Hold, 144), 1e-300);
            CHECK(e <= 1e-12, "%s: structured Hessian (proj %d) differs from the previous kernel by %.2e (F #%d)",
                  mt->info.name, pi, e, f);
            worst = fmax(worst, e);
        }
        n++;
    }
    printf("  %-20s structured 12x12 Hessian vs previous kernel on %d tets x 3 projections (%d with an indefinite "
           "scaling block): worst rel. %.2e\n", mt->info.name, n, nindef, worst);
}

/* eo_tet_hessian (the assembly loops' call): hess, J, psi and energy bit for bit those of
 * eo_tet_evaluate(EO_EVAL_HESS) for every projection, inverted tets included; the
 * gradient is not written. */
static void test_hessian_only(const eo_material_type *mt)
{
    static const eo_proj projs[3] = {EO_PROJ_NONE, EO_PROJ_CLAMP, EO_PROJ_ABS};
    int n = 0, ninv = 0;
    for (int f = 0; f < nF + 100; f++) {
        double Dminv[9], w, x[12];
        test_tet_of(f, Dminv, &w, x);
        for (int pi = 0; pi < 3; pi++) {
            eo_tet_out a, b;
            memset(&a, 0, sizeof a);
            for (int i = 0; i < 12; i++) b.grad[i] = 12345.0;
            int ra = eo_tet_evaluate(mt, coef, Dminv, w, x, EO_EVAL_HESS, projs[pi], &a);
            int rb = eo_tet_hessian(mt, coef, Dminv, w, x, projs[pi], &b);
            int same = ra == rb && memcmp(a.hess, b.hess, sizeof a.hess) == 0 &&
                       memcmp(&a.J, &b.J, sizeof a.J) == 0 && memcmp(&a.psi, &b.psi, sizeof a.psi) == 0 &&
                       memcmp(&a.energy, &b.energy, sizeof a.energy) == 0;
            int untouched = 1;
            for (int i = 0; i < 12; i++) untouched &= b.grad[i] == 12345.0;
            CHECK(same && untouched, "%s: eo_tet_hessian differs from eo_tet_evaluate (F #%d, proj %d; grad %s)",
                  mt->info.name, f, pi, untouched ? "untouched" : "written");
            ninv += pi == 0 && eo_tet_is_inverted(a.J);
        }
        n++;
    }
    printf("  %-20s eo_tet_hessian = eo_tet_evaluate(HESS) bit for bit on %d tets (%d inverted) x 3 projections\n",
           mt->info.name, n, ninv);
}

/* ---------------------------------------------------------------- the inversion rule */
static void test_inversion_rule(const eo_material_type *mt)
{
    /* issue 15: an L-BFGS iterate on a hand mesh; J = det F = -1.4e-17 while the SVD's
     * signed sigma3 comes out +2e-18 */
    static const double Fp[9] = {0.052508965302966913, -0.60269908045118836, 0.5231714895167181,
                                 0.28929428228145077,  0.040833032270308357, -0.076993424939603775,
                                 -0.80658925397590697, -0.72485843956344009, 0.75260633555179257};
    double J = eo_det3(Fp);
    CHECK(J < 0 && J > -2e-17, "pinned F: J = %g", J);
    CHECK(eo_tet_is_inverted(J) && !eo_tet_is_inverted(1e-300) && eo_tet_is_inverted(0) && eo_tet_is_inverted(NAN),
          "eo_tet_is_inverted");
    /* the rest tet with Dm = I: x = the columns of F, vertex 3 at the origin, F exactly */
    double X[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, Dminv[9], w;
    eo_tet_rest(X, Dminv, &w);
    for (int sign = 1; sign >= -1; sign -= 2) {
        double F[9], x[12] = {0};
        for (int i = 0; i < 9; i++) F[i] = sign * Fp[i];
        for (int c = 0; c < 3; c++)
            for (int a = 0; a < 3; a++) x[3 * c + a] = F[3 * a + c];
        int inv = eo_tet_is_inverted(eo_det3(F));
        CHECK(inv == (sign == 1), "sign %d: inverted %d", sign, inv);
        CHECK(eo_tet_J(Dminv, x) == eo_det3(F), "eo_tet_J %g vs eo_det3 %g", eo_tet_J(Dminv, x), eo_det3(F));
        int barrier = (mt->flags & EO_MATERIAL_BARRIER) != 0;
        for (int what = EO_EVAL_ENERGY; what <= EO_EVAL_HESS; what++) {
            eo_material_eval e1, e2;
            eo_tet_out o;
            eo_material_evaluate(mt, coef, F, (eo_eval_what)what, EO_PROJ_CLAMP, &e1);
            eo_material_evaluate_svd(mt, coef, F, (eo_eval_what)what, EO_PROJ_CLAMP, &e2);
            eo_tet_evaluate(mt, coef, Dminv, w, x, (eo_eval_what)what, EO_PROJ_CLAMP, &o);
            CHECK(o.J == eo_det3(F) && e1.J == o.J, "%s: J kernel %g material %g det3 %g", mt->info.name, o.J, e1.J,
                  eo_det3(F));
            if (barrier && inv)
                CHECK(e1.psi == INFINITY && e2.psi == INFINITY && o.energy == INFINITY,
                      "%s: inverted pinned F (what %d): psi %g, svd path %g, tet %g", mt->info.name, what, e1.psi,
                      e2.psi, o.energy);
            else
                CHECK(isfinite(e1.psi) && isfinite(e2.psi) && isfinite(o.energy),
                      "%s: pinned F sign %d (what %d): psi %g, svd path %g, tet %g", mt->info.name, sign, what, e1.psi,
                      e2.psi, o.energy);
            int finite = 1;
            for (int i = 0; i < 9; i++) finite &= isfinite(e1.P[i]) && isfinite(e2.P[i]);
            for (int i = 0; what == EO_EVAL_HESS && i < 144; i++) finite &= isfinite(o.hess[i]);
            CHECK(finite, "%s: non-finite P or Hessian at the pinned F", mt->info.name);
        }
    }
}

/* ---------------------------------------------------------------- params */
static void test_params(void)
{
    eo_material_opts o;
    eo_params_default(eo_material_opts_desc, &o);
    CHECK(strcmp(o.model, "stable_neo_hookean") == 0 && o.E == 1e5 && o.nu == 0.45 && o.density == 1000 && o.k == 1000,
          "defaults");
    eo_material_coef c = eo_material_coef_from_opts(&o);
    CHECK_CLOSE(c.mu, 1e5 / 2.9, 1e-14);
    CHECK_CLOSE(c.lambda, 1e5 * 0.45 / (1.45 * 0.1), 1e-14);
    eo_ctx *ctx = eo_test_ctx();
    CHECK(eo_params_check(ctx, eo_material_opts_desc, &o, NULL) == EO_OK, "defaults in range");
    o.nu = 0.5;
    CHECK(eo_params_check(ctx, eo_material_opts_desc, &o, NULL) == EO_ERR_RANGE, "nu = 0.5 rejected");
    o.nu = 0.3;
    snprintf(o.model, sizeof o.model, "%s", "rubber");
    CHECK(eo_params_check(ctx, eo_material_opts_desc, &o, NULL) == EO_ERR_UNKNOWN_NAME, "unknown model: %s",
          eo_ctx_message(ctx));
    CHECK(strstr(eo_ctx_message(ctx), "stvk") != NULL, "message lists models: %s", eo_ctx_message(ctx));
    eo_test_ctx_done(&ctx);
}

int main(void)
{
    eo_material_coef c = eo_material_coef_from(1e5, 0.45, 1000, 1000);
    coef = &c;
    build_F_list();
    printf("materials suite: %d deformation gradients\n", nF);
    const void *lin_v = NULL;
    eo_ctx *ctx = eo_test_ctx();
    CHECK(eo_registry_find(ctx, EO_KIND_MATERIAL, "linear", &lin_v) == EO_OK, "linear registered");
    static const char *const expected[] = {"linear", "stvk", "corotated", "fixed_corotated", "neo_hookean",
                                           "stable_neo_hookean", "spring"};
    for (size_t i = 0; i < sizeof expected / sizeof *expected; i++) {
        const void *t;
        CHECK(eo_registry_find(ctx, EO_KIND_MATERIAL, expected[i], &t) == EO_OK, "%s registered", expected[i]);
    }
    eo_test_ctx_done(&ctx);
    test_params();
    test_svd();
    test_tet_rest();
    test_polar();
    for (const void *const *t = eo_registry_list(EO_KIND_MATERIAL); t && *t; t++) {
        const eo_material_type *mt = *t;
        if (mt->flags & EO_MATERIAL_EDGE) {
            test_spring(mt);
            continue;
        }
        test_fd_material(mt);
        test_invariance(mt, lin_v);
        test_projection(mt);
        test_tet(mt);
        test_barrier_and_nan(mt);
        test_fast_path(mt);
        test_hess_vs_old(mt);
        test_hessian_only(mt);
        test_inversion_rule(mt);
    }
    return eo_test_finish("test_materials");
}
