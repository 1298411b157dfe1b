/* 2D Poisson FEM (notes 001 §3, corrected weak form per ERRATA), see poisson.h.
 *
 * Linear triangle with vertices p₁, p₂, p₃, area A: Nᵢ = (aᵢ + bᵢx + cᵢy)/(2A) with
 * bᵢ = y_j − y_k, cᵢ = x_k − x_j (i, j, k cyclic), so ∇Nᵢ = (bᵢ, cᵢ)/(2A) is constant and
 *     K^e_ij = ∫ ∇Nᵢ·∇N_j = (bᵢb_j + cᵢc_j)/(4A)        (001 eq. 48 per element).
 * Load F_j = Σ_e ∫_e f N_j: the notes' one-point barycentre rule (eq. 50) is exact only
 * for linear f; here the three-edge-midpoint rule ∫_e φ ≈ (A/3) Σ_midpoints φ (exact for
 * quadratics: N_j is ½ at the two midpoints of edges through j, 0 at the third), which
 * keeps the O(h²) L2 rate clean of quadrature error. Dirichlet u = 0: boundary nodes
 * get id −1 in the assembler and drop out of K and F.
 * L2 error: Dunavant's 7-point rule (degree 5) on every triangle. */
#include <math.h>
#include <string.h>

#include "elastopt/poisson.h"

static const double PI = 3.14159265358979323846;

struct eo_poisson {
    eo_ctx *ctx;
    int n, nfree;
    eo_assembler *as;
    double *F, *Ku;
    int *tri;        /* 3·2n² node ids */
    int *dofs;       /* 3·2n² free ids (−1 boundary) */
    eo_objective obj;
};

static double exact(double x, double y) { return sin(PI * x) * sin(PI * y); }
static double source(double x, double y) { return 2 * PI * PI * exact(x, y); }

static int node_free(const eo_poisson *p, int node)
{
    int i = node % (p->n + 1), j = node / (p->n + 1);
    if (i == 0 || j == 0 || i == p->n || j == p->n) return -1;
    return (j - 1) * (p->n - 1) + (i - 1);
}

static void node_xy(const eo_poisson *p, int node, double *x, double *y)
{
    *x = (double)(node % (p->n + 1)) / p->n;
    *y = (double)(node / (p->n + 1)) / p->n;
}

static int op_value(void *data, const double *u, double *g)
{
    eo_poisson *p = data;
    eo_csc_symv(eo_assembler_matrix(p->as), u, p->Ku);
    double e = 0;
    for (int i = 0; i < p->nfree; i++) e += 0.5 * u[i] * p->Ku[i] - p->F[i] * u[i];
    *g = isfinite(e) ? e : INFINITY;
    return EO_OK;
}

static int op_gradient(void *data, const double *u, double *g, double *grad)
{
    eo_poisson *p = data;
    eo_csc_symv(eo_assembler_matrix(p->as), u, p->Ku);
    double e = 0;
    for (int i = 0; i < p->nfree; i++) {
        e += 0.5 * u[i] * p->Ku[i] - p->F[i] * u[i];
        grad[i] = p->Ku[i] - p->F[i];
    }
    *g = isfinite(e) ? e : INFINITY;
    return EO_OK;
}

static int op_hessian(void *data, const double *u, eo_proj proj, eo_csc **H)
{
    (void)u, (void)proj; /* constant and SPD */
    eo_poisson *p = data;
    *H = eo_assembler_matrix(p->as);
    return EO_OK;
}

static const eo_objective_ops poisson_ops = {
    .value = op_value,
    .gradient = op_gradient,
    .hessian = op_hessian,
};

void eo_poisson_destroy(eo_poisson **pp)
{
    if (!pp || !*pp) return;
    eo_poisson *p = *pp;
    eo_assembler_destroy(p->ctx, &p->as);
    eo_free(p->ctx, p->F);
    eo_free(p->ctx, p->Ku);
    eo_free(p->ctx, p->tri);
    eo_free(p->ctx, p->dofs);
    eo_free(p->ctx, p);
    *pp = NULL;
}

