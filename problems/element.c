/* The element kind: the generic per-tet kernel over an element's quadrature (element.h),
 * and its registry (one line per element). */
#include <math.h>
#include <string.h>

#include "elastopt/element.h"
#include "problem_registry.h"
#include "term.h"

void eo_element_grad(const eo_element_type *el, const double Dminv[9], const double lambda[4], double *G)
{
    double dN[4 * EO_ELEMENT_MAX_NODES];
    el->shape(lambda, NULL, dN);
    /* ∇λ_j = row j of Dₘ⁻¹ (j < 3), ∇λ₃ = −Σ: X − X₃ = Dₘ (λ₀, λ₁, λ₂) */
    double gl[4][3];
    for (int c = 0; c < 3; c++) {
        gl[0][c] = Dminv[c], gl[1][c] = Dminv[3 + c], gl[2][c] = Dminv[6 + c];
        gl[3][c] = -(gl[0][c] + gl[1][c] + gl[2][c]);
    }
    for (int a = 0; a < el->nodes; a++)
        for (int c = 0; c < 3; c++)
            G[3 * a + c] = dN[4 * a] * gl[0][c] + dN[4 * a + 1] * gl[1][c] + dN[4 * a + 2] * gl[2][c] +
                           dN[4 * a + 3] * gl[3][c];
}

eo_material_coef eo_element_split_coef(const eo_material_coef *c, double *kappa)
{
    eo_material_coef d = *c;
    const double mu = c->mu, ld = c->lambda < mu ? c->lambda : mu;
    d.lambda = ld;
    d.nu = ld / (2 * (ld + mu));
    d.E = 2 * mu * (1 + d.nu);
    if (kappa) *kappa = c->lambda - ld;
    return d;
}

