/* 2D Poisson FEM (notes 001 §3, corrected weak form per ERRATA), see poisson.h.
 *
 * Linear triangle with vertices p₁, p₂, p₃, area A: Nᵢ = (aᵢ + bᵢx + cᵢy)/(2A) with
 * bᵢ = y_j − y_k, cᵢ = x_k − x_j (i, j, k cyclic), so ∇Nᵢ = (bᵢ, cᵢ)/(2A) is constant and
 *     K^e_ij = ∫ ∇Nᵢ·∇N_j = (bᵢb_j + cᵢc_j)/(4|A|)      (001 eq. 48 per element;
 * either orientation: reversing it flips every bᵢ, cᵢ and the sign of A).
 * Load F_j = Σ_e ∫_e f N_j:
 *   midpoint  ∫_e φ ≈ (A/3) Σ_midpoints φ, exact for quadratics: N_j is ½ at the two
 *             midpoints of the edges through j, 0 at the third;
 *   centroid  001 eq. 50, A f(x_c) N_j(x_c) with N_j(x_c) = ⅓.
 * Dirichlet: boundary nodes get id −1 in the assembler and drop out of K; their values
 * u_D (the problem's exact u, 0 by default) enter F as −K^e_jb u_D per element.
 * L2 error: Dunavant's 7-point rule (degree 5) on every triangle. */
#include <math.h>
#include <string.h>

#include "elastopt/poisson.h"
#include "elastopt/suggest.h"

static const double PI = 3.14159265358979323846;

struct eo_poisson {
    eo_ctx *ctx;
    int n;             /* cells per side on the unit square, 0 for a general mesh */
    int nfree;
    double h;
    eo_trimesh *mesh;  /* owned copy */
    eo_poisson_opts opts;
    eo_assembler *as;
    double *F, *Ku;
    int *free_of;      /* nv: free id or −1 */
    int *node_of;      /* nfree: node */
    int *dofs;         /* 3·nt free ids (−1 boundary) */
    eo_objective obj;
};

static double sine_u(void *d, double x, double y)
{
    (void)d;
    return sin(PI * x) * sin(PI * y);
}
static double sine_f(void *d, double x, double y) { return 2 * PI * PI * sine_u(d, x, y); }
static const eo_poisson_problem sine_problem = {.f = sine_f, .u = sine_u, .data = NULL};

void eo_poisson_opts_default(eo_poisson_opts *o)
{
    memset(o, 0, sizeof *o);
    o->quadrature = EO_POISSON_QUAD_MIDPOINT;
    o->dirichlet = 1;
    o->problem = NULL;
}

static const char *const quad_names[] = {"midpoint", "centroid"};

const char *eo_poisson_quadrature_name(eo_poisson_quadrature q)
{
    return (unsigned)q < 2 ? quad_names[q] : "?";
}

int eo_poisson_quadrature_parse(eo_ctx *ctx, const char *name, eo_poisson_quadrature *q)
{
    for (int i = 0; i < 2; i++)
        if (strcmp(name, quad_names[i]) == 0) {
            *q = (eo_poisson_quadrature)i;
            return EO_OK;
        }
    char hint[96];
    eo_suggest_hint(name, "midpoint, centroid", NULL, hint, sizeof hint);
    return eo_error(ctx, EO_ERR_UNKNOWN_NAME, "unknown poisson.quadrature '%s'%s; valid: midpoint, centroid", name,
                    hint);
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
    eo_assembler_destroy(&p->as);
    eo_trimesh_destroy(&p->mesh);
    eo_free(p->ctx, p->F);
    eo_free(p->ctx, p->Ku);
    eo_free(p->ctx, p->free_of);
    eo_free(p->ctx, p->node_of);
    eo_free(p->ctx, p->dofs);
    eo_free(p->ctx, p);
    *pp = NULL;
}

static const eo_poisson_problem *problem_of(const eo_poisson *p)
{
    return p->opts.problem ? p->opts.problem : &sine_problem;
}

