/* Explicit integrators of the step engine (eo_step_advance).
 *
 * The ODE the explicit integrators see (step.h, eo_ode): x' = v, v' = a(t, x, v) over
 * the full 3·nv coordinates with
 *     a = M⁻¹ f,   f = −∇E(x) − damping,
 * E the sum of the step's terms at weight 1 (elastic, springs, gravity, collisions; no
 * inertia or linear term exists for an explicit integrator). Prescribed vertices are
 * set to their position at the stage time t before the forces are evaluated and get
 * a = 0; after the step they are overwritten with their motion at tₙ₊₁. Lumped mass:
 * a = f/m per vertex. Consistent mass: M_ff (free rows and columns) assembled once per
 * pattern and factored with the mass solver (eo_step_set_mass_solver; eo_sim passes the
 * scene's solver.linear; default cholmod); a_f = M_ff⁻¹ f_f.
 *
 * Divergence: a non-finite energy or force at any stage of a step (any term), or a
 * non-finite or overflowing new state, ends the step with EO_DIVERGED_NONFINITE and
 * leaves the state at tₙ (the last finite one). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "step_impl.h"

static int factor_mass(eo_step *st)
{
    eo_ctx *ctx = st->ctx;
    eo_assembler_zero(st->as);
    for (int k = 0; k < st->nt; k++) {
        eo_sys_element_mass(&st->sys, k, st->sys.elem_H);
        eo_assembler_add(st->as, st->sys.tet_group, k, st->sys.elem_H);
    }
    for (int j = 0; j < st->n_full; j++) {
        int i = st->full2free[j];
        if (i >= 0 && st->sys.pmass) eo_assembler_add_diag(st->as, i, st->sys.pmass[j / 3]);
    }
    eo_csc_destroy(&st->Mc);
    int rc = eo_csc_clone(ctx, eo_assembler_matrix(st->as), &st->Mc);
    if (rc < 0) return rc;
    st->Mc_pattern = st->pattern_id;
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
    st->inv_valid = 0;
    memcpy(st->xw, x, (size_t)st->n_full * sizeof(double));
    for (int q = 0; q < st->nv; q++) {
        if (st->vbc[q] < 0) continue;
        double p[3], vel[3];
        eo_stepi_bc_motion(st, st->sc->bc + st->vbc[q], q, t, p, vel);
        for (int k = 0; k < 3; k++)
            if (st->sc->bc[st->vbc[q]].mask[k]) st->xw[3 * q + k] = p[k];
    }
    memset(st->gfull, 0, (size_t)st->n_full * sizeof(double));
    double e = 0;
    for (int i = 0; i < st->nterms; i++) {
        /* the potentials' forces (damping: a force of v, below; inertia, linear, friction:
         * implicit only, see eo_stepi_accel) */
        if (!(st->terms[i]->flags & EO_TERM_POTENTIAL)) continue;
        st->terms[i]->weight = 1;
        e += st->terms[i]->ops->gradient(st->terms[i], &st->sys, st->xw, st->gfull);
    }
    if (st->spring) eo_term_spring_damping(st->spring, &st->sys, st->xw, v, st->gfull);
    if (st->damping) eo_term_damping_apply(st->damping, &st->sys, v, st->gfull); /* f −= C v */
    int finite = isfinite(e);
    for (int j = 0; j < st->n_full && finite; j++) finite = isfinite(st->gfull[j]);
    if (!finite) { /* diverged: the step is rejected (eo_step_advance); no solve with it */
        st->enonfinite = 1;
        for (int j = 0; j < st->n_full; j++) a[j] = NAN;
        return EO_OK;
    }
    if (st->sc->lumped || !st->nt) {
        for (int j = 0; j < st->n_full; j++) a[j] = st->vmass[j / 3] > 0 ? -st->gfull[j] / st->vmass[j / 3] : 0;
    } else {
        for (int i = 0; i < st->nfree; i++) st->vnew[i] = -st->gfull[st->free2full[i]];
        int rc = eo_linsolve_solve(st->mls, st->vnew, st->guess);
        if (rc < 0) return rc;
        for (int j = 0; j < st->n_full; j++) a[j] = 0;
        for (int i = 0; i < st->nfree; i++) a[st->free2full[i]] = st->guess[i];
    }
    for (int q = 0; q < st->nv; q++)
        for (int k = 0; k < 3; k++)
            if (eo_stepi_fixed(st, st->vbc, 3 * q + k)) a[3 * q + k] = 0;
    return EO_OK;
}