/* ∂²J/∂F_ij∂F_kl = Σ_mn ε_ikm ε_jln F_mn (row-major pairs (ij), (kl)) */
void eo_elementi_det_hessian(const double F[9], double D[81])
{
    static const int eps[3][3][3] = {{{0, 0, 0}, {0, 0, 1}, {0, -1, 0}},
                                     {{0, 0, -1}, {0, 0, 0}, {1, 0, 0}},
                                     {{0, 1, 0}, {-1, 0, 0}, {0, 0, 0}}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                for (int l = 0; l < 3; l++) {
                    double s = 0;
                    for (int m = 0; m < 3; m++)
                        for (int q = 0; q < 3; q++) s += eps[i][k][m] * eps[j][l][q] * F[3 * m + q];
                    D[9 * (3 * i + j) + 3 * k + l] = s;
                }
}

/* H[(a i)][(b k)] += w Σ_jl G_aj D[(ij)][(kl)] G_bl for n nodes (H is (3n)², row-major),
 * the blocks b >= a only (D symmetric: the rest by eo_elementi_mirror, once) */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
/* the element Hessians' inner loops vectorize 2× wider with AVX2/FMA (chosen at load) */
#define EO_HOT_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define EO_HOT_CLONES
#endif

EO_HOT_CLONES void eo_elementi_GtDG(int n, const double *G, const double *D, double w, double *H)
{
    const int n3 = 3 * n;
    double T[9 * 3 * EO_ELEMENT_MAX_NODES];
    for (int ij = 0; ij < 9; ij++)
        for (int b = 0; b < n; b++)
            for (int k = 0; k < 3; k++) {
                const double *d = D + 9 * ij + 3 * k;
                T[ij * n3 + 3 * b + k] = d[0] * G[3 * b] + d[1] * G[3 * b + 1] + d[2] * G[3 * b + 2];
            }
    for (int a = 0; a < n; a++)
        for (int i = 0; i < 3; i++) {
            double *h = H + (size_t)(3 * a + i) * n3;
            const double g0 = w * G[3 * a], g1 = w * G[3 * a + 1], g2 = w * G[3 * a + 2];
            const double *t0 = T + (3 * i) * n3, *t1 = t0 + n3, *t2 = t1 + n3;
            for (int bk = 3 * a; bk < n3; bk++) h[bk] += g0 * t0[bk] + g1 * t1[bk] + g2 * t2[bk];
        }
}

/* the blocks b < a of H from the blocks b > a (H symmetric) */
void eo_elementi_mirror(int n, double *H)
{
    const int n3 = 3 * n;
    for (int r = 0; r < n3; r++)
        for (int c = 3 * (r / 3 + 1); c < n3; c++) H[(size_t)c * n3 + r] = H[(size_t)r * n3 + c];
}

EO_HOT_CLONES int eo_element_evaluate(const eo_element_type *el, const eo_material_type *mt, const eo_material_coef *c0,
                        const double Dminv[9], double V, const double *x, eo_eval_what what, eo_proj proj,
                        double *energy, double *grad, double *hess, double *minJ)
{
    if (mt->flags & EO_MATERIAL_EDGE) return EO_ERR_UNSUPPORTED;
    const int n = el->nodes, n3 = 3 * n, md = (el->flags & EO_ELEMENT_MEAN_DILATATION) != 0;
    const int split = md || (el->flags & EO_ELEMENT_NODAL_DILATATION);
    double kappa = 0;
    const eo_material_coef cd = split ? eo_element_split_coef(c0, &kappa) : *c0;
    const eo_material_coef *c = &cd;
    double theta = 0, dtheta[3 * EO_ELEMENT_MAX_NODES];
    if (md) memset(dtheta, 0, sizeof dtheta);
    double e = 0, jmin = INFINITY;
    /* the Hessian alone (grad NULL) of an isotropic model: from the analytic modes, no ∂P/∂F */
    const int hess_only = what >= EO_EVAL_HESS && !grad && mt->sigma_eval;
    if (what >= EO_EVAL_GRAD && grad) memset(grad, 0, (size_t)n3 * sizeof(double));
    if (what >= EO_EVAL_HESS) memset(hess, 0, (size_t)n3 * n3 * sizeof(double));
    for (int q = 0; q < el->nq; q++) {
        double G[3 * EO_ELEMENT_MAX_NODES], F[9] = {0};
        eo_element_grad(el, Dminv, el->qp + 4 * q, G);
        for (int a = 0; a < n; a++)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) F[3 * i + j] += x[3 * a + i] * G[3 * a + j];
        const double w = el->qw[q] * V;
        eo_material_eval me;
        if (hess_only) {
            int rc = eo_material_hessian_nodes(mt, c, F, n, G, w, proj, hess, &me.psi, &me.J);
            if (rc < 0) return rc;
        } else {
            int rc = eo_material_evaluate(mt, c, F, what, proj, &me);
            if (rc < 0) return rc;
        }
        if (me.J < jmin) jmin = me.J;
        e += w * me.psi;
        if (!isfinite(me.psi)) continue;
        if (what >= EO_EVAL_GRAD && grad)
            for (int a = 0; a < n; a++)
                for (int i = 0; i < 3; i++)
                    grad[3 * a + i] += w * (me.P[3 * i] * G[3 * a] + me.P[3 * i + 1] * G[3 * a + 1] +
                                            me.P[3 * i + 2] * G[3 * a + 2]);
        if (what >= EO_EVAL_HESS && !hess_only) eo_elementi_GtDG(n, G, me.dPdF, w, hess);
        if (md) { /* θ = Σ_q w_q J_q, ∇θ = Σ_q w_q cof(F_q) G_q, ∇²θ = Σ_q w_q Gᵀ ∂²J G */
            const double wq = el->qw[q];
            theta += wq * me.J;
            if (what >= EO_EVAL_GRAD) {
                const double C[9] = {F[4] * F[8] - F[5] * F[7], F[5] * F[6] - F[3] * F[8], F[3] * F[7] - F[4] * F[6],
                                     F[2] * F[7] - F[1] * F[8], F[0] * F[8] - F[2] * F[6], F[1] * F[6] - F[0] * F[7],
                                     F[1] * F[5] - F[2] * F[4], F[2] * F[3] - F[0] * F[5], F[0] * F[4] - F[1] * F[3]};
                for (int a = 0; a < n; a++)
                    for (int i = 0; i < 3; i++)
                        dtheta[3 * a + i] += wq * (C[3 * i] * G[3 * a] + C[3 * i + 1] * G[3 * a + 1] + C[3 * i + 2] * G[3 * a + 2]);
            }
        }
    }
    if (md && isfinite(e)) {
        const double r = theta - 1;
        e += V * 0.5 * kappa * r * r;
        if (what >= EO_EVAL_GRAD && grad)
            for (int k = 0; k < n3; k++) grad[k] += V * kappa * r * dtheta[k];
        if (what >= EO_EVAL_HESS) {
            for (int a = 0; a < n3; a++)
                for (int b = 0; b < n3; b++) hess[(size_t)a * n3 + b] += V * kappa * dtheta[a] * dtheta[b];
            if (proj == EO_PROJ_NONE) /* the curvature term, exact Hessian only */
                for (int q = 0; q < el->nq; q++) {
                    double G[3 * EO_ELEMENT_MAX_NODES], F[9] = {0}, D[81];
                    eo_element_grad(el, Dminv, el->qp + 4 * q, G);
                    for (int a = 0; a < n; a++)
                        for (int i = 0; i < 3; i++)
                            for (int j = 0; j < 3; j++) F[3 * i + j] += x[3 * a + i] * G[3 * a + j];
                    eo_elementi_det_hessian(F, D);
                    eo_elementi_GtDG(n, G, D, V * kappa * r * el->qw[q], hess);
                }
        }
    }
    if (what >= EO_EVAL_HESS) eo_elementi_mirror(n, hess);
    if (minJ) *minJ = jmin;
    if (!isfinite(e) || ((mt->flags & EO_MATERIAL_BARRIER) && eo_tet_is_inverted(jmin))) {
        *energy = INFINITY;
        if (what >= EO_EVAL_GRAD && grad) memset(grad, 0, (size_t)n3 * sizeof(double));
        if (what >= EO_EVAL_HESS) memset(hess, 0, (size_t)n3 * n3 * sizeof(double));
        return EO_OK;
    }
    *energy = e;
    return EO_OK;
}