static double dirichlet_value(const eo_poisson *p, int v)
{
    const eo_poisson_problem *pr = problem_of(p);
    return pr->u ? pr->u(pr->data, p->mesh->xy[2 * v], p->mesh->xy[2 * v + 1]) : 0.0;
}

/* p->mesh set: boundary, free ids, assembly of K and F. */
static int setup(eo_poisson *p)
{
    eo_ctx *ctx = p->ctx;
    const eo_trimesh *m = p->mesh;
    const eo_poisson_problem *pr = problem_of(p);
    unsigned char *bnd = NULL;
    int rc = EO_OK;
    for (int i = 0; i < 3 * m->nt; i++)
        if (m->tri[i] < 0 || m->tri[i] >= m->nv)
            return eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(NULL, -1, "triangle", i / 3),
                               "poisson: node %d out of range [0, %d)", m->tri[i], m->nv);
    bnd = eo_calloc(ctx, (size_t)(m->nv ? m->nv : 1), 1);
    p->free_of = eo_malloc(ctx, (size_t)(m->nv ? m->nv : 1) * sizeof(int));
    p->dofs = eo_malloc(ctx, 3 * (size_t)(m->nt ? m->nt : 1) * sizeof(int));
    if (!bnd || !p->free_of || !p->dofs) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (poisson)");
        goto done;
    }
    if (p->opts.dirichlet && (rc = eo_trimesh_boundary(ctx, m, bnd)) < 0) goto done;
    p->nfree = 0;
    for (int v = 0; v < m->nv; v++) p->free_of[v] = bnd[v] ? -1 : p->nfree++;
    if (p->nfree == 0) {
        rc = eo_error(ctx, EO_ERR_MESH, "poisson: every node is on the boundary; no unknown left");
        goto done;
    }
    p->node_of = eo_malloc(ctx, (size_t)p->nfree * sizeof(int));
    p->F = eo_calloc(ctx, (size_t)p->nfree, sizeof(double));
    p->Ku = eo_calloc(ctx, (size_t)p->nfree, sizeof(double));
    if (!p->node_of || !p->F || !p->Ku) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (poisson, %d unknowns)", p->nfree);
        goto done;
    }
    for (int v = 0; v < m->nv; v++)
        if (p->free_of[v] >= 0) p->node_of[p->free_of[v]] = v;
    for (int i = 0; i < 3 * m->nt; i++) p->dofs[i] = p->free_of[m->tri[i]];
    EO_TRY(rc = eo_assembler_create(ctx, p->nfree, &p->as));
    int grp = eo_assembler_add_elements(ctx, p->as, m->nt, 3, p->dofs);
    if (grp < 0) {
        rc = grp;
        goto done;
    }
    EO_TRY(rc = eo_assembler_finalize(ctx, p->as));
    const double scale = eo_trimesh_max_edge(m);
    for (int t = 0; t < m->nt; t++) {
        double x[3], y[3], b[3], c[3], Ke[9];
        const int *tv = m->tri + 3 * t, *td = p->dofs + 3 * t;
        for (int q = 0; q < 3; q++) x[q] = m->xy[2 * tv[q]], y[q] = m->xy[2 * tv[q] + 1];
        for (int q = 0; q < 3; q++) {
            int j = (q + 1) % 3, k = (q + 2) % 3;
            b[q] = y[j] - y[k];
            c[q] = x[k] - x[j];
        }
        double A = fabs(0.5 * ((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])));
        if (!(A > 1e-14 * scale * scale)) {
            rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(NULL, -1, "triangle", t),
                             "poisson: degenerate triangle (area %g)", A);
            goto done;
        }
        for (int q = 0; q < 3; q++)
            for (int r = 0; r < 3; r++) Ke[3 * q + r] = (b[q] * b[r] + c[q] * c[r]) / (4 * A);
        eo_assembler_add(p->as, grp, t, Ke);
        double fe[3] = {0, 0, 0};
        if (p->opts.quadrature == EO_POISSON_QUAD_CENTROID) {
            double fc = pr->f(pr->data, (x[0] + x[1] + x[2]) / 3, (y[0] + y[1] + y[2]) / 3);
            for (int q = 0; q < 3; q++) fe[q] = A * fc / 3;
        } else { /* edge midpoints m_qr (between q and r); N_j(m_qr) = ½ if j ∈ {q, r} */
            for (int q = 0; q < 3; q++) {
                int r = (q + 1) % 3;
                double fm = pr->f(pr->data, 0.5 * (x[q] + x[r]), 0.5 * (y[q] + y[r]));
                fe[q] += A / 3 * fm * 0.5;
                fe[r] += A / 3 * fm * 0.5;
            }
        }
        for (int q = 0; q < 3; q++) {
            if (td[q] < 0) continue;
            double lift = 0;
            for (int r = 0; r < 3; r++)
                if (td[r] < 0) lift += Ke[3 * q + r] * dirichlet_value(p, tv[r]);
            p->F[td[q]] += fe[q] - lift;
        }
    }
    p->obj.n = p->nfree;
    p->obj.ops = &poisson_ops;
    p->obj.data = p;
