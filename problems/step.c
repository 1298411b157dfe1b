/* The step objective: one implicit time step of a scene as min over the FREE
 * coordinates of
 *
 *     g(x) = ½‖x − x̃‖²_M + w·(E_el(x) − f_gᵀx − cᵀx) [+ springs]
 *
 * (see step.h for w, x̃, c per integrator). Constrained vertices are eliminated: a map
 * full → free (−1 for constrained coordinates); before every evaluation the free values
 * are scattered into a full work vector whose constrained entries already hold their
 * prescribed positions at tₙ₊₁, the terms (term.h) evaluate on the full vector, and the
 * gradient is gathered back to the free coordinates. The Hessian pattern over the free
 * coordinates is built once per set of constrained vertices with the fixed-pattern
 * assembler (each tet registered with its 12 free ids, −1 where constrained); assembly
 * scatters through the precomputed maps with no search, sort or allocation.
 *
 * Boundary conditions (scene.h): at time t a vertex follows the last active entry of
 * the boundary list that selects it (an entry is active until its `release` time);
 * prescribed position p(t) = motion(x₀, min(t, until)) with x₀ the initial position,
 * prescribed velocity dp/dt (0 after `until`). When a release changes the constrained
 * set, the free map and the pattern are rebuilt (once per release).
 *
 * This file: create / destroy, accessors, the parallel switch; the other jobs are in
 * step_bc.c, step_objective.c, step_initial.c, step_explicit.c, step_stats.c (see
 * step_impl.h). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include "elastopt/registry.h"
#include "step_impl.h"

/* ---------------------------------------------------------------- create / destroy */

static int add_term(eo_step *st, const eo_term_type *tt, eo_term *t)
{
    if (!t) return EO_OK;
    if (st->nterms == MAX_TERMS) {
        eo_term_destroy(st->ctx, &t);
        return eo_error(st->ctx, EO_ERR_INVALID, "term %s: more than %d terms in one step problem", tt->info.name,
                        MAX_TERMS);
    }
    t->type = tt;
    t->flags = tt->flags;
    st->terms[st->nterms++] = t;
    st->term_flags |= tt->flags;
    if (tt->flags & EO_TERM_INERTIA) st->inertia = t;
    if (tt->flags & EO_TERM_FORCE_N) st->linear = t;
    if (tt->flags & EO_TERM_DAMPING) st->damping = t;
    if (tt->flags & EO_TERM_LAGGED) st->friction = t;
    if (tt == &eo_term_type_elastic) st->elastic = t;
    if (tt == &eo_term_type_spring) st->spring = t;
    return EO_OK;
}

void eo_step_destroy(eo_step **pst)
{
    if (!pst || !*pst) return;
    eo_step *st = *pst;
    eo_ctx *ctx = st->ctx;
    for (int i = 0; i < st->nterms; i++) eo_term_destroy(ctx, &st->terms[i]);
    eo_assembler_destroy(&st->as);
    eo_pd_matrix_deinit(ctx, &st->pd);
    eo_stepi_pd_deinit(st);
    eo_linsolve_destroy(&st->mls);
    eo_csc_destroy(&st->Mc);
    eo_free(ctx, st->ework);
    eo_free(ctx, st->xe);
    eo_free(ctx, st->ve);
    eo_free(ctx, st->xp);
    eo_csc_destroy(&st->Mi);
    eo_free(ctx, st->fin);
    eo_free(ctx, st->vp);
    eo_free(ctx, st->rpot);
    eo_free(ctx, st->rpot1);
    eo_free(ctx, st->an);
    eo_free(ctx, st->anew);
    void *arrays[] = {st->vload, st->Dminv, st->psi_rest, st->vol, st->rho, st->vmass, (void *)st->tet_type, (void *)st->tet_coef,
                      st->x, st->v, st->x0, st->xw, st->gfull, st->vnew, st->guess, st->inv_x, st->rs_a, st->split_k, st->vbc,
                      st->vbc_new, st->full2free, st->free2full, st->tet_dofs, st->tet_order, st->ord_tets, st->ord_dofs,
                      st->ord_Dminv, st->ord_vol, st->ord_psi, st->ord_rho, (void *)st->ord_type, (void *)st->ord_coef, st->sys.elem_g,
                      st->sys.elem_H, st->vt_ptr, st->vt_tet, st->vb_vert, st->vb_dofs, st->vb_ptr, st->vb_adj,
                      st->vb_mark};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++) eo_free(ctx, arrays[i]);
    eo_free(ctx, st);
    *pst = NULL;
}