void eo_sys_element_mass(const eo_sys *s, int k, double *Ke)
{
    if (s->linear) { /* ρV/20 (1 + δ_ab), computed as it always was (bit for bit) */
        const double m = s->rho[k] * s->vol[k] / 20.0;
        memset(Ke, 0, 144 * sizeof(double));
        for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++)
                for (int c = 0; c < 3; c++) Ke[(3 * a + c) * 12 + 3 * b + c] = m * (a == b ? 2.0 : 1.0);
        return;
    }
    const int n = s->npe, ne = 3 * n;
    const double rv = s->rho[k] * s->vol[k];
    memset(Ke, 0, (size_t)ne * ne * sizeof(double));
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++)
            for (int c = 0; c < 3; c++) Ke[(size_t)(3 * a + c) * ne + 3 * b + c] = rv * s->el->mass[n * a + b];
}

/* ---------------------------------------------------------------- registry */

const void *const eo_registry_element[] = {
    &eo_element_p1,
    &eo_element_p2,
    &eo_element_p2p0,
    &eo_element_p1anp,
    NULL,
};

static int check_element(eo_ctx *ctx, const void *type)
{
    const eo_element_type *t = type;
    if (t->nodes != 4 && t->nodes != 10)
        return eo_error(ctx, EO_ERR_INVALID, "register element '%s': nodes must be 4 or 10 (got %d)", t->info.name,
                        t->nodes);
    if (t->nq < 1 || t->nq > EO_ELEMENT_MAX_QP || !t->qp || !t->qw || !t->shape || !t->mass || !t->lumped || !t->load)
        return eo_error(ctx, EO_ERR_INVALID,
                        "register element '%s': 1 <= nq <= %d, qp, qw, shape, mass, lumped and load are required",
                        t->info.name, EO_ELEMENT_MAX_QP);
    double sw = 0, sl = 0, sm = 0, sf = 0;
    for (int q = 0; q < t->nq; q++) sw += t->qw[q];
    for (int a = 0; a < t->nodes; a++) {
        if (!(t->lumped[a] > 0))
            return eo_error(ctx, EO_ERR_INVALID, "register element '%s': lumped mass of node %d not positive",
                            t->info.name, a);
        sl += t->lumped[a], sf += t->load[a];
        for (int b = 0; b < t->nodes; b++) sm += t->mass[t->nodes * a + b];
    }
    if (fabs(sw - 1) > 1e-12 || fabs(sl - 1) > 1e-12 || fabs(sm - 1) > 1e-12 || fabs(sf - 1) > 1e-12)
        return eo_error(ctx, EO_ERR_INVALID,
                        "register element '%s': quadrature weights, lumped mass, consistent mass and load must each "
                        "sum to 1 (got %g, %g, %g, %g)",
                        t->info.name, sw, sl, sm, sf);
    return EO_OK;
}

eo_registry eo_reg_element = EO_REGISTRY_INIT(EO_KIND_ELEMENT, eo_registry_element, check_element);
