/* Collision term: penalty forces against static obstacles (001 §2.7; shapes in
 * obstacle.h: plane, sphere, box),
 *
 *     E_c(x) = Σ_obstacles Σ_vertices (k/2) · max(0, d(x_v))²,
 *
 * d the obstacle's penetration depth (plane: −(x − p)·n; sphere: r − |x − c|; box: the
 * distance to the nearest face), k the obstacle's stiffness in N/m PER VERTEX (not
 * mass-weighted: a vertex pushed into a plane by a force F rests at depth d = F/k, e.g.
 * m_v g/k under its own weight; refine the mesh and the total contact stiffness grows
 * with the number of touching vertices). With d > 0, n = −∇d the outward normal and
 * ∇²d = −κ (I − n nᵀ):
 *     ∇_v E = −k d n,   ∇²_v E = k n nᵀ − k d κ (I − n nᵀ);
 * zero otherwise. The tangential eigenvalue −k d κ (a sphere: κ = 1/ρ) is negative:
 * EO_PROJ_CLAMP drops it, EO_PROJ_ABS flips it; planes and boxes are PSD already. E is C¹
 * with a jump of the Hessian at d = 0. The term is weighted by the integrator's w like
 * every potential, and absent when the scene has no `collisions`. The obstacle list is
 * borrowed from the scene. */
#include <math.h>

#include "obstacle.h"
#include "elastopt/step.h"
#include "term.h"

typedef struct collision_data {
    int nob;
    const eo_scene_obstacle *ob;   /* borrowed (the scene's) */
    int group;                     /* one 3-dof element per vertex */
    int *dofs;                     /* 3·nv free ids */
} collision_data;

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    const collision_data *d = t->data;
    double e = 0, n[3], kap;
    for (int o = 0; o < d->nob; o++) {
        const eo_scene_obstacle *ob = d->ob + o;
        for (int v = 0; v < s->nv; v++) {
            if (!eo_sys_vertex_once(s, v)) continue;
            double dd = ob->type->depth(ob->shape, x + 3 * v, n, &kap);
            if (dd > 0) e += 0.5 * ob->opts.stiffness * dd * dd;
        }
    }
    return t->weight * e;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    const collision_data *d = t->data;
    double e = 0, n[3], kap;
    for (int o = 0; o < d->nob; o++) {
        const eo_scene_obstacle *ob = d->ob + o;
        const double k = ob->opts.stiffness;
        for (int v = 0; v < s->nv; v++) {
            if (!eo_sys_vertex_once(s, v)) continue;
            double dd = ob->type->depth(ob->shape, x + 3 * v, n, &kap);
            if (!(dd > 0)) continue;
            e += 0.5 * k * dd * dd;
            for (int c = 0; c < 3; c++) g[3 * v + c] -= t->weight * k * dd * n[c];
        }
    }
    return t->weight * e;
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    const collision_data *d = t->data;
    double He[9], n[3], kap;
    for (int o = 0; o < d->nob; o++) {
        const eo_scene_obstacle *ob = d->ob + o;
        const double k = t->weight * ob->opts.stiffness;
        for (int v = 0; v < s->nv; v++) {
            if (!eo_sys_vertex_once(s, v)) continue;
            double dd = ob->type->depth(ob->shape, x + 3 * v, n, &kap);
            if (!(dd > 0)) continue;
            /* eigenvalues k (n) and lt = −k d κ (tangent plane) */
            double lt = -k * dd * kap;
            if (proj == EO_PROJ_CLAMP && lt < 0) lt = 0;
            if (proj == EO_PROJ_ABS) lt = fabs(lt);
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) He[3 * i + j] = (k - lt) * n[i] * n[j] + (i == j ? lt : 0);
            eo_assembler_add(s->as, d->group, v, He);
        }
    }
    return EO_OK;
}

static double vertex(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3)
{
    (void)s;
    const collision_data *d = t->data;
    double e = 0, n[3], kap;
    for (int o = 0; o < d->nob; o++) {
        const eo_scene_obstacle *ob = d->ob + o;
        const double k = t->weight * ob->opts.stiffness;
        double dd = ob->type->depth(ob->shape, x + 3 * v, n, &kap);
        if (!(dd > 0)) continue;
        e += 0.5 * k * dd * dd;
        if (g3)
            for (int c = 0; c < 3; c++) g3[c] -= k * dd * n[c];
        if (H3) {
            double lt = -k * dd * kap;
            if (proj == EO_PROJ_CLAMP && lt < 0) lt = 0;
            if (proj == EO_PROJ_ABS) lt = fabs(lt);
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) H3[3 * i + j] += (k - lt) * n[i] * n[j] + (i == j ? lt : 0);
        }
    }
    return e;
}

static int attach(eo_term *t, eo_sys *s)
{
    collision_data *d = t->data;
    return eo_term_attach_vertex_blocks(s, d->dofs, &d->group);
}

static void destroy(eo_term *t, eo_ctx *ctx)
{
    collision_data *d = t->data;
    if (!d) return;
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
    .vertex = vertex,
};

int eo_term_collision_create(eo_sys *s, int nob, const eo_scene_obstacle *ob, eo_term **out)
{
    *out = NULL;
    if (nob <= 0) return EO_OK;
    int rc = eo_term_alloc(s, &collision_ops, 0, out);
    if (rc < 0) return rc;
    collision_data *d = eo_calloc(s->ctx, 1, sizeof *d);
    if (d) {
        d->nob = nob;
        d->ob = ob;
        d->dofs = eo_malloc(s->ctx, (size_t)(s->n_full > 0 ? s->n_full : 1) * sizeof(int));
    }
    (*out)->data = d;
    if (!d || !d->dofs) {
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (collisions)");
    }
    return EO_OK;
}

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)cfg;
    return eo_term_collision_create(s, sc->ncollision, sc->collision, out);
}

const eo_term_type eo_term_type_collision = {
    .info = {.name = "collision", .summary = "penalty contact with the static obstacles of `collisions`"},
    .flags = EO_TERM_POTENTIAL | EO_TERM_CONTACT | EO_TERM_NO_PD,
    .create = type_create,
};
