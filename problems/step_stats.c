/* Diagnostics of the step engine's current state: eo_step_stats (centre of mass,
 * displacement, det F range, inverted tets, kinetic, elastic and gravity energy) and
 * the per-tet fields written to the frames. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "step_impl.h"

/* ---------------------------------------------------------------- small math */

static double det3(const double A[9])
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* det F of tet k at positions x: det(Ds)·det(Dm⁻¹). */
double eo_stepi_tet_J(const eo_step *st, const double *x, int k)
{
    const int *tet = st->sc->mesh->tets + 4 * k;
    double Ds[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) Ds[3 * r + c] = x[3 * tet[c] + r] - x[3 * tet[3] + r];
    return det3(Ds) * det3(st->Dminv + 9 * k);
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
        double J = eo_stepi_tet_J(st, x, k);
        if (J < s->min_J) s->min_J = J;
        if (J > s->max_J) s->max_J = J;
        s->inverted += J <= 0;
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
        double Jk = eo_stepi_tet_J(st, st->x, k), p = 0;
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
        if (inverted) inverted[k] = Jk <= 0;
    }
    return EO_OK;
}
