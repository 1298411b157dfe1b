/* Diagnostics of the step engine's current state: eo_step_stats (centre of mass,
 * displacement, det F range, inverted tets, kinetic, elastic, gravity and contact
 * energy, the work of the prescribed motions and the total energy) and the per-tet
 * fields written to the frames.
 *
 * Energy balance. With V = E_el + springs + gravity + contact and the prescribed
 * (constrained) coordinates c moving on p(t), d/dt(½vᵀMv + V) = v_cᵀ r_c with the
 * reaction r = Ma + ∇V (zero on the free coordinates of an undamped scene), so
 *     total = ½vᵀMv + V − W,   W = ∫ r_c · dp
 * is constant along an exact trajectory. W (st->work) is accumulated per accepted step
 * by eo_stepi_work_update, see eo_step_work_prescribed in step.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "step_impl.h"

/* ---------------------------------------------------------------- small math */

/* out = M (u − u0) (u0 NULL: 0) over all coordinates for a general element (consistent: ρV M_el ⊗ I₃ per tet,
 * plus the point masses); out is overwritten */
static void mass_apply_el(const eo_step *st, const double *u, const double *u0, double *out)
{
    const int n = st->sys.npe;
    const double *M = st->sys.el->mass;
    memset(out, 0, (size_t)st->n_full * sizeof(double));
    for (int k = 0; k < st->nt; k++) {
        const int *en = st->sys.enodes + (size_t)n * k;
        const double rv = st->rho[k] * st->vol[k];
        for (int a = 0; a < n; a++)
            for (int b = 0; b < n; b++)
                for (int c = 0; c < 3; c++) {
                    const int j = 3 * en[b] + c;
                    out[3 * en[a] + c] += rv * M[n * a + b] * (u0 ? u[j] - u0[j] : u[j]);
                }
    }
    for (int i = 0; st->sc->pmass && i < st->nv; i++)
        for (int c = 0; c < 3; c++) {
            const int j = 3 * i + c;
            out[j] += st->sc->pmass[i] * (u0 ? u[j] - u0[j] : u[j]);
        }
}

/* det F of tet k at positions x, computed as the material kernel computes it (eo_tet_J:
 * F = Ds Dm⁻¹, then eo_det3), so that eo_tet_is_inverted agrees with the barrier. */
