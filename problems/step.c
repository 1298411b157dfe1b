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
 * set, the free map and the pattern are rebuilt (once per release). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include "elastopt/linsolve.h"
#include "elastopt/step.h"
#include "pd_matrix.h"
#include "term.h"

enum { MAX_TERMS = 8, BLOCK = 1024, PARALLEL_MIN_TETS = 2048 };

struct eo_step {
    eo_ctx *ctx;
    const eo_scene *sc;
    const eo_integrator_type *integ;
    eo_sys sys;
    int nv, nt, n_full;
    double h;
    /* rest data */
    double *Dminv, *vol, *rho, *vmass;
    double *psi_rest;     /* nt: ψ(I) of each tet's material (reported energies are relative to it) */
    const eo_material_type **tet_type;
    const eo_material_coef **tet_coef;
    /* state */
    double *x, *v, *x0, t;
    int index;
    /* work */
    double *xw, *gfull, *vnew, *guess;
    /* terms */
    eo_term *terms[MAX_TERMS];
    int nterms;
    eo_term *inertia, *elastic, *gravity, *linear, *spring, *collision;
    /* constraints and pattern */
    int *vbc, *vbc_new;   /* nv: active boundary entry per vertex, -1 free */
    int have_pattern;
    int *full2free, *free2full, nfree;
    int *tet_dofs;
    eo_assembler *as;
    eo_objective obj;
    unsigned long pattern_id;   /* bumped by build_pattern */
    /* explicit integrators (eo_step_advance) */
    double *ework, *xe, *ve;    /* work_vectors·n_full; trial state */
    int erestart;               /* next explicit step restarts (leapfrog) */
    eo_linsolve *mls;           /* consistent mass: M_ff factored with CHOLMOD */
    eo_csc *Mc;                 /* its values (a copy of the pattern) */
    eo_pd_matrix pd;            /* constant_hessian cache (pd_matrix.c) */
};

/* ---------------------------------------------------------------- small math */

/* det F of tet k at positions x, computed as the material kernel computes it (eo_tet_J:
 * F = Ds Dm⁻¹, then eo_det3), so that eo_tet_is_inverted agrees with the barrier. */
static double tet_J(const eo_step *st, const double *x, int k)
{
    double x12[12];
    eo_gather12(x, st->sc->mesh->tets + 4 * k, x12);
    return eo_tet_J(st->Dminv + 9 * k, x12);
}

