/* Spring term (mass-spring systems, 001 §2.2): w · Σₑ kₑ/2 (‖x_b − x_a‖ − Lₑ)² over
 *   - the unique edges of the tets whose region material is an edge model
 *     (EO_MATERIAL_EDGE, `material.model = "spring"`, stiffness material.k): those tets
 *     have no tet elasticity, their mass still comes from ρV;
 *   - the scene's `springs` (structural springs on every mesh edge, or an explicit list
 *     of vertex pairs), stiffness springs.k, on top of whatever the materials give.
 * Rest length Lₑ = ‖X_b − X_a‖ at the rest positions. The spring material's edge_eval
 * gives energy, 6-gradient (Hooke, 001 eq. 2: f_a = −k(l − L) n̂, n̂ = (x_a − x_b)/l)
 * and the (projected) 6×6 Hessian. Absent (no term) when there is no spring.
 *
 * Damping (scene springs, explicit integrators): f_a = −c ((v_a − v_b)·n̂) n̂ = −f_b,
 * which dissipates power c((v_a − v_b)·n̂)² and leaves rigid motions alone. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/step.h"
#include "term.h"

typedef struct spring_data {
    int ne;
    int *ab;                              /* 2·ne vertex ids */
    double *L;                            /* ne rest lengths */
    const eo_material_type **type;        /* ne */
    const eo_material_coef **coef;        /* ne */
    int group;                            /* assembler group (6 ids per edge) */
    int *dofs;                            /* 6·ne free ids */
    int first_scene;                      /* edges [first_scene, ne) are scene springs */
    double damping;                       /* c of the scene springs, N·s/m */
    eo_material_coef scene_coef;          /* k of the scene springs */
    eo_material_coef *list_coef;          /* per scene spring (a lattice's kinds), or NULL */
    int *ve_ptr, *ve_edge;                /* vertex -> springs (CSR, nv + 1 and 2·ne) */
} spring_data;

extern const eo_material_type eo_material_spring;

static int cmp_edge(const void *a, const void *b)
{
    const int *x = a, *y = b;
    if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
    if (x[1] != y[1]) return x[1] < y[1] ? -1 : 1;
    return 0;
}

static double edge(const spring_data *d, int e, const double *x, eo_eval_what what, eo_proj proj,
                   double g[6], double H[36])
{
    const int a = d->ab[2 * e], b = d->ab[2 * e + 1];
    return d->type[e]->edge_eval(d->coef[e], d->L[e], x + 3 * a, x + 3 * b, what, proj, g, H);
}

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    (void)s;
    const spring_data *d = t->data;
    double e = 0;
    for (int k = 0; k < d->ne; k++) e += edge(d, k, x, EO_EVAL_ENERGY, EO_PROJ_NONE, NULL, NULL);
    return isnan(e) ? INFINITY : t->weight * e;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    (void)s;
    const spring_data *d = t->data;
    double e = 0, ge[6];
    for (int k = 0; k < d->ne; k++) {
        e += edge(d, k, x, EO_EVAL_GRAD, EO_PROJ_NONE, ge, NULL);
        const int a = d->ab[2 * k], b = d->ab[2 * k + 1];
        for (int c = 0; c < 3; c++) {
            g[3 * a + c] += t->weight * ge[c];
            g[3 * b + c] += t->weight * ge[3 + c];
        }
    }
    return isnan(e) ? INFINITY : t->weight * e;
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    const spring_data *d = t->data;
    double ge[6], He[36];
    for (int k = 0; k < d->ne; k++) {
        edge(d, k, x, EO_EVAL_HESS, proj, ge, He);
        for (int q = 0; q < 36; q++) He[q] *= t->weight;
        eo_assembler_add(s->as, d->group, k, He);
    }
    return EO_OK;
}

/* Projective-dynamics matrix of the springs (pd_matrix.c; Liu, Bouaziz & Kavan, "Fast
 * Simulation of Mass-Spring Systems", 2013): a spring is the constraint ‖x_a − x_b‖ = Lₑ,
 * k/2(‖d‖ − L)² = min_{‖p‖ = L} k/2‖d − p‖² with d = x_a − x_b, so its block of the global
 * matrix is w·kₑ·[[1, −1], [−1, 1]] ⊗ I₃ (isotropic: the same for every orientation). */
static int pd_hessian(eo_term *t, const eo_sys *s)
{
    const spring_data *d = t->data;
    double He[36];
    for (int e = 0; e < d->ne; e++) {
        const double k = t->weight * d->coef[e]->k;
        memset(He, 0, sizeof He);
        for (int i = 0; i < 3; i++) {
            He[6 * i + i] = He[6 * (i + 3) + i + 3] = k;
            He[6 * i + i + 3] = He[6 * (i + 3) + i] = -k;
        }
        eo_assembler_add(s->as, d->group, e, He);
    }
    return EO_OK;
}

