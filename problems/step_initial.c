/* Initial state of the step engine (eo_step_reset: the scene's `initial` transform,
 * velocity and ball of random points, constrained vertices at their prescribed state)
 * and eo_step_set_state. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "step_impl.h"

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

/* A barrier material (ψ = +∞ at J <= 0) cannot start from an inverted tet: the step
 * problem would be infinite at its start and every optimizer would stop at once with a
 * non-finite state. Refuse it here, naming the region, the first tet and the cause. */
static int check_barrier_start(const eo_step *st)
{
    const eo_scene *sc = st->sc;
    int count = 0, first = -1;
    double Jfirst = 0;
    for (int k = 0; k < st->nt; k++) {
        if (!(st->tet_type[k]->flags & EO_MATERIAL_BARRIER)) continue;
        double J = eo_stepi_tet_J(st, st->x, k);
        if (!eo_tet_is_inverted(J)) continue;
        if (count++ == 0) {
            first = k;
            Jfirst = J;
        }
    }
    if (!count) return EO_OK;
    int r = sc->tet_mat ? sc->tet_mat[first] : 0;
    char where[32];
    if (r == 0) snprintf(where, sizeof where, "material");
    else snprintf(where, sizeof where, "materials.%d", r - 1);
    const char *cause = sc->has_ball      ? " (initial.random_ball)"
                        : sc->has_reflect ? " (initial.reflect)"
                                          : (sc->initial.scale[0] * sc->initial.scale[1] * sc->initial.scale[2] <= 0
                                                 ? " (initial.scale)"
                                                 : "");
    return eo_error(st->ctx, EO_ERR_RANGE,
                    "%s: the initial state%s has %d inverted tet(s) (first: tet %d, J = %.3g) and %s (%s) is a "
                    "barrier material, infinite at J <= 0; start from a non-inverted state or use a "
                    "model without a barrier (elastopt list: materials)",
                    sc->file, cause, count, first, Jfirst, where, st->tet_type[first]->info.name);
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
    st->inv_valid = 0;
    st->index = 0;
    /* constrained vertices start at their prescribed state */
    eo_stepi_active_set(st, 0, st->vbc_new);
    for (int v = 0; v < st->nv; v++) {
        if (st->vbc_new[v] < 0) continue;
        double p[3], vel[3];
        eo_stepi_bc_motion(st, st->sc->bc + st->vbc_new[v], v, 0, p, vel);
        for (int k = 0; k < 3; k++) {
            if (!st->sc->bc[st->vbc_new[v]].mask[k]) continue;
            st->x[3 * v + k] = p[k];
            st->v[3 * v + k] = st->integ->inertia ? vel[k] : 0;
        }
    }
    if (!st->integ->inertia) memset(st->v, 0, (size_t)st->n_full * sizeof(double));
    st->erestart = 1;
    st->hist_valid = 0;
    st->work = 0;
    st->rpot_valid = 0;
    st->sub_level = 0; /* nominal steps again */
    st->h = st->h_nom;
    st->sub_done = 0;
    return check_barrier_start(st);
}

int eo_step_set_state(eo_step *st, const double *x, const double *v, double t)
{
    memcpy(st->x, x, (size_t)st->n_full * sizeof(double));
    memcpy(st->v, v, (size_t)st->n_full * sizeof(double));
    if (t == 0) /* a state at t = 0 is the initial state: the prescribed motions start from it */
        memcpy(st->x0, x, (size_t)st->n_full * sizeof(double));
    st->t = t;
    st->inv_valid = 0;
    st->erestart = 1;
    st->hist_valid = 0;
    st->rpot_valid = 0; /* the work so far (st->work) is kept */
    st->sub_level = 0; /* at a nominal step boundary, nominal steps (eo_step_set_substep) */
    st->h = st->h_nom;
    st->sub_done = 0;
    return EO_OK;
}


int eo_step_set_index(eo_step *st, int index)
{
    st->index = index;
    return EO_OK;
}