/* Rotate p about the axis (unit) through center by angle th (Rodrigues). */
static void rotate_point(const double axis[3], const double center[3], double th, const double p[3],
                         double out[3])
{
    double r[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
    double c = cos(th), s = sin(th);
    double kr = axis[0] * r[0] + axis[1] * r[1] + axis[2] * r[2];
    double kx[3] = {axis[1] * r[2] - axis[2] * r[1], axis[2] * r[0] - axis[0] * r[2],
                    axis[0] * r[1] - axis[1] * r[0]};
    for (int i = 0; i < 3; i++) out[i] = center[i] + r[i] * c + kx[i] * s + axis[i] * kr * (1 - c);
}

/* ---------------------------------------------------------------- boundary conditions */

static int bc_active(const eo_bc *b, double t, double h)
{
    return b->opts.release < 0 || t <= b->opts.release + 1e-9 * h;
}

static void active_set(const eo_step *st, double t, int *vbc)
{
    for (int v = 0; v < st->nv; v++) vbc[v] = -1;
    for (int b = 0; b < st->sc->nbc; b++) {
        const eo_bc *bc = st->sc->bc + b;
        if (!bc_active(bc, t, st->h)) continue;
        for (int i = 0; i < bc->nverts; i++) vbc[bc->verts[i]] = b;
    }
}

/* Prescribed position and velocity of vertex v under entry bc at time t. */
static void bc_motion(const eo_step *st, const eo_bc *bc, int v, double t, double p[3], double vel[3])
{
    const double *base = st->x0 + 3 * v;
    int moving = !(bc->opts.until >= 0 && t >= bc->opts.until);
    double tau = moving ? t : bc->opts.until;
    for (int c = 0; c < 3; c++) {
        p[c] = base[c];
        vel[c] = 0;
    }
    switch (bc->motion) {
    case EO_BC_FIXED: break;
    case EO_BC_TRANSLATE:
        for (int c = 0; c < 3; c++) {
            p[c] = base[c] + tau * bc->opts.translate[c];
            vel[c] = moving ? bc->opts.translate[c] : 0;
        }
        break;
    case EO_BC_ROTATE: {
        const eo_scene_rotate_opts *r = &bc->rotate;
        rotate_point(r->axis, r->center, r->rate * tau, base, p);
        if (moving) {
            double d[3] = {p[0] - r->center[0], p[1] - r->center[1], p[2] - r->center[2]};
            double w[3] = {r->rate * r->axis[0], r->rate * r->axis[1], r->rate * r->axis[2]};
            vel[0] = w[1] * d[2] - w[2] * d[1];
            vel[1] = w[2] * d[0] - w[0] * d[2];
            vel[2] = w[0] * d[1] - w[1] * d[0];
        }
        break;
    }
    }
}

/* ---------------------------------------------------------------- pattern */

static int build_pattern(eo_step *st)
{
    eo_ctx *ctx = st->ctx;
    int nfree = 0;
    for (int j = 0; j < st->n_full; j++) {
        if (st->vbc[j / 3] >= 0) {
            st->full2free[j] = -1;
        } else {
            st->free2full[nfree] = j;
            st->full2free[j] = nfree++;
        }
    }
    st->nfree = nfree;
    const int *tets = st->sc->mesh->tets;
    for (int k = 0; k < st->nt; k++)
        for (int a = 0; a < 4; a++)
            for (int c = 0; c < 3; c++) st->tet_dofs[12 * k + 3 * a + c] = st->full2free[3 * tets[4 * k + a] + c];
    eo_assembler_destroy(ctx, &st->as);
    st->sys.as = NULL;
    int rc = eo_assembler_create(ctx, nfree, &st->as);
    if (rc < 0) return rc;
    st->sys.as = st->as;
    int hgroup = eo_assembler_add_elements(ctx, st->as, st->nt, 12, st->tet_dofs);
    if (hgroup < 0) return hgroup;
    st->sys.tet_group = hgroup;
    for (int i = 0; i < st->nterms; i++)
        if (st->terms[i]->ops->attach) {
            rc = st->terms[i]->ops->attach(st->terms[i], &st->sys);
            if (rc < 0) return rc;
        }
    rc = eo_assembler_finalize(ctx, st->as);
    if (rc < 0) return rc;
    for (int i = 0; i < st->nterms; i++)
        if (st->terms[i]->ops->prepare) {
            rc = st->terms[i]->ops->prepare(st->terms[i], &st->sys);
            if (rc < 0) return rc;
        }
    st->obj.n = nfree;
    st->have_pattern = 1;
    st->pattern_id++;
    return EO_OK;
}

/* ---------------------------------------------------------------- objective ops */

static void scatter_free(eo_step *st, const double *x)
{
    for (int i = 0; i < st->nfree; i++) st->xw[st->free2full[i]] = x[i];
}

static double sum_energy(eo_step *st, const double *xfull)
{
    double e = 0;
    for (int i = 0; i < st->nterms; i++) e += st->terms[i]->ops->energy(st->terms[i], &st->sys, xfull);
    return isnan(e) ? INFINITY : e;
}

static int op_value(void *data, const double *x, double *g)
{
    eo_step *st = data;
    scatter_free(st, x);
    *g = sum_energy(st, st->xw);
    return EO_OK;
}

static int op_gradient(void *data, const double *x, double *g, double *grad)
{
    eo_step *st = data;
    scatter_free(st, x);
    memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
    double e = 0;
    for (int i = 0; i < st->nterms; i++) {
        e += st->terms[i]->ops->gradient(st->terms[i], &st->sys, st->xw, st->gfull);
        if (!(e < INFINITY)) break;
    }
    *g = isfinite(e) ? e : INFINITY;
    for (int i = 0; i < st->nfree; i++) grad[i] = st->gfull[st->free2full[i]];
    return EO_OK;
}

static int op_hessian(void *data, const double *x, eo_proj proj, eo_csc **H)
{
    eo_step *st = data;
    scatter_free(st, x);
    eo_assembler_zero(st->as);
    for (int i = 0; i < st->nterms; i++) {
        int rc = st->terms[i]->ops->hessian(st->terms[i], &st->sys, st->xw, proj);
        if (rc < 0) return rc;
    }
    *H = eo_assembler_matrix(st->as);
    return EO_OK;
}

static int op_metric_diag(void *data, double *d)
{
    eo_step *st = data;
    for (int i = 0; i < st->nfree; i++) d[i] = st->vmass[st->free2full[i] / 3];
    return EO_OK;
}

static int op_inverted_count(void *data, const double *x)
{
    eo_step *st = data;
    scatter_free(st, x);
    int n = 0;
    for (int k = 0; k < st->nt; k++) n += eo_tet_is_inverted(tet_J(st, st->xw, k));
    return n;
}

static int op_constant_hessian(void *data, eo_csc **L, unsigned long *version)
{
    eo_step *st = data;
    return eo_pd_matrix_get(&st->pd, &st->sys, st->terms, st->nterms, st->pattern_id,
                            st->integ->weight ? st->integ->weight(st->h) : 1.0, L, version);
}

static const eo_objective_ops step_ops = {
    .value = op_value,
    .gradient = op_gradient,
    .hessian = op_hessian,
    .metric_diag = op_metric_diag,
    .inverted_count = op_inverted_count,
    .constant_hessian = op_constant_hessian,
};

/* ---------------------------------------------------------------- create / destroy */

static int add_term(eo_step *st, eo_term *t, eo_term **slot)
{
    if (!t) return EO_OK;
    EO_ASSERT(st->nterms < MAX_TERMS);
    st->terms[st->nterms++] = t;
    if (slot) *slot = t;
    return EO_OK;
}

void eo_step_destroy(eo_step **pst)
{
    if (!pst || !*pst) return;
    eo_step *st = *pst;
    eo_ctx *ctx = st->ctx;
    for (int i = 0; i < st->nterms; i++) eo_term_destroy(ctx, &st->terms[i]);
    eo_assembler_destroy(ctx, &st->as);
    eo_pd_matrix_deinit(ctx, &st->pd);
    eo_linsolve_destroy(&st->mls);
    eo_csc_destroy(ctx, &st->Mc);
    eo_free(ctx, st->ework);
    eo_free(ctx, st->xe);
    eo_free(ctx, st->ve);
    void *arrays[] = {st->Dminv, st->psi_rest, st->vol, st->rho, st->vmass, (void *)st->tet_type, (void *)st->tet_coef,
                      st->x, st->v, st->x0, st->xw, st->gfull, st->vnew, st->guess, st->vbc,
                      st->vbc_new, st->full2free, st->free2full, st->tet_dofs, st->sys.elem_g,
                      st->sys.elem_H};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++) eo_free(ctx, arrays[i]);
    eo_free(ctx, st);
    *pst = NULL;
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
    st->h = sc->time.dt;
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
    st->vbc = eo_malloc(ctx, nv * sizeof(int));
    st->vbc_new = eo_malloc(ctx, nv * sizeof(int));
    st->full2free = eo_malloc(ctx, nf * sizeof(int));
    st->free2full = eo_malloc(ctx, nf * sizeof(int));
    st->tet_dofs = eo_malloc(ctx, 12 * nt * sizeof(int));
    st->sys.block = BLOCK;
    st->sys.elem_g = eo_malloc(ctx, 12 * (size_t)BLOCK * sizeof(double));
    st->sys.elem_H = eo_malloc(ctx, 144 * (size_t)BLOCK * sizeof(double));
    if (!st->Dminv || !st->psi_rest || !st->vol || !st->rho || !st->vmass || !st->tet_type || !st->tet_coef || !st->x ||
        !st->v || !st->x0 || !st->xw || !st->gfull || !st->vnew || !st->guess || !st->vbc ||
        !st->vbc_new || !st->full2free || !st->free2full || !st->tet_dofs || !st->sys.elem_g ||
        !st->sys.elem_H) {
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
        }
        for (int a = 0; a < 4; a++) st->vmass[m->tets[4 * k + a]] += st->rho[k] * st->vol[k] / 4.0;
    }
    if (sc->pmass)
        for (int v = 0; v < m->nv; v++) st->vmass[v] += sc->pmass[v];
    /* shared data for the terms */
    eo_sys *s = &st->sys;
    s->ctx = ctx;
    s->mesh = m;
    s->nv = st->nv;
    s->nt = st->nt;
    s->n_full = st->n_full;
    s->Dminv = st->Dminv;
    s->vol = st->vol;
    s->rho = st->rho;
    s->psi_rest = st->psi_rest;
    s->tet_type = st->tet_type;
    s->tet_coef = st->tet_coef;
    s->vmass = st->vmass;
    s->pmass = sc->pmass;
    s->full2free = st->full2free;
    s->tet_dofs = st->tet_dofs;
    s->parallel = 0; /* serial by default: see eo_step_set_parallel */
    /* the term list: a scene pays only for the terms it uses */
    eo_term *t = NULL;
    if (st->integ->inertia && !st->integ->explicit_step) {
        EO_TRY(rc = eo_term_inertia_create(s, sc->lumped, &t));
        add_term(st, t, &st->inertia);
    }
    int any_tet = 0;
    for (int k = 0; k < m->nt; k++) any_tet |= !(st->tet_type[k]->flags & EO_MATERIAL_EDGE);
    if (any_tet) {
        EO_TRY(rc = eo_term_elastic_create(s, &t));
        add_term(st, t, &st->elastic);
    }
    t = NULL;
    EO_TRY(rc = eo_term_spring_create(s, sc->nspring, sc->spring_ab, sc->springs.k, sc->springs.damping, &t));
    add_term(st, t, &st->spring);
    t = NULL;
    EO_TRY(rc = eo_term_collision_create(s, sc->ncollision, sc->collision_plane, sc->collision_k, &t));
    add_term(st, t, &st->collision);
    if (sc->springs.damping > 0 && !st->integ->explicit_step) {
        rc = eo_error(ctx, EO_ERR_INVALID,
                      "springs.damping acts in explicit integrators only; %s is implicit (backward_euler "
                      "dissipates by itself)", st->integ->info.name);
        goto fail;
    }
    if (sc->opts.gravity[0] != 0 || sc->opts.gravity[1] != 0 || sc->opts.gravity[2] != 0) {
        EO_TRY(rc = eo_term_gravity_create(s, sc->opts.gravity, &t));
        add_term(st, t, &st->gravity);
    }
    if (st->integ->force_n) {
        EO_TRY(rc = eo_term_linear_create(s, &t));
        add_term(st, t, &st->linear);
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
    st->obj.ops = &step_ops;
    st->obj.data = st;
    EO_TRY(rc = eo_step_reset(st));
    *out = st;
    return EO_OK;
fail:
    eo_step_destroy(&st);
    return rc;
}