/* Morton (Z-curve) code of a point quantized to 21 bits per axis in the box [lo, lo + ext] */
static uint64_t spread21(uint64_t v)
{
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

typedef struct morton_key {
    uint64_t code;
    int k;
} morton_key;

static int cmp_morton(const void *a, const void *b)
{
    const morton_key *p = a, *q = b;
    if (p->code != q->code) return p->code < q->code ? -1 : 1;
    return (p->k > q->k) - (p->k < q->k);
}

/* order[0..nt): the tets sorted by the Morton code of their rest centroids (ties by id):
 * the element loops' visit order (eo_sys.tet_order). Setup only (allocates a key array). */
static int morton_order(eo_ctx *ctx, const eo_mesh *m, int *order)
{
    if (m->nt <= 0) return EO_OK;
    morton_key *key = eo_malloc(ctx, (size_t)m->nt * sizeof *key);
    if (!key) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (tet order of %d tets)", m->nt);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < m->nv; v++)
        for (int c = 0; c < 3; c++) lo[c] = fmin(lo[c], m->X[3 * v + c]), hi[c] = fmax(hi[c], m->X[3 * v + c]);
    double ext = 0;
    for (int c = 0; c < 3; c++) ext = fmax(ext, hi[c] - lo[c]);
    const double scale = ext > 0 && isfinite(ext) ? 2097151.0 / ext : 0;
    for (int k = 0; k < m->nt; k++) {
        uint64_t code = 0;
        for (int c = 0; c < 3; c++) {
            const int *t = m->tets + 4 * k;
            double ctr = (m->X[3 * t[0] + c] + m->X[3 * t[1] + c] + m->X[3 * t[2] + c] + m->X[3 * t[3] + c]) / 4;
            double q = (ctr - lo[c]) * scale;
            uint64_t iq = q > 0 ? (q < 2097151.0 ? (uint64_t)q : 2097151u) : 0;
            code |= spread21(iq) << c;
        }
        key[k] = (morton_key){code, k};
    }
    qsort(key, (size_t)m->nt, sizeof *key, cmp_morton);
    for (int k = 0; k < m->nt; k++) order[k] = key[k].k;
    eo_free(ctx, key);
    return EO_OK;
}

int eo_step_create(eo_ctx *ctx, const eo_scene *sc, eo_step **out)
{
    *out = NULL;
    int rc = EO_OK;
    eo_step *st = eo_calloc(ctx, 1, sizeof *st);
    if (!st) return eo_error(ctx, EO_ERR_NOMEM, "out of memory (step)");
    const eo_mesh *m = sc->mesh;
    st->ctx = ctx;
    st->sc = sc;
    st->integ = sc->integrator;
    st->nv = m->nv;
    st->nt = m->nt;
    st->n_full = 3 * m->nv;
    st->h = st->h_nom = sc->time.dt;
    /* (at least 1: a mesh.points scene has no tets) */
    size_t nv = (size_t)(m->nv > 0 ? m->nv : 1), nt = (size_t)(m->nt > 0 ? m->nt : 1), nf = 3 * nv;
    st->Dminv = eo_malloc(ctx, 9 * nt * sizeof(double));
    st->vol = eo_malloc(ctx, nt * sizeof(double));
    st->psi_rest = eo_calloc(ctx, nt, sizeof(double));
    st->rho = eo_malloc(ctx, nt * sizeof(double));
    st->vmass = eo_calloc(ctx, nv, sizeof(double));
    st->tet_type = eo_malloc(ctx, nt * sizeof *st->tet_type);
    st->tet_coef = eo_malloc(ctx, nt * sizeof *st->tet_coef);
    st->x = eo_malloc(ctx, nf * sizeof(double));
    st->v = eo_malloc(ctx, nf * sizeof(double));
    st->x0 = eo_malloc(ctx, nf * sizeof(double));
    st->xw = eo_malloc(ctx, nf * sizeof(double));
    st->gfull = eo_malloc(ctx, nf * sizeof(double));
    st->vnew = eo_malloc(ctx, nf * sizeof(double));
    st->guess = eo_malloc(ctx, nf * sizeof(double));
    st->inv_x = eo_malloc(ctx, nf * sizeof(double));
    st->vbc = eo_malloc(ctx, nv * sizeof(int));
    st->vbc_new = eo_malloc(ctx, nv * sizeof(int));
    st->full2free = eo_malloc(ctx, nf * sizeof(int));
    st->free2full = eo_malloc(ctx, nf * sizeof(int));
    const eo_element_type *el = sc->element ? sc->element : &eo_element_p1;
    const int npe = el->nodes, linear = (el->flags & EO_ELEMENT_LINEAR) != 0;
    st->tet_dofs = eo_malloc(ctx, 3 * (size_t)npe * nt * sizeof(int));
    st->tet_order = eo_malloc(ctx, nt * sizeof(int));
    st->ord_tets = eo_malloc(ctx, 4 * nt * sizeof(int));
    st->ord_dofs = eo_malloc(ctx, 12 * nt * sizeof(int));
    st->ord_Dminv = eo_malloc(ctx, 9 * nt * sizeof(double));
    st->ord_vol = eo_malloc(ctx, nt * sizeof(double));
    st->ord_psi = eo_malloc(ctx, nt * sizeof(double));
    st->ord_rho = eo_malloc(ctx, nt * sizeof(double));
    st->ord_type = eo_malloc(ctx, nt * sizeof *st->ord_type);
    st->ord_coef = eo_malloc(ctx, nt * sizeof *st->ord_coef);
    st->sys.block = BLOCK;
    st->pd_mode = EO_PD_FACTOR_AUTO;
    st->sys.elem_g = eo_malloc(ctx, 3 * (size_t)npe * BLOCK * sizeof(double));
    st->sys.elem_H = eo_malloc(ctx, 9 * (size_t)npe * npe * BLOCK * sizeof(double));
    if (!linear) st->vload = eo_calloc(ctx, nv, sizeof(double));
    if (!st->Dminv || !st->psi_rest || !st->vol || !st->rho || !st->vmass || !st->tet_type || !st->tet_coef || !st->x ||
        !st->v || !st->x0 || !st->xw || !st->gfull || !st->vnew || !st->guess || !st->inv_x || !st->vbc ||
        !st->vbc_new || !st->full2free || !st->free2full || !st->tet_dofs || !st->tet_order || !st->ord_tets ||
        !st->ord_dofs || !st->ord_Dminv || !st->ord_vol || !st->ord_psi || !st->ord_rho || !st->ord_type || !st->ord_coef || !st->sys.elem_g ||
        !st->sys.elem_H || (!linear && !st->vload)) {
        rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (step of %d tets)", m->nt);
        goto fail;
    }
    for (int k = 0; k < m->nt; k++) {
        double X12[12];
        eo_gather12(m->X, m->tets + 4 * k, X12);
        rc = eo_tet_rest(X12, st->Dminv + 9 * k, &st->vol[k]);
        if (rc < 0) {
            rc = eo_error_at(ctx, EO_ERR_MESH, EO_ERRLOC_ITEM(sc->mesh_opts.file[0] ? sc->mesh_opts.file : NULL, -1, "tet", k),
                             "degenerate rest tet (volume %g)", eo_tet_volume(m->X, m->tets + 4 * k));
            goto fail;
        }
        const eo_scene_material *mat = sc->mat + sc->tet_mat[k];
        st->tet_type[k] = mat->type;
        st->tet_coef[k] = &mat->coef;
        st->rho[k] = mat->coef.density;
        if (!(mat->type->flags & EO_MATERIAL_EDGE)) {
            static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            eo_material_eval ev;
            eo_material_evaluate(mat->type, &mat->coef, I3, EO_EVAL_ENERGY, EO_PROJ_NONE, &ev);
            st->psi_rest[k] = ev.psi;
            if (!linear) { /* the element's own energy density at rest (mixed elements split ψ) */
                const int *en = (npe == 10 ? m->tet10 : m->tets) + (size_t)npe * k;
                double Xe[3 * EO_ELEMENT_MAX_NODES], e0;
                for (int a = 0; a < npe; a++)
                    for (int c = 0; c < 3; c++) Xe[3 * a + c] = m->X[3 * en[a] + c];
                eo_element_evaluate(el, mat->type, &mat->coef, st->Dminv + 9 * k, st->vol[k], Xe, EO_EVAL_ENERGY,
                                    EO_PROJ_NONE, &e0, NULL, NULL, NULL);
                st->psi_rest[k] = e0 / st->vol[k];
            }
        }
        if (linear) {
            for (int a = 0; a < 4; a++) st->vmass[m->tets[4 * k + a]] += st->rho[k] * st->vol[k] / 4.0;
            continue;
        }
        const int *en = (npe == 10 ? m->tet10 : m->tets) + (size_t)npe * k;
        for (int a = 0; a < npe; a++) {
            st->vmass[en[a]] += st->rho[k] * st->vol[k] * el->lumped[a];
            st->vload[en[a]] += st->rho[k] * st->vol[k] * el->load[a];
        }
    }
    if (sc->pmass)
        for (int v = 0; v < m->nv; v++) {
            st->vmass[v] += sc->pmass[v];
            if (st->vload) st->vload[v] += sc->pmass[v];
        }
    /* shared data for the terms */
    eo_sys *s = &st->sys;
    s->ctx = ctx;
    s->mesh = m;
    s->nv = st->nv;
    s->nt = st->nt;
    s->n_full = st->n_full;
    {
        const eo_dist_hooks *dh = eo_ctx_dist(ctx);
        s->vonce = dh && dh->owned_vertices ? dh->owned_vertices(dh->user) : NULL;
    }
    s->Dminv = st->Dminv;
    s->vol = st->vol;
    s->rho = st->rho;
    s->psi_rest = st->psi_rest;
    s->tet_type = st->tet_type;
    s->tet_coef = st->tet_coef;
    s->vmass = st->vmass;
    s->vload = st->vload && !sc->lumped ? st->vload : st->vmass; /* f = M g with the scene's mass */
    s->el = el;
    s->npe = npe;
    s->linear = linear;
    s->enodes = npe == 10 ? m->tet10 : m->tets;
    s->pmass = sc->pmass;
    s->full2free = st->full2free;
    s->tet_dofs = st->tet_dofs;
    s->parallel = 0; /* serial by default: see eo_step_set_parallel */
    if (morton_order(ctx, m, st->tet_order) < 0) {
        rc = EO_ERR_NOMEM;
        goto fail;
    }
    for (int i = 0; i < m->nt; i++) {
        const int k = st->tet_order[i];
        memcpy(st->ord_tets + 4 * i, m->tets + 4 * k, 4 * sizeof(int));
        memcpy(st->ord_Dminv + 9 * i, st->Dminv + 9 * k, 9 * sizeof(double));
        st->ord_vol[i] = st->vol[k];
        st->ord_psi[i] = st->psi_rest[k];
        st->ord_rho[i] = st->rho[k];
        st->ord_type[i] = st->tet_type[k];
        st->ord_coef[i] = st->tet_coef[k];
    }
    s->ord_tets = st->ord_tets;
    s->ord_Dminv = st->ord_Dminv;
    s->ord_vol = st->ord_vol;
    s->ord_psi = st->ord_psi;
    s->ord_rho = st->ord_rho;
    s->ord_type = st->ord_type;
    s->ord_coef = st->ord_coef;
    s->ord_group = -1;
    s->tet_order = m->nt > 1 && linear ? st->tet_order : NULL;
    /* the term list: one term per registered kind the scene uses (a scene pays only for
     * those), in registry order */
    for (const void *const *tp = eo_registry_list(EO_KIND_TERM); tp && *tp; tp++) {
        const eo_term_type *tt = *tp;
        eo_term *t = NULL;
        EO_TRY(rc = tt->create(s, sc, eo_scene_term_cfg(sc, tt), &t));
        EO_TRY(rc = add_term(st, tt, t));
    }
    if (st->integ->explicit_step) {
        st->ework = eo_calloc(ctx, (size_t)(st->integ->work_vectors > 0 ? st->integ->work_vectors : 1) * nf,
                              sizeof(double));
        st->xe = eo_malloc(ctx, nf * sizeof(double));
        st->ve = eo_malloc(ctx, nf * sizeof(double));
        if (!st->ework || !st->xe || !st->ve) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (explicit integrator work)");
            goto fail;
        }
    }
    if (st->integ->accel) {
        st->an = eo_calloc(ctx, nf, sizeof(double));
        st->anew = eo_calloc(ctx, nf, sizeof(double));
        if (!st->an || !st->anew) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (integrator acceleration)");
            goto fail;
        }
    }
    if (st->integ->history) {
        st->xp = eo_calloc(ctx, nf, sizeof(double));
        st->vp = eo_calloc(ctx, nf, sizeof(double));
        if (!st->xp || !st->vp) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (integrator history)");
            goto fail;
        }
    }
    if (sc->nbc > 0) { /* the work of prescribed motions (eo_stepi_work_update) */
        st->rpot = eo_malloc(ctx, nf * sizeof(double));
        st->rpot1 = eo_malloc(ctx, nf * sizeof(double));
        if (!st->rpot || !st->rpot1) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory (boundary reactions)");
            goto fail;
        }
    }
    st->obj.ops = linear ? &eo_stepi_ops : &eo_stepi_ops_element;
    st->obj.data = st;
    st->w = eo_stepi_weight(st);
    EO_TRY(rc = eo_step_reset(st));
    *out = st;
    return EO_OK;