int eo_stepi_accel(eo_step *st, double t, const double *x, const double *v, double *a)
{
    int rc;
    if (!st->sc->lumped && st->nt && (!st->Mc || st->Mc->n != st->nfree || st->Mc_pattern != st->pattern_id) &&
        (rc = factor_mass(st)) < 0)
        return rc;
    if ((rc = eo_stepi_damping_stiffness(st)) < 0) return rc;
    st->enonfinite = 0;
    return explicit_accel(st, t, x, v, a);
}

int eo_step_set_mass_solver(eo_step *st, eo_linsolve *ls)
{
    eo_linsolve_destroy(&st->mls);
    eo_csc_destroy(&st->Mc); /* factored again at the next advance */
    st->mls = ls;
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
    double ok = isfinite(sx) && isfinite(sv);
    eo_ctx_reduce(st->ctx, &ok, 1, EO_REDUCE_MIN); /* a distributed run: every part finite */
    return ok > 0;
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
    int changed;
    if ((rc = eo_stepi_update_constraints(st, t1, &changed)) < 0) return rc;
    for (int q = 0; q < st->nv; q++)
        if (st->vbc[q] < 0 && !(st->vmass[q] > 0))
            return eo_error_at(ctx, EO_ERR_INVALID, EO_ERRLOC_ITEM(NULL, -1, "vertex", q),
                               "free vertex %d has no mass (in no tet and no point mass): cannot compute its "
                               "acceleration", q);
    if (!st->sc->lumped && st->nt && (changed || !st->Mc || st->Mc->n != st->nfree) && (rc = factor_mass(st)) < 0)
        return rc;
    if ((rc = eo_stepi_damping_stiffness(st)) < 0) return rc; /* Rayleigh β: K₀ at xₙ */
    memcpy(st->xe, st->x, (size_t)st->n_full * sizeof(double));
    memcpy(st->ve, st->v, (size_t)st->n_full * sizeof(double));
    eo_ode ode = {.n = st->n_full, .data = st, .accel = explicit_accel};
    st->enonfinite = 0;
    rc = st->integ->explicit_step(&ode, t0, h, st->xe, st->ve, st->ework, st->erestart);
    if (rc < 0) return rc;
    for (int q = 0; q < st->nv; q++) {
        if (st->vbc[q] < 0) continue;
        double p[3], vel[3];
        eo_stepi_bc_motion(st, st->sc->bc + st->vbc[q], q, t1, p, vel);
        for (int k = 0; k < 3; k++) {
            if (!st->sc->bc[st->vbc[q]].mask[k]) continue;
            st->xe[3 * q + k] = p[k];
            st->ve[3 * q + k] = vel[k];
        }
    }
    if (st->enonfinite || !state_finite(st, st->xe, st->ve)) {
        *reason = EO_DIVERGED_NONFINITE;
        st->erestart = 1;
        return EO_OK;
    }
    eo_stepi_work_update(st, st->xe, st->ve);
    memcpy(st->x, st->xe, (size_t)st->n_full * sizeof(double));
    memcpy(st->v, st->ve, (size_t)st->n_full * sizeof(double));
    st->t = t1;
    st->index++;
    st->erestart = 0;
    *reason = EO_REASON_EXPLICIT;
    return EO_OK;
}

