/* Elastic term: w · Σₜ Vₜ ψₜ(Fₜ),  Fₜ = Dₛ(x) Dₘ⁻¹  (002 §4.2–4.3, ERRATA eq. 28).
 *
 * Energies are reported relative to the rest state, Vₜ(ψ(Fₜ) − ψ(I)): some models
 * (stable Neo-Hookean) have ψ(I) ≠ 0, and a constant of 10⁴ in g would leave the line
 * search's Armijo test comparing differences below its rounding error.
 * Per tet the material kernel eo_tet_evaluate gives Vψ, its 12-gradient and 12×12
 * Hessian (projected per element as asked: none, clamp, abs; with s->proj_of set, by
 * the objective op hessian_masked, tet k is projected with proj_of[k]). Tets of an edge
 * (spring) material are skipped here; the spring term handles them.
 *
 * Element loops run in blocks of s->block tets: element values are computed (in
 * parallel with OpenMP when s->parallel) into preallocated per-element buffers, then
 * scattered serially into the gradient / assembler, so results do not depend on the
 * thread count and no allocation or atomic is needed. The energy is a plain reduction.
 * Serial Hessian assembly (the default) is one pass: each tet's 12×12 matrix goes from
 * the kernel's output straight into the CSC (eo_assembler_add_scaled, 3×3 blocks),
 * without the element buffer. With a part set (eo_sys.part_tets) the loops run over the
 * part's tets only. */
#include <math.h>
#include <string.h>

#include "pd_matrix.h"
#include "elastopt/step.h"
#include "term.h"

/* The i-th tet of a loop: its mesh id k, its element (e in assembler group `group`) and
 * its data; in the visit order (eo_sys.tet_order, no part) from the copies in that order,
 * so that the loop streams them (term.h). */
typedef struct tref {
    int k, e, group;
    const int *tet;
    const double *Dminv;
    double vol, psi;
    const eo_material_type *type;
    const eo_material_coef *coef;
} tref;

static inline tref tet_ref(const eo_sys *s, int i)
{
    if (s->tet_order && !s->part_tets) {
        const int og = s->ord_group;
        return (tref){s->tet_order[i], og >= 0 ? i : s->tet_order[i], og >= 0 ? og : s->tet_group, s->ord_tets + 4 * i,
                      s->ord_Dminv + 9 * i, s->ord_vol[i], s->ord_psi[i], s->ord_type[i], s->ord_coef[i]};
    }
    const int k = eo_sys_tet(s, i);
    return (tref){k, k, s->tet_group, s->mesh->tets + 4 * k, s->Dminv + 9 * k, s->vol[k], s->psi_rest[k],
                  s->tet_type[k], s->tet_coef[k]};
}

static int skip(const tref *t) { return (t->type->flags & EO_MATERIAL_EDGE) != 0; }

/* the material kernel on tet t at positions x (one place for gather + evaluate); the
 * Hessian loops take the Hessian alone (eo_tet_hessian: no gradient, out->grad unset) */
static void eval_tet(const tref *t, const double *x, eo_eval_what what, eo_proj proj, eo_tet_out *out)
{
    double x12[12];
    eo_gather12(x, t->tet, x12);
    if (what == EO_EVAL_HESS)
        eo_tet_hessian(t->type, t->coef, t->Dminv, t->vol, x12, proj, out);
    else
        eo_tet_evaluate(t->type, t->coef, t->Dminv, t->vol, x12, what, proj, out);
}


/* The term's data: the inverted count of the last gradient evaluation. */
typedef struct elastic_data {
    int inverted;
    eo_anp *anp;    /* the nodal volumetric part (EO_ELEMENT_NODAL_DILATATION), else NULL */
} elastic_data;

/* ---- elements other than the linear tet (element.h): the element's quadrature through
 * eo_element_evaluate, the tets in mesh (or part) order, nodes s->enodes. The same
 * block structure as above: element values in parallel into the buffers, scattered
 * serially. */