fail:
done:
    eo_free(ctx, bnd);
    return rc;
}

static int create_common(eo_ctx *ctx, eo_trimesh *mesh, int n, const eo_poisson_opts *o, eo_poisson **out)
{
    eo_poisson *p = eo_calloc(ctx, 1, sizeof *p);
    if (!p) {
        eo_trimesh_destroy(&mesh);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory (poisson)");
    }
    p->ctx = ctx;
    p->mesh = mesh;
    p->n = n;
    if (o) p->opts = *o;
    else eo_poisson_opts_default(&p->opts);
    if ((unsigned)p->opts.quadrature > EO_POISSON_QUAD_CENTROID) {
        eo_poisson_destroy(&p);
        return eo_error(ctx, EO_ERR_INVALID, "poisson: quadrature %d unknown", (int)o->quadrature);
    }
    p->h = n > 0 ? 1.0 / n : eo_trimesh_max_edge(mesh);
    int rc = setup(p);
    if (rc < 0) {
        eo_poisson_destroy(&p);
        return rc;
    }
    *out = p;
    return EO_OK;
}

int eo_poisson_create_opts(eo_ctx *ctx, int n, const eo_poisson_opts *o, eo_poisson **out)
{
    *out = NULL;
    if (n < 2 || n > 20000) return eo_error(ctx, EO_ERR_INVALID, "poisson: n = %d cells per side, need 2 <= n <= 20000", n);
    eo_trimesh *m;
    int rc = eo_trimesh_create(ctx, (n + 1) * (n + 1), 2 * n * n, &m);
    if (rc < 0) return rc;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            m->xy[2 * (j * (n + 1) + i)] = (double)i / n;
            m->xy[2 * (j * (n + 1) + i) + 1] = (double)j / n;
        }
    for (int j = 0, t = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1; /* counter-clockwise square */
            int tris[2][3] = {{a, b, c}, {a, c, d}};
            for (int k = 0; k < 2; k++, t++)
                for (int q = 0; q < 3; q++) m->tri[3 * t + q] = tris[k][q];
        }
    return create_common(ctx, m, n, o, out);
}

int eo_poisson_create(eo_ctx *ctx, int n, eo_poisson **out) { return eo_poisson_create_opts(ctx, n, NULL, out); }

int eo_poisson_create_mesh(eo_ctx *ctx, const eo_trimesh *src, const eo_poisson_opts *o, eo_poisson **out)
{
    *out = NULL;
    eo_trimesh *m;
    int rc = eo_trimesh_create(ctx, src->nv, src->nt, &m);
    if (rc < 0) return rc;
    memcpy(m->xy, src->xy, 2 * (size_t)src->nv * sizeof(double));
    memcpy(m->tri, src->tri, 3 * (size_t)src->nt * sizeof(int));
    return create_common(ctx, m, 0, o, out);
}

