/* Boundary conditions of the step engine (step.h, scene.h): at time t a vertex follows
 * the last active entry of the boundary list that selects it (an entry is active until
 * its `release` time); prescribed position p(t) = motion(x₀, min(t, until)) with x₀ the
 * initial position, prescribed velocity dp/dt (0 after `until`). When a release changes
 * the constrained set, the free map (full → free, −1 for constrained coordinates) and
 * the Hessian pattern over the free coordinates (fixed-pattern assembler, each tet with
 * its 12 free ids, −1 where constrained) are rebuilt: once per release. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "step_impl.h"

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

void eo_stepi_active_set(const eo_step *st, double t, int *vbc)
{
    for (int v = 0; v < st->nv; v++) vbc[v] = -1;
    for (int b = 0; b < st->sc->nbc; b++) {
        const eo_bc *bc = st->sc->bc + b;
        if (!bc_active(bc, t, st->h_nom)) continue;
        for (int i = 0; i < bc->nverts; i++) vbc[bc->verts[i]] = b;
    }
}

/* Prescribed position and velocity of vertex v under entry bc at time t. */
void eo_stepi_bc_motion(const eo_step *st, const eo_bc *bc, int v, double t, double p[3], double vel[3])
{
    const double *base = st->x0 + 3 * v;
    if (st->sc->time.load_steps > 0) /* load stepping: the motions reach their value at L·dt and hold */
        t = fmin(t, st->sc->time.load_steps * st->h_nom);
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
    st->inv_valid = 0;
    for (int j = 0; j < st->n_full; j++) {
        if (eo_stepi_fixed(st, st->vbc, j)) {
            st->full2free[j] = -1;
        } else {
            st->free2full[nfree] = j;
            st->full2free[j] = nfree++;
        }
    }
    st->nfree = nfree;
    const int *tets = st->sys.enodes, npe = st->sys.npe, ne = 3 * npe;
    for (int k = 0; k < st->nt; k++)
        for (int a = 0; a < npe; a++)
            for (int c = 0; c < 3; c++)
                st->tet_dofs[(size_t)ne * k + 3 * a + c] = st->full2free[3 * tets[(size_t)npe * k + a] + c];
    eo_assembler_destroy(&st->as);
    st->sys.as = NULL;
    int rc = eo_assembler_create(ctx, nfree, &st->as);
    if (rc < 0) return rc;
    st->sys.as = st->as;
    int hgroup = eo_assembler_add_elements(ctx, st->as, st->nt, ne, st->tet_dofs);
    if (hgroup < 0) return hgroup;
    st->sys.tet_group = hgroup;
    st->sys.ord_group = -1;
    if (st->nt > 1 && st->sys.linear) { /* the same tets in the visit order (eo_sys.ord_group) */
        for (int i = 0; i < st->nt; i++)
            memcpy(st->ord_dofs + 12 * i, st->tet_dofs + 12 * st->tet_order[i], 12 * sizeof(int));
        int og = eo_assembler_add_elements(ctx, st->as, st->nt, 12, st->ord_dofs);
        if (og < 0) return og;
        st->sys.ord_group = og;
    }
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


int eo_stepi_pd_matrix_all(eo_step *st, eo_csc **A)
{
    *A = NULL;
    /* the pattern with every vertex free (vbc_new, scratch outside update_constraints,
     * keeps the active set), L assembled into it, then the active set's pattern again
     * (the same free map and pattern as before: build_pattern is deterministic) */
    memcpy(st->vbc_new, st->vbc, (size_t)st->nv * sizeof(int));
    for (int v = 0; v < st->nv; v++) st->vbc[v] = -1;
    int rc = build_pattern(st);
    if (rc >= 0) {
        eo_pd_matrix all = {0};
        eo_csc *L = NULL;
        unsigned long ver = 0;
        rc = eo_pd_matrix_get(&all, &st->sys, st->terms, st->nterms, st->pattern_id, st->w, &L, &ver);
        if (rc >= 0) {
            *A = all.L; /* taken over */
            all.L = NULL;
        }
        eo_pd_matrix_deinit(st->ctx, &all);
    }
    memcpy(st->vbc, st->vbc_new, (size_t)st->nv * sizeof(int));
    int rc2 = build_pattern(st);
    if (rc >= 0 && rc2 < 0) eo_csc_destroy(A);
    return rc < 0 ? rc : rc2;
}

int eo_stepi_update_constraints(eo_step *st, double t, int *changed)
{
    eo_stepi_active_set(st, t, st->vbc_new);
    int ch = !st->have_pattern;
    for (int j = 0; j < st->n_full && !ch; j++) ch = eo_stepi_fixed(st, st->vbc, j) != eo_stepi_fixed(st, st->vbc_new, j);
    memcpy(st->vbc, st->vbc_new, (size_t)st->nv * sizeof(int));
    if (changed) *changed = ch;
    return ch ? build_pattern(st) : EO_OK;
}
