/* Collision term: penalty forces against half-space obstacles (001 §2.7),
 *
 *     E_c(x) = Σ_planes Σ_vertices (k/2) · max(0, −(x_v − p)·n)²,
 *
 * p a point of the plane, n its unit normal pointing to the free side, k the plane's
 * stiffness in N/m PER VERTEX (not mass-weighted: a vertex pushed into the plane by a
 * force F rests at penetration d = F/k, e.g. m_v g/k under its own weight; refine the
 * mesh and the total contact stiffness grows with the number of touching vertices).
 * With d = −(x_v − p)·n > 0 (penetrating):
 *     ∇_v E = −k d n,   ∇²_v E = k n nᵀ   (PSD, rank one);
 * zero otherwise. E is C¹ with a jump of the Hessian at d = 0. The term is weighted by
 * the integrator's w like every potential, and absent when the scene has no
 * `collisions` (a scene without obstacles pays nothing). */
#include <math.h>

#include "term.h"

typedef struct collision_data {
    int np;
    double *plane;   /* 6·np: point, unit normal */
    double *k;       /* np */
    int group;       /* one 3-dof element per vertex */
    int *dofs;       /* 3·nv free ids */
} collision_data;

static double depth(const double *pl, const double *xv)
{
    return -((xv[0] - pl[0]) * pl[3] + (xv[1] - pl[1]) * pl[4] + (xv[2] - pl[2]) * pl[5]);
}

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    const collision_data *d = t->data;
    double e = 0;
    for (int p = 0; p < d->np; p++)
        for (int v = 0; v < s->nv; v++) {
            double dd = depth(d->plane + 6 * p, x + 3 * v);
            if (dd > 0) e += 0.5 * d->k[p] * dd * dd;
        }
    return t->weight * e;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    const collision_data *d = t->data;
    double e = 0;
    for (int p = 0; p < d->np; p++) {
        const double *pl = d->plane + 6 * p;
        for (int v = 0; v < s->nv; v++) {
            double dd = depth(pl, x + 3 * v);
            if (!(dd > 0)) continue;
            e += 0.5 * d->k[p] * dd * dd;
            for (int c = 0; c < 3; c++) g[3 * v + c] -= t->weight * d->k[p] * dd * pl[3 + c];
        }
    }
    return t->weight * e;
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    (void)proj; /* k n nᵀ is PSD already */
    const collision_data *d = t->data;
    double He[9];
    for (int p = 0; p < d->np; p++) {
        const double *n = d->plane + 6 * p + 3;
        for (int v = 0; v < s->nv; v++) {
            if (!(depth(d->plane + 6 * p, x + 3 * v) > 0)) continue;
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) He[3 * i + j] = t->weight * d->k[p] * n[i] * n[j];
            eo_assembler_add(s->as, d->group, v, He);
        }
    }
    return EO_OK;
}

static int attach(eo_term *t, eo_sys *s)
{
    collision_data *d = t->data;
    for (int j = 0; j < s->n_full; j++) d->dofs[j] = s->full2free[j];
    int h = eo_assembler_add_elements(s->ctx, s->as, s->nv, 3, d->dofs);
    if (h < 0) return h;
    d->group = h;
    return EO_OK;
}

static void destroy(eo_term *t, eo_ctx *ctx)
{
    collision_data *d = t->data;
    if (!d) return;
    eo_free(ctx, d->plane);
    eo_free(ctx, d->k);
    eo_free(ctx, d->dofs);
    eo_free(ctx, d);
}

static const eo_term_ops collision_ops = {
    .name = "collision",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .attach = attach,
    .destroy = destroy,
};

int eo_term_collision_create(eo_sys *s, int nplanes, const double *planes, const double *k, eo_term **out)
{
    *out = NULL;
    if (nplanes <= 0) return EO_OK;
    int rc = eo_term_alloc(s, &collision_ops, 0, out);
    if (rc < 0) return rc;
    collision_data *d = eo_calloc(s->ctx, 1, sizeof *d);
    if (d) {
        d->np = nplanes;
        d->plane = eo_malloc(s->ctx, 6 * (size_t)nplanes * sizeof(double));
        d->k = eo_malloc(s->ctx, (size_t)nplanes * sizeof(double));
        d->dofs = eo_malloc(s->ctx, (size_t)(s->n_full > 0 ? s->n_full : 1) * sizeof(int));
    }
    (*out)->data = d;
    if (!d || !d->plane || !d->k || !d->dofs) {
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (collisions)");
    }
    for (int p = 0; p < nplanes; p++) {
        for (int c = 0; c < 6; c++) d->plane[6 * p + c] = planes[6 * p + c];
        d->k[p] = k[p];
    }
    return EO_OK;
}