int eo_poisson_create(eo_ctx *ctx, int n, eo_poisson **out)
{
    *out = NULL;
    if (n < 2 || n > 20000) return eo_error(ctx, EO_ERR_INVALID, "poisson: n = %d cells per side, need 2 <= n <= 20000", n);
    eo_poisson *p = eo_calloc(ctx, 1, sizeof *p);
    if (!p) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (poisson)");
    p->ctx = ctx;
    p->n = n;
    p->nfree = (n - 1) * (n - 1);
    int nt = 2 * n * n, rc;
    p->F = eo_calloc(ctx, (size_t)p->nfree, sizeof(double));
    p->Ku = eo_calloc(ctx, (size_t)p->nfree, sizeof(double));
    p->tri = eo_malloc(ctx, 3 * (size_t)nt * sizeof(int));
    p->dofs = eo_malloc(ctx, 3 * (size_t)nt * sizeof(int));
    if (!p->F || !p->Ku || !p->tri || !p->dofs) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (poisson n = %d)", n);
        goto fail;
    }
    for (int j = 0, t = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1; /* counter-clockwise square */
            int tris[2][3] = {{a, b, c}, {a, c, d}};
            for (int k = 0; k < 2; k++, t++)
                for (int q = 0; q < 3; q++) {
                    p->tri[3 * t + q] = tris[k][q];
                    p->dofs[3 * t + q] = node_free(p, tris[k][q]);
                }
        }
    EO_TRY(rc = eo_assembler_create(ctx, p->nfree, &p->as));
    int grp = eo_assembler_add_elements(ctx, p->as, nt, 3, p->dofs);
    if (grp < 0) {
        rc = grp;
        goto fail;
    }
    EO_TRY(rc = eo_assembler_finalize(ctx, p->as));
    for (int t = 0; t < nt; t++) {
        double x[3], y[3], b[3], c[3], Ke[9];
        for (int q = 0; q < 3; q++) node_xy(p, p->tri[3 * t + q], &x[q], &y[q]);
        for (int q = 0; q < 3; q++) {
            int j = (q + 1) % 3, k = (q + 2) % 3;
            b[q] = y[j] - y[k];
            c[q] = x[k] - x[j];
        }
        double A = 0.5 * ((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
        for (int q = 0; q < 3; q++)
            for (int r = 0; r < 3; r++) Ke[3 * q + r] = (b[q] * b[r] + c[q] * c[r]) / (4 * A);
        eo_assembler_add(p->as, grp, t, Ke);
        /* load: edge midpoints m_qr (between q and r); N_j(m_qr) = ½ if j ∈ {q, r} */
        for (int q = 0; q < 3; q++) {
            int r = (q + 1) % 3;
            double fm = source(0.5 * (x[q] + x[r]), 0.5 * (y[q] + y[r]));
            int iq = p->dofs[3 * t + q], ir = p->dofs[3 * t + r];
            if (iq >= 0) p->F[iq] += A / 3 * fm * 0.5;
            if (ir >= 0) p->F[ir] += A / 3 * fm * 0.5;
        }
    }
    p->obj.n = p->nfree;
    p->obj.ops = &poisson_ops;
    p->obj.data = p;
    *out = p;
    return EO_OK;
fail:
    eo_poisson_destroy(&p);
    return rc;
}

eo_objective *eo_poisson_objective(eo_poisson *p) { return &p->obj; }
const eo_csc *eo_poisson_matrix(const eo_poisson *p) { return eo_assembler_matrix(p->as); }
const double *eo_poisson_load(const eo_poisson *p) { return p->F; }
double eo_poisson_h(const eo_poisson *p) { return 1.0 / p->n; }

int eo_poisson_error(const eo_poisson *p, const double *u, double *l2, double *max_err)
{
    /* Dunavant degree 5: barycentric points and weights (sum 1) */
    static const double w[7] = {0.225, 0.132394152788506, 0.132394152788506, 0.132394152788506,
                                0.125939180544827, 0.125939180544827, 0.125939180544827};
    static const double a1 = 0.059715871789770, b1 = 0.470142064105115, a2 = 0.797426985353087,
                        b2 = 0.101286507323456;
    const double L[7][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {a1, b1, b1}, {b1, a1, b1}, {b1, b1, a1},
                            {a2, b2, b2}, {b2, a2, b2}, {b2, b2, a2}};
    const int nt = 2 * p->n * p->n;
    double e2 = 0, mx = 0;
    for (int t = 0; t < nt; t++) {
        double x[3], y[3], uv[3];
        for (int q = 0; q < 3; q++) {
            node_xy(p, p->tri[3 * t + q], &x[q], &y[q]);
            int i = p->dofs[3 * t + q];
            uv[q] = i >= 0 ? u[i] : 0;
            if (i >= 0) mx = fmax(mx, fabs(uv[q] - exact(x[q], y[q])));
        }
        double A = 0.5 * fabs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
        for (int k = 0; k < 7; k++) {
            double px = 0, py = 0, uh = 0;
            for (int q = 0; q < 3; q++) {
                px += L[k][q] * x[q];
                py += L[k][q] * y[q];
                uh += L[k][q] * uv[q];
            }
            double d = uh - exact(px, py);
            e2 += w[k] * A * d * d;
        }
    }
    *l2 = sqrt(e2);
    *max_err = mx;
    return isfinite(e2) && isfinite(mx) ? EO_OK : EO_ERR_NONFINITE;
}