/* ---------------------------------------------------------------- state */

/* splitmix64 → uniform [0,1) */
static double rnd(unsigned long long *s)
{
    unsigned long long z = (*s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

int eo_step_reset(eo_step *st)
{
    const eo_scene *sc = st->sc;
    const double *X = sc->mesh->X;
    double c[3] = {0, 0, 0}, mt = 0;
    for (int v = 0; v < st->nv; v++) {
        for (int k = 0; k < 3; k++) c[k] += st->vmass[v] * X[3 * v + k];
        mt += st->vmass[v];
    }
    for (int k = 0; k < 3; k++) c[k] /= mt > 0 ? mt : 1;
    unsigned long long seed = (unsigned long long)sc->ball.seed * 0x2545F4914F6CDD1DULL + 1;
    for (int v = 0; v < st->nv; v++) {
        double *p = st->x + 3 * v;
        for (int k = 0; k < 3; k++) p[k] = c[k] + sc->initial.scale[k] * (X[3 * v + k] - c[k]);
        if (sc->has_reflect) {
            const double *n = sc->reflect.normal, *q = sc->reflect.point;
            double d = (p[0] - q[0]) * n[0] + (p[1] - q[1]) * n[1] + (p[2] - q[2]) * n[2];
            for (int k = 0; k < 3; k++) p[k] -= 2 * d * n[k];
        }
        if (sc->has_ball) {
            double u[3], r2;
            do {
                for (int k = 0; k < 3; k++) u[k] = 2 * rnd(&seed) - 1;
                r2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
            } while (r2 > 1);
            for (int k = 0; k < 3; k++) p[k] = c[k] + sc->ball.radius * u[k];
        }
        for (int k = 0; k < 3; k++) st->v[3 * v + k] = sc->initial.velocity[k];
    }
    memcpy(st->x0, st->x, (size_t)st->n_full * sizeof(double));
    st->t = 0;
    st->index = 0;
    /* constrained vertices start at their prescribed state */
    active_set(st, 0, st->vbc_new);
    for (int v = 0; v < st->nv; v++) {
        if (st->vbc_new[v] < 0) continue;
        double p[3], vel[3];
        bc_motion(st, st->sc->bc + st->vbc_new[v], v, 0, p, vel);
        for (int k = 0; k < 3; k++) {
            st->x[3 * v + k] = p[k];
            st->v[3 * v + k] = st->integ->inertia ? vel[k] : 0;
        }
    }
    if (!st->integ->inertia) memset(st->v, 0, (size_t)st->n_full * sizeof(double));
    st->erestart = 1;
    return EO_OK;
}

int eo_step_set_state(eo_step *st, const double *x, const double *v, double t)
{
    memcpy(st->x, x, (size_t)st->n_full * sizeof(double));
    memcpy(st->v, v, (size_t)st->n_full * sizeof(double));
    st->t = t;
    st->erestart = 1;
    return EO_OK;
}

/* ---------------------------------------------------------------- one step */

int eo_step_begin(eo_step *st, eo_objective **obj)
{
    const double h = st->h, t1 = st->t + h;
    int rc;
    /* constrained set at tₙ₊₁; rebuild the pattern if it changed */
    active_set(st, t1, st->vbc_new);
    int changed = !st->have_pattern;
    for (int v = 0; v < st->nv && !changed; v++) changed = (st->vbc[v] >= 0) != (st->vbc_new[v] >= 0);
    memcpy(st->vbc, st->vbc_new, (size_t)st->nv * sizeof(int));
    if (changed) {
        rc = build_pattern(st);
        if (rc < 0) return rc;
    }
    const double w = st->integ->weight ? st->integ->weight(h) : 1.0; /* explicit: E(x) */
    for (int i = 0; i < st->nterms; i++) st->terms[i]->weight = w;
    if (st->inertia) {
        st->inertia->weight = 1;
        st->integ->predict(st->n_full, h, st->x, st->v, st->inertia->vec);
    }
    if (st->linear) {
        /* c = fₙ = −∇(E_el + gravity potential)(xₙ) */
        memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
        eo_term *forces[4] = {st->elastic, st->spring, st->gravity, st->collision};
        for (int i = 0; i < 4; i++) {
            if (!forces[i]) continue;
            double wsave = forces[i]->weight;
            forces[i]->weight = 1;
            forces[i]->ops->gradient(forces[i], &st->sys, st->x, st->gfull);
            forces[i]->weight = wsave;
        }
        for (int j = 0; j < st->n_full; j++) st->linear->vec[j] = -st->gfull[j];
    }
    /* full work vector: xₙ with prescribed positions at tₙ₊₁ */
    memcpy(st->xw, st->x, (size_t)st->n_full * sizeof(double));
    for (int v = 0; v < st->nv; v++) {
        if (st->vbc[v] < 0) continue;
        double p[3], vel[3];
        bc_motion(st, st->sc->bc + st->vbc[v], v, t1, p, vel);
        for (int k = 0; k < 3; k++) st->xw[3 * v + k] = p[k];
    }
    /* starting guess: the lower of g(xₙ) and g(x̃) */
    for (int i = 0; i < st->nfree; i++) st->guess[i] = st->x[st->free2full[i]];
    if (st->inertia) {
        double g0, g1;
        op_value(st, st->guess, &g0);
        for (int i = 0; i < st->nfree; i++) st->vnew[i] = st->inertia->vec[st->free2full[i]];
        op_value(st, st->vnew, &g1);
        if (g1 < g0) memcpy(st->guess, st->vnew, (size_t)st->nfree * sizeof(double));
    }
    st->obj.n = st->nfree;
    st->obj.n_value = st->obj.n_gradient = st->obj.n_hessian = 0;
    *obj = &st->obj;
    return EO_OK;
}

double *eo_step_guess(eo_step *st) { return st->guess; }

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

int eo_step_end(eo_step *st, const double *x)
{
    if (st->integ->explicit_step)
        return eo_error(st->ctx, EO_ERR_UNSUPPORTED, "integrator %s is explicit: advance with eo_step_advance",
                        st->integ->info.name);
    const double h = st->h, t1 = st->t + h;
    scatter_free(st, x);
    st->integ->velocity(st->n_full, h, st->x, st->v, st->xw, st->vnew);
    for (int v = 0; v < st->nv; v++) {
        if (st->vbc[v] < 0) continue;
        double p[3], vel[3];
        bc_motion(st, st->sc->bc + st->vbc[v], v, t1, p, vel);
        for (int k = 0; k < 3; k++) st->vnew[3 * v + k] = st->integ->inertia ? vel[k] : 0;
    }
    memcpy(st->x, st->xw, (size_t)st->n_full * sizeof(double));
    memcpy(st->v, st->vnew, (size_t)st->n_full * sizeof(double));
    st->t = t1;
    st->index++;
    return EO_OK;
}

/* ---------------------------------------------------------------- explicit integrators
 *
 * The ODE the explicit integrators see (step.h, eo_ode): x' = v, v' = a(t, x, v) over
 * the full 3·nv coordinates with
 *     a = M⁻¹ f,   f = −∇E(x) − damping,
 * E the sum of the step's terms at weight 1 (elastic, springs, gravity, collisions; no
 * inertia or linear term exists for an explicit integrator). Prescribed vertices are
 * set to their position at the stage time t before the forces are evaluated and get
 * a = 0; after the step they are overwritten with their motion at tₙ₊₁. Lumped mass:
 * a = f/m per vertex. Consistent mass: M_ff (free rows and columns) assembled once per
 * pattern and factored with CHOLMOD; a_f = M_ff⁻¹ f_f. */

static void tet_mass_block(double m, double Ke[144])
{
    memset(Ke, 0, 144 * sizeof(double));
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
            for (int c = 0; c < 3; c++) Ke[(3 * a + c) * 12 + 3 * b + c] = m * (a == b ? 2.0 : 1.0);
}

static int factor_mass(eo_step *st)
{
    eo_ctx *ctx = st->ctx;
    eo_assembler_zero(st->as);
    double Ke[144];
    for (int k = 0; k < st->nt; k++) {
        tet_mass_block(st->rho[k] * st->vol[k] / 20.0, Ke);
        eo_assembler_add(st->as, st->sys.tet_group, k, Ke);
    }
    for (int j = 0; j < st->n_full; j++) {
        int i = st->full2free[j];
        if (i >= 0 && st->sys.pmass) eo_assembler_add_diag(st->as, i, st->sys.pmass[j / 3]);
    }
    eo_csc_destroy(ctx, &st->Mc);
    int rc = eo_csc_clone(ctx, eo_assembler_matrix(st->as), &st->Mc);
    if (rc < 0) return rc;
    eo_assembler_zero(st->as);
    if (!st->mls) {
        const eo_linsolve_type *lt;
        if ((rc = eo_linsolve_find(ctx, "cholmod", &lt)) < 0) return rc;
        if ((rc = eo_linsolve_create(ctx, lt, NULL, &st->mls)) < 0) return rc;
    }
    if ((rc = eo_linsolve_analyze(st->mls, st->Mc)) < 0) return rc;
    rc = eo_linsolve_factor(st->mls, st->Mc);
    if (rc == EO_WARN_NOT_PD)
        return eo_error(ctx, EO_ERR_INVALID,
                        "consistent mass matrix not positive definite (a free vertex without mass?)");
    if (rc < 0) return rc;
    return EO_OK;
}

static int explicit_accel(void *data, double t, const double *x, const double *v, double *a)
{
    eo_step *st = data;
    memcpy(st->xw, x, (size_t)st->n_full * sizeof(double));
    for (int q = 0; q < st->nv; q++) {
        if (st->vbc[q] < 0) continue;
        double p[3], vel[3];
        bc_motion(st, st->sc->bc + st->vbc[q], q, t, p, vel);
        for (int k = 0; k < 3; k++) st->xw[3 * q + k] = p[k];
    }
    memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
    for (int i = 0; i < st->nterms; i++) {
        st->terms[i]->weight = 1;
        st->terms[i]->ops->gradient(st->terms[i], &st->sys, st->xw, st->gfull);
    }
    if (st->spring) eo_term_spring_damping(st->spring, &st->sys, st->xw, v, st->gfull);
    if (st->sc->lumped || !st->nt) {
        for (int j = 0; j < st->n_full; j++) a[j] = -st->gfull[j] / st->vmass[j / 3];
    } else {
        for (int i = 0; i < st->nfree; i++) st->vnew[i] = -st->gfull[st->free2full[i]];
        int rc = eo_linsolve_solve(st->mls, st->vnew, st->guess);
        if (rc < 0) return rc;
        for (int j = 0; j < st->n_full; j++) a[j] = 0;
        for (int i = 0; i < st->nfree; i++) a[st->free2full[i]] = st->guess[i];
    }
    for (int q = 0; q < st->nv; q++)
        if (st->vbc[q] >= 0) a[3 * q] = a[3 * q + 1] = a[3 * q + 2] = 0;
    return EO_OK;
}

int eo_step_is_explicit(const eo_step *st) { return st->integ->explicit_step != NULL; }

/* Finite: every coordinate, ‖x‖² and the lumped kinetic energy Σ m v² (an overflowing
 * square is as diverged as an infinite coordinate). */
static int state_finite(const eo_step *st, const double *x, const double *v)
{
    double sx = 0, sv = 0;
    for (int j = 0; j < st->n_full; j++) {
        sx += x[j] * x[j];
        sv += st->vmass[j / 3] * v[j] * v[j];
    }
    return isfinite(sx) && isfinite(sv);
}

int eo_step_state_finite(const eo_step *st) { return state_finite(st, st->x, st->v); }

int eo_step_advance(eo_step *st, int *reason)
{
    eo_ctx *ctx = st->ctx;
    *reason = 0;
    if (!st->integ->explicit_step)
        return eo_error(ctx, EO_ERR_UNSUPPORTED, "integrator %s is implicit: use eo_step_begin/eo_step_end",
                        st->integ->info.name);
    const double h = st->h, t0 = st->t, t1 = st->t + h;
    int rc;
    active_set(st, t1, st->vbc_new);
    int changed = !st->have_pattern;
    for (int q = 0; q < st->nv && !changed; q++) changed = (st->vbc[q] >= 0) != (st->vbc_new[q] >= 0);
    memcpy(st->vbc, st->vbc_new, (size_t)st->nv * sizeof(int));
    if (changed && (rc = build_pattern(st)) < 0) return rc;
    for (int q = 0; q < st->nv; q++)
        if (st->vbc[q] < 0 && !(st->vmass[q] > 0))
            return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_ITEM(NULL, -1, "vertex", q),
                               "free vertex %d has no mass (in no tet and no point mass): cannot compute its "
                               "acceleration", q);
    if (!st->sc->lumped && st->nt && (changed || !st->Mc || st->Mc->n != st->nfree) && (rc = factor_mass(st)) < 0)
        return rc;
    memcpy(st->xe, st->x, (size_t)st->n_full * sizeof(double));
    memcpy(st->ve, st->v, (size_t)st->n_full * sizeof(double));
    eo_ode ode = {.n = st->n_full, .data = st, .accel = explicit_accel};
    rc = st->integ->explicit_step(&ode, t0, h, st->xe, st->ve, st->ework, st->erestart);
    if (rc < 0) return rc;
    for (int q = 0; q < st->nv; q++) {
        if (st->vbc[q] < 0) continue;
        double p[3], vel[3];
        bc_motion(st, st->sc->bc + st->vbc[q], q, t1, p, vel);
        for (int k = 0; k < 3; k++) {
            st->xe[3 * q + k] = p[k];
            st->ve[3 * q + k] = vel[k];
        }
    }
    if (!state_finite(st, st->xe, st->ve)) {
        *reason = EO_DIVERGED_NONFINITE;
        st->erestart = 1;
        return EO_OK;
    }
    memcpy(st->x, st->xe, (size_t)st->n_full * sizeof(double));
    memcpy(st->v, st->ve, (size_t)st->n_full * sizeof(double));
    st->t = t1;
    st->index++;
    st->erestart = 0;
    *reason = EO_CONVERGED_EXPLICIT;
    return EO_OK;
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
int eo_step_full_to_free(const eo_step *st, int j)
{
    return st->have_pattern && j >= 0 && j < st->n_full ? st->full2free[j] : -1;
}

int eo_step_stats_compute(eo_step *st, eo_step_stats *s)
{
    const double *x = st->x, *v = st->v, *X = st->sc->mesh->X;
    memset(s, 0, sizeof *s);
    double mt = 0;
    s->max_disp = 0;
    for (int i = 0; i < st->nv; i++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            s->com[k] += st->vmass[i] * x[3 * i + k];
            double d = x[3 * i + k] - X[3 * i + k];
            d2 += d * d;
        }
        mt += st->vmass[i];
        if (sqrt(d2) > s->max_disp) s->max_disp = sqrt(d2);
    }
    for (int k = 0; k < 3; k++) s->com[k] /= mt > 0 ? mt : 1;
    s->min_J = st->nt ? INFINITY : 1; /* no tets (mesh.points): nothing deformed, J = 1 */
    s->max_J = st->nt ? -INFINITY : 1;
    for (int k = 0; k < st->nt; k++) {
        double J = tet_J(st, x, k);
        if (J < s->min_J) s->min_J = J;
        if (J > s->max_J) s->max_J = J;
        s->inverted += eo_tet_is_inverted(J);
    }
    /* kinetic energy with the scene's mass matrix */
    double ke = 0;
    if (st->sc->lumped) {
        for (int i = 0; i < st->nv; i++)
            ke += st->vmass[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    } else {
        for (int k = 0; k < st->nt; k++) {
            const int *tet = st->sc->mesh->tets + 4 * k;
            double sum[3] = {0, 0, 0}, q = 0;
            for (int a = 0; a < 4; a++)
                for (int c = 0; c < 3; c++) {
                    q += v[3 * tet[a] + c] * v[3 * tet[a] + c];
                    sum[c] += v[3 * tet[a] + c];
                }
            ke += st->rho[k] * st->vol[k] / 20.0 * (q + sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        }
        for (int i = 0; st->sc->pmass && i < st->nv; i++)
            ke += st->sc->pmass[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    }
    s->kinetic = 0.5 * ke;
    eo_term *el[2] = {st->elastic, st->spring};
    for (int i = 0; i < 2; i++) {
        if (!el[i]) continue;
        double wsave = el[i]->weight;
        el[i]->weight = 1;
        s->elastic += el[i]->ops->energy(el[i], &st->sys, x);
        el[i]->weight = wsave;
    }
    const double *g = st->sc->opts.gravity;
    for (int i = 0; i < st->nv; i++)
        s->gravity -= st->vmass[i] * (g[0] * x[3 * i] + g[1] * x[3 * i + 1] + g[2] * x[3 * i + 2]);
    return EO_OK;
}

int eo_step_fields(eo_step *st, double *psi, double *J, unsigned char *inverted)
{
    for (int k = 0; k < st->nt; k++) {
        double Jk = tet_J(st, st->x, k), p = 0;
        if (psi && !(st->tet_type[k]->flags & EO_MATERIAL_EDGE)) {
            double x12[12];
            eo_tet_out out;
            eo_gather12(st->x, st->sc->mesh->tets + 4 * k, x12);
            eo_tet_evaluate(st->tet_type[k], st->tet_coef[k], st->Dminv + 9 * k, st->vol[k], x12,
                            EO_EVAL_ENERGY, EO_PROJ_NONE, &out);
            p = out.psi - st->psi_rest[k];
        }
        if (psi) psi[k] = p;
        if (J) J[k] = Jk;
        if (inverted) inverted[k] = (unsigned char)eo_tet_is_inverted(Jk);
    }
    return EO_OK;
}