fail:
    eo_step_destroy(&st);
    return rc;
}


int eo_step_set_tet_order(eo_step *st, int on)
{
    st->sys.tet_order = on && st->nt > 1 && st->sys.linear ? st->tet_order : NULL;
    return st->sys.tet_order != NULL;
}

int eo_step_set_parallel(eo_step *st, int on)
{
#if defined(_OPENMP)
    st->sys.parallel = on && st->nt >= PARALLEL_MIN_TETS && omp_get_max_threads() > 1;
#else
    (void)on;
    st->sys.parallel = 0;
#endif
    return st->sys.parallel;
}


/* ---------------------------------------------------------------- accessors */

const double *eo_step_x(const eo_step *st) { return st->x; }
const double *eo_step_v(const eo_step *st) { return st->v; }
const double *eo_step_x0(const eo_step *st) { return st->x0; }
double eo_step_time(const eo_step *st) { return st->t; }
int eo_step_index(const eo_step *st) { return st->index; }
const eo_mesh *eo_step_mesh(const eo_step *st) { return st->sc->mesh; }
const double *eo_step_vertex_mass(const eo_step *st) { return st->vmass; }
int eo_step_free_to_full(const eo_step *st, int i)
{
    return i >= 0 && i < st->nfree ? st->free2full[i] : -1;
}
size_t eo_step_history_len(const eo_step *st)
{
    return st->integ->history ? 2 * (size_t)st->n_full + 1 : st->integ->accel ? (size_t)st->n_full + 1 : 0;
}

