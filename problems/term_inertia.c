/* Inertia term: ½ (x − x̃)ᵀ M (x − x̃), weight 1 (absent for the static integrator).
 *
 * Consistent mass (002 §4.1 with the ERRATA's volume form): per tet
 *     M_t = ρV/20 · (I₄ + 𝟙𝟙ᵀ) ⊗ I₃      (ρV/10 on the diagonal, ρV/20 off it),
 * so dᵀM_t d = ρV/20 (Σᵢ‖dᵢ‖² + ‖Σᵢ dᵢ‖²) and (M_t d)ᵢ = ρV/20 (dᵢ + Σⱼ dⱼ).
 * Lumped mass: ρV/4 on each tet vertex (s->vmass), M = diag(m_v) ⊗ I₃.
 * Other elements (element.h): their consistent mass ρV·M_el ⊗ I₃ and lumped weights
 * (s->vmass); the vertex op is the linear tet's only.
 * Point masses (s->pmass, scene point_mass / point_masses) are part of s->vmass and are
 * added on the diagonal of the consistent mass too.
 * The consistent Hessian is constant: its values in the fixed pattern are computed once
 * per pattern (prepare) and added with one vector loop per assembly (with a part set,
 * eo_sys.part_tets, the part's tet matrices are assembled instead). */
#include <string.h>

#include "elastopt/step.h"
#include "term.h"

typedef struct inertia_data {
    int lumped;
    double *mass_val;   /* consistent: M's values in the pattern (nnz), per attach */
    int nnz;
} inertia_data;


/* Consistent mass of a general element (element.h): per tet ρV Σ_ab M_ab (d_a · d_b),
 * M the element's consistent mass per unit ρV, nodes s->enodes. */
static double consistent_el(const eo_sys *s, const double *x, const double *xt, double *g)
{
    const int n = s->npe;
    const double *M = s->el->mass;
    double e = 0;
    for (int i = 0; i < eo_sys_ntets(s); i++) {
        const int k = eo_sys_tet(s, i);
        const int *en = s->enodes + (size_t)n * k;
        const double rv = s->rho[k] * s->vol[k];
        double d[3 * EO_ELEMENT_MAX_NODES];
        for (int a = 0; a < n; a++)
            for (int c = 0; c < 3; c++) d[3 * a + c] = x[3 * en[a] + c] - xt[3 * en[a] + c];
        for (int a = 0; a < n; a++) {
            double md[3] = {0, 0, 0};
            for (int b = 0; b < n; b++)
                for (int c = 0; c < 3; c++) md[c] += M[n * a + b] * d[3 * b + c];
            for (int c = 0; c < 3; c++) {
                e += rv * d[3 * a + c] * md[c];
                if (g) g[3 * en[a] + c] += rv * md[c];
            }
        }
    }
    return e;
}


static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    const inertia_data *d = t->data;
    const double *xt = t->vec;
    double e = 0;
    if (d->lumped) {
        for (int v = 0; v < s->nv; v++) {
            if (!eo_sys_vertex_on(s, v)) continue;
            double q = 0;
            for (int c = 0; c < 3; c++) {
                double dd = x[3 * v + c] - xt[3 * v + c];
                q += dd * dd;
            }
            e += s->vmass[v] * q;
        }
        return 0.5 * e;
    }
    if (!s->linear) e = consistent_el(s, x, xt, NULL);
    const int ord = s->tet_order && !s->part_tets; /* the copies in the visit order (term.h) */
    for (int i = 0; s->linear && i < eo_sys_ntets(s); i++) {
        const int k = eo_sys_tet(s, i);
        const int *tet = ord ? s->ord_tets + 4 * i : s->mesh->tets + 4 * k;
        const double rv = ord ? s->ord_rho[i] * s->ord_vol[i] : s->rho[k] * s->vol[k];
        double sum[3] = {0, 0, 0}, q = 0;
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) {
                double dd = x[3 * tet[a] + c] - xt[3 * tet[a] + c];
                q += dd * dd;
                sum[c] += dd;
            }
        e += rv / 20.0 * (q + sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    }
    for (int v = 0; s->pmass && v < s->nv; v++)
        for (int c = 0; c < 3 && eo_sys_vertex_on(s, v); c++)
            e += s->pmass[v] * (x[3 * v + c] - xt[3 * v + c]) * (x[3 * v + c] - xt[3 * v + c]);
    return 0.5 * e;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    const inertia_data *d = t->data;
    const double *xt = t->vec;
    double e = 0;
    if (d->lumped) {
        for (int v = 0; v < s->nv; v++)
            for (int c = 0; c < 3 && eo_sys_vertex_on(s, v); c++) {
                double dd = x[3 * v + c] - xt[3 * v + c];
                e += s->vmass[v] * dd * dd;
                g[3 * v + c] += s->vmass[v] * dd;
            }
        return 0.5 * e;
    }
    if (!s->linear) e = consistent_el(s, x, xt, g);
    const int ord = s->tet_order && !s->part_tets; /* the copies in the visit order (term.h) */
    for (int i = 0; s->linear && i < eo_sys_ntets(s); i++) {
        const int k = eo_sys_tet(s, i);
        const int *tet = ord ? s->ord_tets + 4 * i : s->mesh->tets + 4 * k;
        const double rv = ord ? s->ord_rho[i] * s->ord_vol[i] : s->rho[k] * s->vol[k];
        double dd[12], sum[3] = {0, 0, 0}, q = 0;
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) {
                dd[3 * a + c] = x[3 * tet[a] + c] - xt[3 * tet[a] + c];
                q += dd[3 * a + c] * dd[3 * a + c];
                sum[c] += dd[3 * a + c];
            }
        double m = rv / 20.0;
        e += m * (q + sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) g[3 * tet[a] + c] += m * (dd[3 * a + c] + sum[c]);
    }
    for (int v = 0; s->pmass && v < s->nv; v++)
        for (int c = 0; c < 3 && eo_sys_vertex_on(s, v); c++) {
            double dd = x[3 * v + c] - xt[3 * v + c];
            e += s->pmass[v] * dd * dd;
            g[3 * v + c] += s->pmass[v] * dd;
        }
    return 0.5 * e;
}