double eo_stepi_tet_J(const eo_step *st, const double *x, int k)
{
    if (!st->sys.linear) { /* the smallest det F over the element's quadrature points */
        const eo_element_type *el = st->sys.el;
        const int *en = st->sys.enodes + (size_t)el->nodes * k;
        double jmin = INFINITY;
        for (int q = 0; q < el->nq; q++) {
            double G[3 * EO_ELEMENT_MAX_NODES], F[9] = {0};
            eo_element_grad(el, st->Dminv + 9 * k, el->qp + 4 * q, G);
            for (int a = 0; a < el->nodes; a++)
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) F[3 * i + j] += x[3 * en[a] + i] * G[3 * a + j];
            const double J = eo_det3(F);
            if (!(J >= jmin)) jmin = J;
        }
        return jmin;
    }
    double x12[12];
    eo_gather12(x, st->sc->mesh->tets + 4 * k, x12);
    return eo_tet_J(st->Dminv + 9 * k, x12);
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
    double mt_all = mt, com_all[3] = {s->com[0], s->com[1], s->com[2]};
    s->min_J = st->nt ? INFINITY : 1; /* no tets (mesh.points): nothing deformed, J = 1 */
    s->max_J = st->nt ? -INFINITY : 1;
    for (int k = 0; k < st->nt; k++) {
        double J = eo_stepi_tet_J(st, x, k);
        if (J < s->min_J) s->min_J = J;
        if (J > s->max_J) s->max_J = J;
        s->inverted += eo_tet_is_inverted(J);
    }
    /* kinetic energy with the scene's mass matrix */
    double ke = 0;
    if (st->sc->lumped) {
        for (int i = 0; i < st->nv; i++)
            ke += st->vmass[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    } else if (!st->sys.linear) {
        mass_apply_el(st, v, NULL, st->gfull);
        for (int j = 0; j < st->n_full; j++) ke += v[j] * st->gfull[j];
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
    /* the potential terms at weight 1: elastic energy, contact, other loads (tractions);
     * gravity from the vertex loads */
    double other = 0;
    int have_other = 0;
    for (int i = 0; i < st->nterms; i++) {
        eo_term *t = st->terms[i];
        if (!(t->flags & EO_TERM_POTENTIAL) || (t->flags & EO_TERM_GRAVITY)) continue;
        double wsave = t->weight;
        t->weight = 1;
        const double e = t->ops->energy(t, &st->sys, x);
        t->weight = wsave;
        if (t->flags & EO_TERM_ELASTIC_ENERGY) s->elastic += e;
        else if (t->flags & EO_TERM_CONTACT) s->contact += e;
        else other += e, have_other = 1;
    }
    const double *g = st->sc->opts.gravity;
    for (int i = 0; i < st->nv; i++)
        s->gravity -= st->sys.vload[i] * (g[0] * x[3 * i] + g[1] * x[3 * i + 1] + g[2] * x[3 * i + 2]);
    s->potential = s->elastic + s->gravity + s->contact;
    if (have_other) s->potential += other;
    s->work_prescribed = st->work;
    if (eo_ctx_dist(st->ctx)) { /* a distributed run: every part's sums and extremes */
        double sum[9] = {com_all[0], com_all[1], com_all[2], mt_all, s->kinetic, s->elastic, s->gravity, s->contact,
                         s->work_prescribed};
        double mx[3] = {s->max_disp, s->max_J, -s->min_J}, inv = s->inverted;
        eo_ctx_reduce(st->ctx, sum, 9, EO_REDUCE_SUM);
        eo_ctx_reduce(st->ctx, mx, 3, EO_REDUCE_MAX);
        eo_ctx_reduce(st->ctx, &inv, 1, EO_REDUCE_SUM);
        double oth = other;
        eo_ctx_reduce(st->ctx, &oth, 1, EO_REDUCE_SUM);
        for (int k = 0; k < 3; k++) com_all[k] = sum[k];
        mt_all = sum[3], s->kinetic = sum[4], s->elastic = sum[5], s->gravity = sum[6], s->contact = sum[7];
        s->work_prescribed = sum[8];
        s->max_disp = mx[0], s->max_J = mx[1], s->min_J = -mx[2], s->inverted = (int)inv;
        other = oth;
        s->potential = s->elastic + s->gravity + s->contact + (have_other ? other : 0);
    }
    for (int k = 0; k < 3; k++) s->com[k] = com_all[k] / (mt_all > 0 ? mt_all : 1);
    s->total_energy = s->kinetic + s->potential - s->work_prescribed;
    return EO_OK;
}

double eo_step_work_prescribed(const eo_step *st) { return st->work; }

void eo_step_set_work_prescribed(eo_step *st, double w) { st->work = w; }

/* r = ∇V(x) over all coordinates: the static reaction */
static void potential_gradient(eo_step *st, const double *x, double *r)
{
    memset(r, 0, (size_t)st->n_full * sizeof(double));
    eo_stepi_potential_gradient(st, x, r);
}

void eo_stepi_potential_gradient(eo_step *st, const double *x, double *r)
{
    for (int pass = 0; pass < 2; pass++) /* the contact terms last (the engine's summation order) */
        for (int i = 0; i < st->nterms; i++) {
            eo_term *t = st->terms[i];
            if (!(t->flags & EO_TERM_POTENTIAL) || !(t->flags & EO_TERM_CONTACT) != !pass) continue;
            double wsave = t->weight;
            t->weight = 1;
            t->ops->gradient(t, &st->sys, x, r);
            t->weight = wsave;
        }
}

void eo_stepi_work_update(eo_step *st, const double *x1, const double *v1)
{
    const double *x = st->x, *v = st->v;
    if (!st->rpot) return; /* no boundary entries: nothing prescribed */
    int moving = 0;
    for (int q = 0; q < st->nv && !moving; q++) {
        if (st->vbc[q] < 0) continue;
        for (int k = 0; k < 3; k++) {
            const int j = 3 * q + k;
            if (!eo_stepi_fixed(st, st->vbc, j)) continue;
            moving |= x1[j] != x[j] || v[j] + v1[j] != 0;
        }
    }
    if (!moving) { /* fixed vertices: no work; the reaction at xₙ₊₁ is not needed */
        st->rpot_valid = 0;
        return;
    }
    if (!st->rpot_valid) potential_gradient(st, x, st->rpot);
    potential_gradient(st, x1, st->rpot1);
    /* M Δv (only the constrained entries are read) */
    double *mdv = st->gfull;
    if (st->sc->lumped || !st->nt) {
        for (int j = 0; j < st->n_full; j++) mdv[j] = st->vmass[j / 3] * (v1[j] - v[j]);
    } else if (!st->sys.linear) {
        mass_apply_el(st, v1, v, mdv);
    } else {
        memset(mdv, 0, (size_t)st->n_full * sizeof(double));
        for (int k = 0; k < st->nt; k++) {
            const int *tet = st->sc->mesh->tets + 4 * k;
            const double m = st->rho[k] * st->vol[k] / 20.0;
            double sum[3] = {0, 0, 0};
            for (int a = 0; a < 4; a++)
                for (int c = 0; c < 3; c++) sum[c] += v1[3 * tet[a] + c] - v[3 * tet[a] + c];
            for (int a = 0; a < 4; a++)
                for (int c = 0; c < 3; c++) {
                    const int j = 3 * tet[a] + c;
                    mdv[j] += m * (v1[j] - v[j] + sum[c]);
                }
        }
        for (int i = 0; st->sc->pmass && i < st->nv; i++)
            for (int c = 0; c < 3; c++) mdv[3 * i + c] += st->sc->pmass[i] * (v1[3 * i + c] - v[3 * i + c]);
    }
    double dw = 0;
    for (int q = 0; q < st->nv; q++) {
        if (st->vbc[q] < 0) continue;
        for (int k = 0; k < 3; k++) {
            const int j = 3 * q + k;
            if (!eo_stepi_fixed(st, st->vbc, j)) continue;
            dw += 0.5 * (st->rpot[j] + st->rpot1[j]) * (x1[j] - x[j]) + 0.5 * (v[j] + v1[j]) * mdv[j];
        }
    }
    st->work += dw;
    double *tmp = st->rpot; /* the reaction at xₙ₊₁ is the next step's at xₙ */
    st->rpot = st->rpot1;
    st->rpot1 = tmp;
    st->rpot_valid = 1;
}

int eo_step_fields(eo_step *st, double *psi, double *J, unsigned char *inverted)
{
    for (int k = 0; k < st->nt; k++) {
        double Jk = eo_stepi_tet_J(st, st->x, k), p = 0;
        if (psi && !(st->tet_type[k]->flags & EO_MATERIAL_EDGE) && !st->sys.linear) {
            /* a general element: its mean ψ, energy / V */
            const int n = st->sys.npe, *en = st->sys.enodes + (size_t)n * k;
            double xe[3 * EO_ELEMENT_MAX_NODES], e;
            for (int a = 0; a < n; a++)
                for (int c = 0; c < 3; c++) xe[3 * a + c] = st->x[3 * en[a] + c];
            eo_element_evaluate(st->sys.el, st->tet_type[k], st->tet_coef[k], st->Dminv + 9 * k, st->vol[k], xe,
                                EO_EVAL_ENERGY, EO_PROJ_NONE, &e, NULL, NULL, NULL);
            p = e / st->vol[k] - st->psi_rest[k];
        } else if (psi && !(st->tet_type[k]->flags & EO_MATERIAL_EDGE)) {
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