static inline const int *enodes_of(const eo_sys *s, int k) { return s->enodes + (size_t)s->npe * k; }

static void gather_nodes(const eo_sys *s, const double *x, int k, double *xe)
{
    const int *en = enodes_of(s, k);
    for (int a = 0; a < s->npe; a++)
        for (int c = 0; c < 3; c++) xe[3 * a + c] = x[3 * en[a] + c];
}

static double energy_el(eo_term *t, const eo_sys *s, const double *x)
{
    double e = 0;
    const int nt = eo_sys_ntets(s);
#if defined(_OPENMP)
#pragma omp parallel for reduction(+ : e) schedule(static) if (s->parallel)
#endif
    for (int i = 0; i < nt; i++) {
        const int k = eo_sys_tet(s, i);
        if (s->tet_type[k]->flags & EO_MATERIAL_EDGE) continue;
        double xe[3 * EO_ELEMENT_MAX_NODES], ek;
        gather_nodes(s, x, k, xe);
        eo_element_evaluate(s->el, s->tet_type[k], s->tet_coef[k], s->Dminv + 9 * k, s->vol[k], xe, EO_EVAL_ENERGY,
                            EO_PROJ_NONE, &ek, NULL, NULL, NULL);
        e += ek - s->vol[k] * s->psi_rest[k];
    }
    const elastic_data *d = t->data;
    if (d->anp) e += eo_anp_energy(d->anp, s, x);
    if (isnan(e)) e = INFINITY;
    return t->weight * e;
}

static double gradient_el(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    double e = 0;
    const double w = t->weight;
    const int nt = eo_sys_ntets(s), ne = 3 * s->npe;
    int inv = 0;
    for (int b0 = 0; b0 < nt; b0 += s->block) {
        int nb = nt - b0 < s->block ? nt - b0 : s->block;
        double eb = 0;
        int ib = 0;
#if defined(_OPENMP)
#pragma omp parallel for reduction(+ : eb, ib) schedule(static) if (s->parallel)
#endif
        for (int j = 0; j < nb; j++) {
            const int k = eo_sys_tet(s, b0 + j);
            if (s->tet_type[k]->flags & EO_MATERIAL_EDGE) continue;
            double xe[3 * EO_ELEMENT_MAX_NODES], ek, minJ;
            gather_nodes(s, x, k, xe);
            eo_element_evaluate(s->el, s->tet_type[k], s->tet_coef[k], s->Dminv + 9 * k, s->vol[k], xe,
                                EO_EVAL_GRAD, EO_PROJ_NONE, &ek, s->elem_g + (size_t)ne * j, NULL, &minJ);
            eb += ek - s->vol[k] * s->psi_rest[k];
            ib += eo_tet_is_inverted(minJ);
        }
        e += eb;
        inv += ib;
        for (int j = 0; j < nb; j++) {
            const int k = eo_sys_tet(s, b0 + j);
            if (s->tet_type[k]->flags & EO_MATERIAL_EDGE) continue;
            const int *en = enodes_of(s, k);
            const double *ge = s->elem_g + (size_t)ne * j;
            for (int a = 0; a < s->npe; a++)
                for (int c = 0; c < 3; c++) g[3 * en[a] + c] += w * ge[3 * a + c];
        }
    }
    elastic_data *d = t->data;
    d->inverted = inv;
    if (d->anp) e += eo_anp_gradient(d->anp, s, x, w, g);
    return isfinite(e) ? w * e : INFINITY;
}