/* Vertex op (term.h): the springs at v, the rows of v kept. */
static double vertex(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3)
{
    (void)s;
    const spring_data *d = t->data;
    const eo_eval_what what = H3 ? EO_EVAL_HESS : g3 ? EO_EVAL_GRAD : EO_EVAL_ENERGY;
    double e = 0, ge[6], He[36];
    for (int q = d->ve_ptr[v]; q < d->ve_ptr[v + 1]; q++) {
        const int k = d->ve_edge[q], side = d->ab[2 * k] == v ? 0 : 1;
        e += edge(d, k, x, what, proj, ge, He);
        if (g3)
            for (int c = 0; c < 3; c++) g3[c] += t->weight * ge[3 * side + c];
        if (H3)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) H3[3 * i + j] += t->weight * He[(3 * side + i) * 6 + 3 * side + j];
    }
    return isnan(e) ? INFINITY : t->weight * e;
}

int eo_term_spring_degree(const eo_term *t, int v)
{
    const spring_data *d = t->data;
    return d->ve_ptr[v + 1] - d->ve_ptr[v];
}

int eo_term_spring_other(const eo_term *t, int v, int q)
{
    const spring_data *d = t->data;
    const int k = d->ve_edge[d->ve_ptr[v] + q];
    return d->ab[2 * k] == v ? d->ab[2 * k + 1] : d->ab[2 * k];
}

static int attach(eo_term *t, eo_sys *s)
{
    spring_data *d = t->data;
    for (int k = 0; k < d->ne; k++)
        for (int i = 0; i < 2; i++)
            for (int c = 0; c < 3; c++) d->dofs[6 * k + 3 * i + c] = s->full2free[3 * d->ab[2 * k + i] + c];
    int h = eo_assembler_add_elements(s->ctx, s->as, d->ne, 6, d->dofs);
    if (h < 0) return h;
    d->group = h;
    return EO_OK;
}

static void destroy(eo_term *t, eo_ctx *ctx)
{
    spring_data *d = t->data;
    if (!d) return;
    eo_free(ctx, d->ab);
    eo_free(ctx, d->L);
    eo_free(ctx, d->type);
    eo_free(ctx, d->coef);
    eo_free(ctx, d->dofs);
    eo_free(ctx, d->list_coef);
    eo_free(ctx, d->ve_ptr);
    eo_free(ctx, d->ve_edge);
    eo_free(ctx, d);
}

static const eo_term_ops spring_ops = {
    .name = "spring",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .pd_hessian = pd_hessian,
    .attach = attach,
    .destroy = destroy,
    .vertex = vertex,
};

void eo_term_spring_damping(eo_term *t, const eo_sys *s, const double *x, const double *v, double *g)
{
    (void)s;
    const spring_data *d = t->data;
    if (!(d->damping > 0)) return;
    for (int e = d->first_scene; e < d->ne; e++) {
        const int a = d->ab[2 * e], b = d->ab[2 * e + 1];
        double n[3], l = 0, dv = 0;
        for (int c = 0; c < 3; c++) {
            n[c] = x[3 * a + c] - x[3 * b + c];
            l += n[c] * n[c];
        }
        l = sqrt(l);
        if (!(l > 0)) continue;
        for (int c = 0; c < 3; c++) dv += (v[3 * a + c] - v[3 * b + c]) * n[c] / l;
        for (int c = 0; c < 3; c++) { /* g = −f: f_a = −c dv n̂ */
            g[3 * a + c] += d->damping * dv * n[c] / l;
            g[3 * b + c] -= d->damping * dv * n[c] / l;
        }
    }
}

