/* Gravity term: −w · f_gᵀx with f_g = M g.
 *
 * For a constant field g the consistent and the lumped mass give the same force: each
 * row of M_t = ρV/20 (I₄ + 𝟙𝟙ᵀ) ⊗ I₃ sums to ρV/20 · 5 = ρV/4, so f_g on vertex v is
 * m_v g with m_v = Σ_{t∋v} ρₜVₜ/4. Other elements (element.h): f = M g with the scene's
 * mass matrix, so that a free body falls uniformly: the consistent load ρ∫N_v dV g (P2:
 * −ρV/20 at corners, ρV/5 at midside nodes) with the consistent mass, the lumped masses'
 * m_v g with the lumped one. Both in s->vload. Linear in x: no Hessian. */
#include "elastopt/step.h"
#include "term.h"

typedef struct gravity_data {
    double g[3];
} gravity_data;

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    const gravity_data *d = t->data;
    double e = 0;
    for (int v = 0; v < s->nv; v++)
        if (eo_sys_vertex_on(s, v)) e -= s->vload[v] * (d->g[0] * x[3 * v] + d->g[1] * x[3 * v + 1] + d->g[2] * x[3 * v + 2]);
    return t->weight * e;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *grad)
{
    const gravity_data *d = t->data;
    for (int v = 0; v < s->nv; v++)
        for (int c = 0; c < 3 && eo_sys_vertex_on(s, v); c++) grad[3 * v + c] -= t->weight * s->vload[v] * d->g[c];
    return energy(t, s, x);
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    (void)t, (void)s, (void)x, (void)proj;
    return EO_OK;
}

static double vertex(eo_term *t, const eo_sys *s, const double *x, int v, eo_proj proj, double *g3, double *H3)
{
    (void)proj, (void)H3;
    const gravity_data *d = t->data;
    double e = 0;
    for (int c = 0; c < 3; c++) {
        e -= t->weight * s->vload[v] * d->g[c] * x[3 * v + c];
        if (g3) g3[c] -= t->weight * s->vload[v] * d->g[c];
    }
    return e;
}

static void destroy(eo_term *t, eo_ctx *ctx) { eo_free(ctx, t->data); }

static const eo_term_ops gravity_ops = {
    .name = "gravity",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .destroy = destroy,
    .vertex = vertex,
};

int eo_term_gravity_create(eo_sys *s, const double g[3], eo_term **out)
{
    int rc = eo_term_alloc(s, &gravity_ops, 0, out);
    if (rc < 0) return rc;
    gravity_data *d = eo_malloc(s->ctx, sizeof *d);
    if (!d) {
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory");
    }
    for (int c = 0; c < 3; c++) d->g[c] = g[c];
    (*out)->data = d;
    return EO_OK;
}

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)cfg;
    *out = NULL;
    const double *g = sc->opts.gravity;
    return g[0] != 0 || g[1] != 0 || g[2] != 0 ? eo_term_gravity_create(s, g, out) : EO_OK;
}

const eo_term_type eo_term_type_gravity = {
    .info = {.name = "gravity", .summary = "gravity −f_gᵀx, f_g = M g (scene key `gravity`; ramped by time.load_steps)"},
    .flags = EO_TERM_POTENTIAL | EO_TERM_GRAVITY | EO_TERM_LOAD_STEPPED,
    .create = type_create,
};