static int hessian_el(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    const double w = t->weight;
    const int nt = eo_sys_ntets(s), ne = 3 * s->npe;
    for (int b0 = 0; b0 < nt; b0 += s->block) {
        int nb = nt - b0 < s->block ? nt - b0 : s->block;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (s->parallel)
#endif
        for (int j = 0; j < nb; j++) {
            const int k = eo_sys_tet(s, b0 + j);
            if (s->tet_type[k]->flags & EO_MATERIAL_EDGE) continue;
            double xe[3 * EO_ELEMENT_MAX_NODES], ek;
            gather_nodes(s, x, k, xe);
            eo_element_evaluate(s->el, s->tet_type[k], s->tet_coef[k], s->Dminv + 9 * k, s->vol[k], xe,
                                EO_EVAL_HESS, s->proj_of ? (eo_proj)s->proj_of[k] : proj, &ek, NULL,
                                s->elem_H + (size_t)ne * ne * j, NULL);
        }
        for (int j = 0; j < nb; j++) {
            const int k = eo_sys_tet(s, b0 + j);
            if (s->tet_type[k]->flags & EO_MATERIAL_EDGE) continue;
            eo_assembler_add_scaled(s->as, s->tet_group, k, s->elem_H + (size_t)ne * ne * j, w);
        }
    }
    const elastic_data *d = t->data;
    return d->anp ? eo_anp_hessian(d->anp, s, x, proj, w) : EO_OK;
}

/* Projective-dynamics matrix of a general element: w Σₜ Vₜ kₜ Σ_q w_q G_qᵀG_q ⊗ I₃, G_q the
 * shape gradients at the energy quadrature points (the linear tet's pd_hessian below for
 * one point). */
static int pd_hessian_el(eo_term *t, const eo_sys *s)
{
    const int n = s->npe, ne = 3 * n;
    double *Ke = s->elem_H; /* one element's worth of the buffer (serial) */
    for (int e = 0; e < s->nt; e++) {
        if (s->tet_type[e]->flags & EO_MATERIAL_EDGE) continue;
        const double scale = t->weight * s->vol[e] * eo_pd_tet_weight(s->tet_type[e], s->tet_coef[e]);
        memset(Ke, 0, (size_t)ne * ne * sizeof(double));
        for (int q = 0; q < s->el->nq; q++) {
            double G[3 * EO_ELEMENT_MAX_NODES];
            eo_element_grad(s->el, s->Dminv + 9 * e, s->el->qp + 4 * q, G);
            for (int a = 0; a < n; a++)
                for (int b = 0; b < n; b++) {
                    const double d = scale * s->el->qw[q] *
                                     (G[3 * a] * G[3 * b] + G[3 * a + 1] * G[3 * b + 1] + G[3 * a + 2] * G[3 * b + 2]);
                    for (int r = 0; r < 3; r++) Ke[(size_t)(3 * a + r) * ne + 3 * b + r] += d;
                }
        }
        eo_assembler_add(s->as, s->tet_group, e, Ke);
    }
    return EO_OK;
}

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    if (!s->linear) return energy_el(t, s, x);
    double e = 0;
    const int nt = eo_sys_ntets(s);
#if defined(_OPENMP)
#pragma omp parallel for reduction(+ : e) schedule(static) if (s->parallel)
#endif
    for (int i = 0; i < nt; i++) {
        const tref r = tet_ref(s, i);
        if (skip(&r)) continue;
        eo_tet_out out;
        eval_tet(&r, x, EO_EVAL_ENERGY, EO_PROJ_NONE, &out);
        e += out.energy - r.vol * r.psi;
    }
    if (isnan(e)) e = INFINITY;
    return t->weight * e;
}


static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    if (!s->linear) return gradient_el(t, s, x, g);
    double e = 0;
    const double w = t->weight;
    const int nt = eo_sys_ntets(s);
    int inv = 0;
    for (int b0 = 0; b0 < nt; b0 += s->block) {
        int nb = nt - b0 < s->block ? nt - b0 : s->block;
        double eb = 0;
        int ib = 0;
#if defined(_OPENMP)
#pragma omp parallel for reduction(+ : eb, ib) schedule(static) if (s->parallel)
#endif
        for (int j = 0; j < nb; j++) {
            const tref r = tet_ref(s, b0 + j);
            if (skip(&r)) { /* an edge material: counted, not evaluated */
                double x12[12];
                eo_gather12(x, r.tet, x12);
                ib += eo_tet_is_inverted(eo_tet_J(r.Dminv, x12));
                continue;
            }
            eo_tet_out out;
            eval_tet(&r, x, EO_EVAL_GRAD, EO_PROJ_NONE, &out);
            eb += out.energy - r.vol * r.psi;
            ib += eo_tet_is_inverted(out.J);
            memcpy(s->elem_g + 12 * j, out.grad, sizeof out.grad);
        }
        e += eb; /* a non-finite e is returned after all forces are scattered */
        inv += ib;
        for (int j = 0; j < nb; j++) {
            const tref r = tet_ref(s, b0 + j);
            if (skip(&r)) continue;
            const int *tet = r.tet;
            const double *ge = s->elem_g + 12 * j;
            for (int a = 0; a < 4; a++)
                for (int c = 0; c < 3; c++) g[3 * tet[a] + c] += w * ge[3 * a + c];
        }
    }
    ((elastic_data *)t->data)->inverted = inv;
    return isfinite(e) ? w * e : INFINITY;
}