int eo_term_spring_create(eo_sys *s, int nlist, const int *ab, double k, const double *klist, double damping,
                          eo_term **out)
{
    static const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    *out = NULL;
    int nspring_tets = 0;
    for (int k2 = 0; k2 < s->nt; k2++)
        if (s->tet_type[k2]->flags & EO_MATERIAL_EDGE) nspring_tets++;
    if (!nspring_tets && nlist <= 0) return EO_OK;
    /* candidate edges (a < b, region tet) sorted, then unique */
    int *cand = eo_malloc(s->ctx, ((size_t)nspring_tets * 6 + 1) * 3 * sizeof(int));
    if (!cand) return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (springs)");
    int nc = 0;
    for (int t = 0; t < s->nt; t++) {
        if (!(s->tet_type[t]->flags & EO_MATERIAL_EDGE)) continue;
        const int *tet = s->mesh->tets + 4 * t;
        for (int p = 0; p < 6; p++) {
            int a = tet[pairs[p][0]], b = tet[pairs[p][1]];
            cand[3 * nc] = a < b ? a : b;
            cand[3 * nc + 1] = a < b ? b : a;
            cand[3 * nc + 2] = t;
            nc++;
        }
    }
    qsort(cand, (size_t)nc, 3 * sizeof(int), cmp_edge);
    int ne = 0;
    for (int i = 0; i < nc; i++)
        if (i == 0 || cmp_edge(cand + 3 * i, cand + 3 * (i - 1)) != 0) ne++;
    int nmat = ne;
    ne += nlist > 0 ? nlist : 0;
    int rc = eo_term_alloc(s, &spring_ops, 0, out);
    if (rc < 0) {
        eo_free(s->ctx, cand);
        return rc;
    }
    spring_data *d = eo_calloc(s->ctx, 1, sizeof *d);
    if (d) {
        d->ne = ne;
        d->ab = eo_malloc(s->ctx, (size_t)ne * 2 * sizeof(int));
        d->L = eo_malloc(s->ctx, (size_t)ne * sizeof(double));
        d->type = eo_malloc(s->ctx, (size_t)ne * sizeof *d->type);
        d->coef = eo_malloc(s->ctx, (size_t)ne * sizeof *d->coef);
        d->dofs = eo_malloc(s->ctx, (size_t)ne * 6 * sizeof(int));
        if (klist && nlist > 0) d->list_coef = eo_malloc(s->ctx, (size_t)nlist * sizeof *d->list_coef);
    }
    (*out)->data = d;
    if (!d || !d->ab || !d->L || !d->type || !d->coef || !d->dofs || (klist && nlist > 0 && !d->list_coef)) {
        eo_free(s->ctx, cand);
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (springs)");
    }
    d->first_scene = nmat;
    d->damping = damping;
    d->scene_coef = eo_material_coef_from(1, 0, 1, k);
    ne = 0;
    for (int i = 0; i < nc; i++) {
        if (i > 0 && cmp_edge(cand + 3 * i, cand + 3 * (i - 1)) == 0) continue;
        d->ab[2 * ne] = cand[3 * i];
        d->ab[2 * ne + 1] = cand[3 * i + 1];
        d->type[ne] = s->tet_type[cand[3 * i + 2]];
        d->coef[ne] = s->tet_coef[cand[3 * i + 2]];
        ne++;
    }
    eo_free(s->ctx, cand);
    for (int i = 0; i < nlist; i++, ne++) {
        d->ab[2 * ne] = ab[2 * i];
        d->ab[2 * ne + 1] = ab[2 * i + 1];
        d->type[ne] = &eo_material_spring;
        d->coef[ne] = &d->scene_coef;
        if (d->list_coef) {
            d->list_coef[i] = eo_material_coef_from(1, 0, 1, klist[i]);
            d->coef[ne] = d->list_coef + i;
        }
    }
    for (int e = 0; e < d->ne; e++) {
        double L2 = 0;
        for (int c = 0; c < 3; c++) {
            double dx = s->mesh->X[3 * d->ab[2 * e + 1] + c] - s->mesh->X[3 * d->ab[2 * e] + c];
            L2 += dx * dx;
        }
        d->L[e] = sqrt(L2);
    }
    /* vertex -> springs, for the vertex op */
    d->ve_ptr = eo_calloc(s->ctx, (size_t)s->nv + 1, sizeof(int));
    d->ve_edge = eo_malloc(s->ctx, (size_t)(2 * d->ne > 0 ? 2 * d->ne : 1) * sizeof(int));
    if (!d->ve_ptr || !d->ve_edge) {
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (springs)");
    }
    for (int q = 0; q < 2 * d->ne; q++) d->ve_ptr[d->ab[q] + 1]++;
    for (int v = 0; v < s->nv; v++) d->ve_ptr[v + 1] += d->ve_ptr[v];
    for (int e = 0; e < d->ne; e++) /* ve_ptr[v] as the cursor of v, shifted back after */
        for (int i = 0; i < 2; i++) d->ve_edge[d->ve_ptr[d->ab[2 * e + i]]++] = e;
    for (int v = s->nv; v > 0; v--) d->ve_ptr[v] = d->ve_ptr[v - 1];
    d->ve_ptr[0] = 0;
    return EO_OK;
}

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)cfg;
    *out = NULL;
    if (sc->springs.damping > 0 && !sc->integrator->explicit_step)
        return eo_error(s->ctx, EO_ERR_INVALID,
                        "springs.damping acts in explicit integrators only; %s is implicit (use damping.viscous / "
                        "damping.rayleigh_alpha / rayleigh_beta)", sc->integrator->info.name);
    return eo_term_spring_create(s, sc->nspring, sc->spring_ab, sc->springs.k, sc->spring_k, sc->springs.damping, out);
}

const eo_term_type eo_term_type_spring = {
    .info = {.name = "spring", .summary = "springs: edge-model regions (material.model = spring), `springs`, `mesh.lattice`"},
    .flags = EO_TERM_POTENTIAL | EO_TERM_ELASTIC_ENERGY | EO_TERM_NO_PART,
    .create = type_create,
};