eo_objective *eo_poisson_objective(eo_poisson *p) { return &p->obj; }
const eo_csc *eo_poisson_matrix(const eo_poisson *p) { return eo_assembler_matrix(p->as); }
const double *eo_poisson_load(const eo_poisson *p) { return p->F; }
double eo_poisson_h(const eo_poisson *p) { return p->h; }
const eo_trimesh *eo_poisson_mesh(const eo_poisson *p) { return p->mesh; }
int eo_poisson_free_node(const eo_poisson *p, int i) { return i >= 0 && i < p->nfree ? p->node_of[i] : -1; }
int eo_poisson_node_free(const eo_poisson *p, int v) { return v >= 0 && v < p->mesh->nv ? p->free_of[v] : -1; }

void eo_poisson_nodal(const eo_poisson *p, const double *u, double *nodal)
{
    for (int v = 0; v < p->mesh->nv; v++) nodal[v] = p->free_of[v] >= 0 ? u[p->free_of[v]] : dirichlet_value(p, v);
}

int eo_poisson_write_vtu(const eo_poisson *p, const double *u, const char *path)
{
    const eo_trimesh *m = p->mesh;
    double *nodal = eo_malloc(p->ctx, (size_t)(m->nv ? m->nv : 1) * sizeof(double));
    if (!nodal) return eo_error(p->ctx, EO_ERR_NOMEM, "out of memory (poisson vtu)");
    eo_poisson_nodal(p, u, nodal);
    int rc = eo_vtu_write_tri(p->ctx, path, m->nv, m->xy, m->nt, m->tri, "u", nodal);
    eo_free(p->ctx, nodal);
    return rc;
}

int eo_poisson_error(const eo_poisson *p, const double *u, double *l2, double *max_err)
{
    const eo_poisson_problem *pr = problem_of(p);
    if (!pr->u) return eo_error(p->ctx, EO_ERR_UNSUPPORTED, "poisson: the problem has no exact solution");
    /* Dunavant degree 5: barycentric points and weights (sum 1) */
    static const double w[7] = {0.225, 0.132394152788506, 0.132394152788506, 0.132394152788506,
                                0.125939180544827, 0.125939180544827, 0.125939180544827};
    static const double a1 = 0.059715871789770, b1 = 0.470142064105115, a2 = 0.797426985353087,
                        b2 = 0.101286507323456;
    const double L[7][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {a1, b1, b1}, {b1, a1, b1}, {b1, b1, a1},
                            {a2, b2, b2}, {b2, a2, b2}, {b2, b2, a2}};
    const eo_trimesh *m = p->mesh;
    double e2 = 0, mx = 0;
    for (int t = 0; t < m->nt; t++) {
        double x[3], y[3], uv[3];
        for (int q = 0; q < 3; q++) {
            int v = m->tri[3 * t + q], i = p->free_of[v];
            x[q] = m->xy[2 * v];
            y[q] = m->xy[2 * v + 1];
            uv[q] = i >= 0 ? u[i] : dirichlet_value(p, v);
            if (i >= 0) mx = fmax(mx, fabs(uv[q] - pr->u(pr->data, x[q], y[q])));
        }
        double A = 0.5 * fabs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
        for (int k = 0; k < 7; k++) {
            double px = 0, py = 0, uh = 0;
            for (int q = 0; q < 3; q++) {
                px += L[k][q] * x[q];
                py += L[k][q] * y[q];
                uh += L[k][q] * uv[q];
            }
            double d = uh - pr->u(pr->data, px, py);
            e2 += w[k] * A * d * d;
        }
    }
    *l2 = sqrt(e2);
    *max_err = mx;
    return isfinite(e2) && isfinite(mx) ? EO_OK : EO_ERR_NONFINITE;
}