static int prepare(eo_term *t, eo_sys *s)
{
    inertia_data *d = t->data;
    if (d->lumped) return EO_OK;
    eo_csc *H = eo_assembler_matrix(s->as);
    eo_free(s->ctx, d->mass_val);
    d->mass_val = eo_malloc(s->ctx, (size_t)(H->nnz > 0 ? H->nnz : 1) * sizeof(double));
    if (!d->mass_val) return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (mass matrix)");
    d->nnz = H->nnz;
    eo_assembler_zero(s->as);
    for (int k = 0; k < s->nt; k++) { /* elem_H: one element's worth, serial */
        eo_sys_element_mass(s, k, s->elem_H);
        eo_assembler_add(s->as, s->tet_group, k, s->elem_H);
    }
    for (int j = 0; s->pmass && j < s->n_full; j++) {
        int i = s->full2free[j];
        if (i >= 0) eo_assembler_add_diag(s->as, i, s->pmass[j / 3]);
    }
    memcpy(d->mass_val, H->val, (size_t)H->nnz * sizeof(double));
    eo_assembler_zero(s->as);
    return EO_OK;
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    (void)x;
    (void)proj;
    const inertia_data *d = t->data;
    if (d->lumped) {
        for (int j = 0; j < s->n_full; j++) {
            int i = s->full2free[j];
            if (i >= 0 && eo_sys_vertex_on(s, j / 3)) eo_assembler_add_diag(s->as, i, s->vmass[j / 3]);
        }
        return EO_OK;
    }
    if (s->part_tets || s->vown) { /* a part: its tets' mass matrices, its vertices' point masses */
        for (int i = 0; i < eo_sys_ntets(s); i++) {
            const int k = eo_sys_tet(s, i);
            eo_sys_element_mass(s, k, s->elem_H);
            eo_assembler_add(s->as, s->tet_group, k, s->elem_H);
        }
        for (int j = 0; s->pmass && j < s->n_full; j++) {
            int i = s->full2free[j];
            if (i >= 0 && eo_sys_vertex_on(s, j / 3)) eo_assembler_add_diag(s->as, i, s->pmass[j / 3]);
        }
        return EO_OK;
    }
    eo_csc *H = eo_assembler_matrix(s->as);
    EO_ASSERT(H->nnz == d->nnz);
    for (int k = 0; k < d->nnz; k++) H->val[k] += d->mass_val[k];
    return EO_OK;
}

/* Vertex op (term.h): lumped ½m_v‖d_v‖²; consistent: the energy of each tet around v
 * (gradient ρV/20 (d_v + Σⱼ dⱼ), block ρV/10 I) and the point mass. */
static double vertex(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3)
{
    (void)proj;
    const inertia_data *d = t->data;
    const double *xt = t->vec;
    double e = 0;
    const double mp = d->lumped ? s->vmass[v] : s->pmass ? s->pmass[v] : 0;
    for (int c = 0; c < 3; c++) {
        double dd = x[3 * v + c] - xt[3 * v + c];
        e += 0.5 * mp * dd * dd;
        if (g3) g3[c] += mp * dd;
        if (H3) H3[4 * c] += mp;
    }
    if (d->lumped) return e;
    for (int q = s->vt_ptr[v]; q < s->vt_ptr[v + 1]; q++) {
        const int k = s->vt_tet[q];
        const int *tet = s->mesh->tets + 4 * k;
        const double m = s->rho[k] * s->vol[k] / 20.0;
        double sum[3] = {0, 0, 0}, qq = 0;
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) {
                double dd = x[3 * tet[a] + c] - xt[3 * tet[a] + c];
                qq += dd * dd;
                sum[c] += dd;
            }
        e += 0.5 * m * (qq + sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        for (int c = 0; c < 3; c++) {
            if (g3) g3[c] += m * (x[3 * v + c] - xt[3 * v + c] + sum[c]);
            if (H3) H3[4 * c] += 2 * m;
        }
    }
    return e;
}

static void destroy(eo_term *t, eo_ctx *ctx)
{
    inertia_data *d = t->data;
    if (d) eo_free(ctx, d->mass_val);
    eo_free(ctx, d);
}

static const eo_term_ops inertia_ops = {
    .name = "inertia",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .prepare = prepare,
    .destroy = destroy,
    .vertex = vertex,
};

int eo_term_inertia_create(eo_sys *s, int lumped, eo_term **out)
{
    int rc = eo_term_alloc(s, &inertia_ops, 1, out);
    if (rc < 0) return rc;
    inertia_data *d = eo_calloc(s->ctx, 1, sizeof *d);
    if (!d) {
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory");
    }
    d->lumped = lumped;
    (*out)->data = d;
    return EO_OK;
}

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)cfg;
    *out = NULL;
    if (!sc->integrator->inertia || sc->integrator->explicit_step) return EO_OK; /* static, or explicit */
    return eo_term_inertia_create(s, sc->lumped, out);
}

const eo_term_type eo_term_type_inertia = {
    .info = {.name = "inertia", .summary = "inertia ½‖x − x̃‖²_M of the implicit integrators (mass: the scene's `mass`)"},
    .flags = EO_TERM_INERTIA,
    .create = type_create,
};