int eo_term_elastic_inverted(const eo_term *t) { return ((const elastic_data *)t->data)->inverted; }

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    if (!s->linear) return hessian_el(t, s, x, proj);
    const double w = t->weight;
    const int nt = eo_sys_ntets(s);
    if (!s->parallel) { /* one pass: evaluate and scatter each tet, no element buffer */
        for (int i = 0; i < nt; i++) {
            const tref r = tet_ref(s, i);
            if (skip(&r)) continue;
            eo_tet_out out;
            eval_tet(&r, x, EO_EVAL_HESS, s->proj_of ? (eo_proj)s->proj_of[r.k] : proj, &out);
            eo_assembler_add_scaled(s->as, r.group, r.e, out.hess, w);
        }
        return EO_OK;
    }
    for (int b0 = 0; b0 < nt; b0 += s->block) {
        int nb = nt - b0 < s->block ? nt - b0 : s->block;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (s->parallel)
#endif
        for (int j = 0; j < nb; j++) {
            const tref r = tet_ref(s, b0 + j);
            if (skip(&r)) continue;
            eo_tet_out out;
            eval_tet(&r, x, EO_EVAL_HESS, s->proj_of ? (eo_proj)s->proj_of[r.k] : proj, &out);
            double *He = s->elem_H + 144 * j;
            for (int q = 0; q < 144; q++) He[q] = w * out.hess[q];
        }
        for (int j = 0; j < nb; j++) {
            const tref r = tet_ref(s, b0 + j);
            if (skip(&r)) continue;
            eo_assembler_add(s->as, r.group, r.e, s->elem_H + 144 * j);
        }
    }
    return EO_OK;
}

/* Projective-dynamics matrix of the tets (pd_matrix.c): w · Σₜ Vₜ kₜ GₜᵀGₜ with
 * Gₜ = ∂vec(F)/∂x = Bₜ ⊗ I₃, so GₜᵀGₜ = (BₜᵀBₜ) ⊗ I₃, where the columns of the 3×4 Bₜ are
 * bₐ = row a of Dm⁻¹ (a = 0, 1, 2) and b₃ = −(b₀ + b₁ + b₂) (F = Ds Dm⁻¹, Ds columns
 * xₐ − x₃), and kₜ = eo_pd_tet_weight of the tet's material. */
static int pd_hessian(eo_term *t, const eo_sys *s)
{
    if (!s->linear) return pd_hessian_el(t, s);
    double Ke[144];
    const eo_material_type *last_type = NULL;
    const eo_material_coef *last_coef = NULL;
    double k = 0;
    for (int e = 0; e < s->nt; e++) {
        if (s->tet_type[e]->flags & EO_MATERIAL_EDGE) continue;
        if (s->tet_type[e] != last_type || s->tet_coef[e] != last_coef) {
            last_type = s->tet_type[e];
            last_coef = s->tet_coef[e];
            k = eo_pd_tet_weight(last_type, last_coef);
        }
        const double *Dm = s->Dminv + 9 * e;
        double b[4][3];
        for (int c = 0; c < 3; c++) {
            b[3][c] = 0;
            for (int a = 0; a < 3; a++) {
                b[a][c] = Dm[3 * a + c];
                b[3][c] -= Dm[3 * a + c];
            }
        }
        const double scale = t->weight * s->vol[e] * k;
        memset(Ke, 0, sizeof Ke);
        for (int a = 0; a < 4; a++)
            for (int bb = 0; bb < 4; bb++) {
                double d = scale * (b[a][0] * b[bb][0] + b[a][1] * b[bb][1] + b[a][2] * b[bb][2]);
                for (int r = 0; r < 3; r++) Ke[(3 * a + r) * 12 + 3 * bb + r] = d;
            }
        eo_assembler_add(s->as, s->tet_group, e, Ke);
    }
    return EO_OK;
}