int eo_step_get_history(const eo_step *st, double *h)
{
    if (st->integ->accel) { /* aₙ, valid flag */
        memcpy(h, st->an, (size_t)st->n_full * sizeof(double));
        h[st->n_full] = st->hist_valid;
        return EO_OK;
    }
    if (!st->integ->history)
        return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "integrator %s keeps no history", st->integ->info.name);
    memcpy(h, st->xp, (size_t)st->n_full * sizeof(double));
    memcpy(h + st->n_full, st->vp, (size_t)st->n_full * sizeof(double));
    h[2 * st->n_full] = st->hist_valid;
    return EO_OK;
}

int eo_step_set_history(eo_step *st, const double *h)
{
    if (st->integ->accel) {
        const double valid = h[st->n_full];
        if (valid != 0 && valid != 1)
            return eo_error(st->ctx, EO_ERR_RANGE, "history: valid flag %g is neither 0 nor 1", valid);
        memcpy(st->an, h, (size_t)st->n_full * sizeof(double));
        st->hist_valid = valid == 1;
        return EO_OK;
    }
    if (!st->integ->history)
        return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "integrator %s keeps no history", st->integ->info.name);
    const double valid = h[2 * st->n_full];
    if (valid != 0 && valid != 1)
        return eo_error(st->ctx, EO_ERR_RANGE, "history: valid flag %g is neither 0 nor 1", valid);
    memcpy(st->xp, h, (size_t)st->n_full * sizeof(double));
    memcpy(st->vp, h + st->n_full, (size_t)st->n_full * sizeof(double));
    st->hist_valid = valid == 1;
    return EO_OK;
}

int eo_step_full_to_free(const eo_step *st, int j)
{
    return st->have_pattern && j >= 0 && j < st->n_full ? st->full2free[j] : -1;
}

