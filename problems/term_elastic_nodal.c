/* The nodal volumetric part of the average-nodal-pressure linear tet (element p1anp,
 * EO_ELEMENT_NODAL_DILATATION; Bonet & Burton 1998, "A simple average nodal pressure
 * tetrahedral element for incompressible and nearly incompressible dynamic explicit
 * applications", Commun. Numer. Meth. Engng 14; Bonet, Marriott & Hassan 2001 for the
 * implicit form). The elastic term adds it to the tets' ψ_d (the material at
 * λ_d = min(λ, μ), element.h):
 *
 *     E_vol = Σ_a V_a κ_a/2 (J_a − 1)²,   V_a = Σ_{t∋a} V_t/4,
 *     J_a = Σ_{t∋a} (V_t/4) J_t / V_a,   κ_a = Σ_{t∋a} (V_t/4) κ_t / V_a,  κ_t = λ_t − λ_d,
 *
 * i.e. the volume constraint counted once per vertex (its patch's volume ratio) instead of
 * once per tet, which is what frees the linear tet from volumetric locking (about one
 * constraint per vertex instead of five to six per vertex).
 *   ∇E_vol = Σ_t c_t ∇J_t,  c_t = (V_t/4) Σ_{a∈t} κ_a (J_a − 1),
 *   ∇²E_vol = Σ_a V_a κ_a ∇J_a ∇J_aᵀ + Σ_t c_t ∇²J_t,  ∇J_a = Σ_{t∋a} (V_t / 4V_a) ∇J_t.
 * The first Hessian part couples the whole patch of a (every vertex of a tet around a):
 * one assembler element per vertex over its patch, grouped by patch size (block groups,
 * (patch size)² ints each). With a projection asked, the second part (indefinite) is
 * dropped: Gauss–Newton, PSD. Serial loops; no allocation after create/attach. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "term.h"

struct eo_anp {
    int nv, nt;
    double *Va, *ka;      /* nv: nodal volume, nodal κ */
    double *Ja;           /* nv: nodal J (scratch) */
    double *Jt, *dJ;      /* nt, 12·nt: tet J and ∇J_t (scratch) */
    int *vt_ptr, *vt_tet; /* vertex -> tets (CSR) */
    int *pptr, *pvert;    /* vertex -> its patch's vertices (CSR, sorted, a included) */
    int *loc;             /* per (a, q-th tet of a): the patch slots of the tet's 4 corners (4 each) */
    int smax;
    int *ghandle;         /* smax+1: assembler group of the patches of size s, -1 none */
    int *gelem;           /* nv: element index of a's patch in its group */
    int *dofs;            /* 3·Σ patch sizes: the groups' dof lists (one block per size) */
    double *K, *b;        /* (3·smax)², 3·smax scratch */
};