/* Vertex op (term.h): the tets around v, each evaluated whole (the 12×12 projected as
 * asked), of which the rows of v are kept. */
static double vertex(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3)
{
    const double w = t->weight;
    const eo_eval_what what = H3 ? EO_EVAL_HESS : g3 ? EO_EVAL_GRAD : EO_EVAL_ENERGY;
    double e = 0;
    for (int q = s->vt_ptr[v]; q < s->vt_ptr[v + 1]; q++) {
        const int k = s->vt_tet[q];
        const tref r = {k, k, s->tet_group, s->mesh->tets + 4 * k, s->Dminv + 9 * k, s->vol[k], s->psi_rest[k],
                        s->tet_type[k], s->tet_coef[k]};
        if (skip(&r)) continue;
        int a = 0;
        while (a < 3 && r.tet[a] != v) a++;
        eo_tet_out out;
        double x12[12];
        eo_gather12(x, r.tet, x12);
        eo_tet_evaluate(r.type, r.coef, r.Dminv, r.vol, x12, what, proj, &out);
        e += out.energy - r.vol * r.psi;
        if (g3)
            for (int c = 0; c < 3; c++) g3[c] += w * out.grad[3 * a + c];
        if (H3)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) H3[3 * i + j] += w * out.hess[(3 * a + i) * 12 + 3 * a + j];
    }
    return isfinite(e) ? w * e : INFINITY;
}

static void destroy(eo_term *t, eo_ctx *ctx)
{
    elastic_data *d = t->data;
    if (d) eo_anp_destroy(&d->anp, ctx);
    eo_free(ctx, t->data);
    t->data = NULL;
}

static int attach(eo_term *t, eo_sys *s)
{
    elastic_data *d = t->data;
    return d->anp ? eo_anp_attach(d->anp, s) : EO_OK;
}

static const eo_term_ops elastic_ops = {
    .name = "elastic",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .destroy = destroy,
    .attach = attach,
    .pd_hessian = pd_hessian,
    .vertex = vertex,
};

int eo_term_elastic_create(eo_sys *s, eo_term **out)
{
    int rc = eo_term_alloc(s, &elastic_ops, 0, out);
    if (rc < 0) return rc;
    elastic_data *d = eo_calloc(s->ctx, 1, sizeof(elastic_data));
    if (!((*out)->data = d)) {
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (term elastic)");
    }
    if (s->el && (s->el->flags & EO_ELEMENT_NODAL_DILATATION) && (rc = eo_anp_create(s, &d->anp)) < 0) {
        eo_term_destroy(s->ctx, out);
        return rc;
    }
    return EO_OK;
}

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)sc, (void)cfg;
    *out = NULL;
    int any_tet = 0;
    for (int k = 0; k < s->nt; k++) any_tet |= !(s->tet_type[k]->flags & EO_MATERIAL_EDGE);
    return any_tet ? eo_term_elastic_create(s, out) : EO_OK;
}

const eo_term_type eo_term_type_elastic = {
    .info = {.name = "elastic", .summary = "elastic energy Σ V(ψ(F) − ψ(I)) of the tet materials (`material`, `materials`) with the scene's `element`"},
    .flags = EO_TERM_POTENTIAL | EO_TERM_ELASTIC_ENERGY,
    .create = type_create,
};