static int cmp_int(const void *a, const void *b)
{
    const int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

void eo_anp_destroy(eo_anp **pa, eo_ctx *ctx)
{
    eo_anp *a = *pa;
    if (!a) return;
    void *arr[] = {a->Va, a->ka, a->Ja, a->Jt, a->dJ, a->vt_ptr, a->vt_tet, a->pptr, a->pvert, a->loc, a->ghandle,
                   a->gelem, a->dofs, a->K, a->b};
    for (size_t i = 0; i < sizeof arr / sizeof *arr; i++) eo_free(ctx, arr[i]);
    eo_free(ctx, a);
    *pa = NULL;
}

int eo_anp_create(eo_sys *s, eo_anp **out)
{
    eo_ctx *ctx = s->ctx;
    const int nv = s->nv, nt = s->nt;
    const int *tets = s->mesh->tets;
    *out = NULL;
    eo_anp *a = eo_calloc(ctx, 1, sizeof *a);
    if (!a) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (nodal pressure)");
    a->nv = nv, a->nt = nt;
    const size_t nv1 = (size_t)(nv > 0 ? nv : 1), nt1 = (size_t)(nt > 0 ? nt : 1);
    a->Va = eo_calloc(ctx, nv1, sizeof(double));
    a->ka = eo_calloc(ctx, nv1, sizeof(double));
    a->Ja = eo_calloc(ctx, nv1, sizeof(double));
    a->Jt = eo_calloc(ctx, nt1, sizeof(double));
    a->dJ = eo_calloc(ctx, 12 * nt1, sizeof(double));
    a->vt_ptr = eo_calloc(ctx, nv1 + 1, sizeof(int));
    a->vt_tet = eo_malloc(ctx, 4 * nt1 * sizeof(int));
    a->pptr = eo_calloc(ctx, nv1 + 1, sizeof(int));
    a->gelem = eo_calloc(ctx, nv1, sizeof(int));
    if (!a->Va || !a->ka || !a->Ja || !a->Jt || !a->dJ || !a->vt_ptr || !a->vt_tet || !a->pptr || !a->gelem) goto nomem;
    /* vertex -> tets; nodal volumes and κ (materials with λ ≤ μ contribute κ_t = 0) */
    for (int t = 0; t < nt; t++)
        for (int q = 0; q < 4; q++) a->vt_ptr[tets[4 * t + q] + 1]++;
    for (int v = 0; v < nv; v++) a->vt_ptr[v + 1] += a->vt_ptr[v];
    {
        int *fill = a->gelem; /* scratch, reset below */
        for (int t = 0; t < nt; t++)
            for (int q = 0; q < 4; q++) {
                const int v = tets[4 * t + q];
                a->vt_tet[a->vt_ptr[v] + fill[v]++] = t;
            }
        memset(fill, 0, nv1 * sizeof(int));
    }
    for (int t = 0; t < nt; t++) {
        if (s->tet_type[t]->flags & EO_MATERIAL_EDGE) continue;
        double kappa;
        eo_element_split_coef(s->tet_coef[t], &kappa);
        for (int q = 0; q < 4; q++) {
            a->Va[tets[4 * t + q]] += s->vol[t] / 4;
            a->ka[tets[4 * t + q]] += s->vol[t] / 4 * kappa;
        }
    }
    for (int v = 0; v < nv; v++)
        if (a->Va[v] > 0) a->ka[v] /= a->Va[v];
    /* patches: the sorted unique corners of the tets around each vertex */
    size_t np = 0;
    for (int v = 0; v < nv; v++) np += 4 * (size_t)(a->vt_ptr[v + 1] - a->vt_ptr[v]);
    a->pvert = eo_malloc(ctx, (np ? np : 1) * sizeof(int));
    a->loc = eo_malloc(ctx, (np ? np : 1) * sizeof(int));
    if (!a->pvert || !a->loc) goto nomem;
    int pos = 0;
    for (int v = 0; v < nv; v++) {
        const int p0 = pos;
        for (int q = a->vt_ptr[v]; q < a->vt_ptr[v + 1]; q++)
            for (int c = 0; c < 4; c++) a->pvert[pos++] = tets[4 * a->vt_tet[q] + c];
        qsort(a->pvert + p0, (size_t)(pos - p0), sizeof(int), cmp_int);
        int u = p0;
        for (int i = p0; i < pos; i++)
            if (i == p0 || a->pvert[i] != a->pvert[i - 1]) a->pvert[u++] = a->pvert[i];
        pos = u;
        a->pptr[v + 1] = pos;
        if (pos - p0 > a->smax) a->smax = pos - p0;
    }
    /* slots of each incident tet's corners in the patch */
    for (int v = 0; v < nv; v++) {
        const int *pv = a->pvert + a->pptr[v];
        const int ps = a->pptr[v + 1] - a->pptr[v];
        for (int q = a->vt_ptr[v]; q < a->vt_ptr[v + 1]; q++)
            for (int c = 0; c < 4; c++) {
                const int key = tets[4 * a->vt_tet[q] + c];
                const int *f = bsearch(&key, pv, (size_t)ps, sizeof(int), cmp_int);
                a->loc[4 * q + c] = (int)(f - pv);
            }
    }
    a->ghandle = eo_malloc(ctx, (size_t)(a->smax + 1) * sizeof(int));
    a->dofs = eo_malloc(ctx, 3 * (size_t)(a->pptr[nv] > 0 ? a->pptr[nv] : 1) * sizeof(int));
    a->K = eo_malloc(ctx, 9 * (size_t)(a->smax > 0 ? a->smax * a->smax : 1) * sizeof(double));
    a->b = eo_malloc(ctx, 3 * (size_t)(a->smax > 0 ? a->smax : 1) * sizeof(double));
    if (!a->ghandle || !a->dofs || !a->K || !a->b) goto nomem;
    *out = a;
    return EO_OK;
nomem:
    eo_anp_destroy(&a, ctx);
    return eo_error(ctx, EO_ERR_NOMEM, "out of memory (nodal pressure of %d vertices)", nv);
}

/* One assembler element per vertex over its patch, grouped by patch size. */
int eo_anp_attach(eo_anp *a, eo_sys *s)
{
    int off = 0;
    for (int sz = 1; sz <= a->smax; sz++) {
        a->ghandle[sz] = -1;
        int cnt = 0, *d = a->dofs + off;
        for (int v = 0; v < a->nv; v++) {
            if (a->pptr[v + 1] - a->pptr[v] != sz) continue;
            for (int i = 0; i < sz; i++)
                for (int c = 0; c < 3; c++) d[3 * (cnt * sz + i) + c] = s->full2free[3 * a->pvert[a->pptr[v] + i] + c];
            a->gelem[v] = cnt++;
        }
        if (!cnt) continue;
        const int h = eo_assembler_add_elements(s->ctx, s->as, cnt, 3 * sz, d);
        if (h < 0) return h;
        a->ghandle[sz] = h;
        off += 3 * cnt * sz;
    }
    return EO_OK;
}

/* J_t, ∇J_t of every tet and the nodal J_a at x; returns the energy Σ V_a κ_a/2 (J_a − 1)² */
static double nodal_state(eo_anp *a, const eo_sys *s, const double *x, int grad)
{
    const int *tets = s->mesh->tets;
    memset(a->Ja, 0, (size_t)a->nv * sizeof(double));
    for (int t = 0; t < a->nt; t++) {
        double x12[12], F[9];
        eo_gather12(x, tets + 4 * t, x12);
        eo_tet_F(s->Dminv + 9 * t, x12, F);
        const double J = eo_det3(F);
        a->Jt[t] = J;
        for (int q = 0; q < 4; q++) a->Ja[tets[4 * t + q]] += s->vol[t] / 4 * J;
        if (!grad) continue;
        const double C[9] = {F[4] * F[8] - F[5] * F[7], F[5] * F[6] - F[3] * F[8], F[3] * F[7] - F[4] * F[6],
                             F[2] * F[7] - F[1] * F[8], F[0] * F[8] - F[2] * F[6], F[1] * F[6] - F[0] * F[7],
                             F[1] * F[5] - F[2] * F[4], F[2] * F[3] - F[0] * F[5], F[0] * F[4] - F[1] * F[3]};
        double G[12];
        static const double bary_c[4] = {0.25, 0.25, 0.25, 0.25};
        eo_element_grad(&eo_element_p1, s->Dminv + 9 * t, bary_c, G);
        double *d = a->dJ + 12 * t;
        for (int q = 0; q < 4; q++)
            for (int i = 0; i < 3; i++)
                d[3 * q + i] = C[3 * i] * G[3 * q] + C[3 * i + 1] * G[3 * q + 1] + C[3 * i + 2] * G[3 * q + 2];
    }
    double e = 0;
    for (int v = 0; v < a->nv; v++) {
        if (!(a->Va[v] > 0)) continue;
        a->Ja[v] /= a->Va[v];
        const double r = a->Ja[v] - 1;
        e += 0.5 * a->Va[v] * a->ka[v] * r * r;
    }
    return e;
}

double eo_anp_energy(eo_anp *a, const eo_sys *s, const double *x) { return nodal_state(a, s, x, 0); }

double eo_anp_gradient(eo_anp *a, const eo_sys *s, const double *x, double w, double *g)
{
    const double e = nodal_state(a, s, x, 1);
    const int *tets = s->mesh->tets;
    for (int t = 0; t < a->nt; t++) {
        double c = 0;
        for (int q = 0; q < 4; q++) {
            const int v = tets[4 * t + q];
            c += a->ka[v] * (a->Ja[v] - 1);
        }
        c *= w * s->vol[t] / 4;
        for (int q = 0; q < 4; q++)
            for (int i = 0; i < 3; i++) g[3 * tets[4 * t + q] + i] += c * a->dJ[12 * t + 3 * q + i];
    }
    return e;
}

int eo_anp_hessian(eo_anp *a, const eo_sys *s, const double *x, eo_proj proj, double w)
{
    nodal_state(a, s, x, 1);
    const int *tets = s->mesh->tets;
    /* Σ_a V_a κ_a ∇J_a ∇J_aᵀ over each patch */
    for (int v = 0; v < a->nv; v++) {
        const int sz = a->pptr[v + 1] - a->pptr[v], n3 = 3 * sz;
        if (!(a->Va[v] > 0) || !(a->ka[v] > 0) || a->ghandle[sz] < 0) continue;
        memset(a->b, 0, (size_t)n3 * sizeof(double));
        for (int q = a->vt_ptr[v]; q < a->vt_ptr[v + 1]; q++) {
            const int t = a->vt_tet[q];
            const double f = s->vol[t] / (4 * a->Va[v]);
            for (int c = 0; c < 4; c++)
                for (int i = 0; i < 3; i++) a->b[3 * a->loc[4 * q + c] + i] += f * a->dJ[12 * t + 3 * c + i];
        }
        const double k = w * a->Va[v] * a->ka[v];
        for (int i = 0; i < n3; i++)
            for (int j = 0; j < n3; j++) a->K[(size_t)i * n3 + j] = k * a->b[i] * a->b[j];
        eo_assembler_add(s->as, a->ghandle[sz], a->gelem[v], a->K);
    }
    /* Σ_t c_t ∇²J_t: the exact Hessian only (dropped when projecting: Gauss–Newton) */
    for (int t = 0; t < a->nt; t++) {
        const eo_proj pt = s->proj_of ? (eo_proj)s->proj_of[t] : proj;
        if (pt != EO_PROJ_NONE) continue;
        double c = 0;
        for (int q = 0; q < 4; q++) {
            const int v = tets[4 * t + q];
            c += a->ka[v] * (a->Ja[v] - 1);
        }
        c *= w * s->vol[t] / 4;
        if (c == 0) continue;
        double x12[12], F[9], D[81], G[12], H[144];
        static const double bary_c[4] = {0.25, 0.25, 0.25, 0.25};
        eo_gather12(x, tets + 4 * t, x12);
        eo_tet_F(s->Dminv + 9 * t, x12, F);
        eo_elementi_det_hessian(F, D);
        eo_element_grad(&eo_element_p1, s->Dminv + 9 * t, bary_c, G);
        memset(H, 0, sizeof H);
        eo_elementi_GtDG(4, G, D, c, H);
        eo_elementi_mirror(4, H);
        eo_assembler_add(s->as, s->tet_group, t, H);
    }
    return EO_OK;
}
