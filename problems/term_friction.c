/* Friction term: Coulomb friction against the static obstacles with friction μ > 0,
 * penalty-regularized and lagged as in Incremental Potential Contact (Li et al. 2020,
 * §5: lagged normal forces and tangent bases, the smoothed friction f₁), for the
 * implicit integrators. At the start of each step (eo_term_friction_lag, from xₙ, vₙ)
 * every vertex v inside an obstacle o becomes a contact with
 *
 *     λ = k d(xₙ)      the penalty normal force magnitude at xₙ (N), kept for the step,
 *     n = n(xₙ)        the outward normal there, P = I − n nᵀ, kept for the step.
 *
 * The slip is measured by the step's own end-of-step velocity (BDF2's uses xₙ₋₁): its velocity map
 * is affine, vₙ₊₁(x) = α (x − x̂) (backward Euler α = 1/h, x̂ = xₙ; Newmark α = 2/h,
 * x̂ = xₙ + h vₙ/2; found by evaluating the map twice), and
 *
 *     u(x) = h P vₙ₊₁,v(x) = s P (x_v − x̂_v),  s = hα,  y = |u|  (the tangential slip),
 *     D(x) = Σ_contacts μ λ f₀(y) / s,   f₀' = f₁,   ε = ε_v h (eps_v of the obstacle),
 *     f₁(y) = 2y/ε − y²/ε² for y < ε, 1 otherwise;  f₀(y) = y²/ε − y³/(3ε²), y − ε/3;
 *
 * so −∇_v D = −μ λ f₁(y) u/y: the friction force opposes the slip velocity with
 * magnitude μλ once the slip speed exceeds ε_v, and grows smoothly (C¹) from 0 below
 * it (sticking is creep slower than ε_v). With φ(y) = f₁(y)/y:
 *     ∇_v D = μ λ φ u,    ∇²_v D = s μ λ (φ P + (φ'/y) u uᵀ),
 *     y < ε: φ = 2/ε − y/ε², φ'/y = −1/(ε² y);   y ≥ ε: φ = 1/y, φ'/y = −1/y³,
 * with eigenvalues sμλ(2/ε − 2y/ε²) ≥ 0 (along u, y < ε), 0 (along u, y ≥ ε), sμλφ > 0
 * (in P across u) and 0 along n: PSD, no projection needed.
 *
 * Weight: the friction force acts at tₙ₊₁ only, fully implicit: the term weight is the
 * integrator's w, doubled for integrators whose linear term carries fₙ (Newmark's
 * trapezoidal rule weighs fₙ and fₙ₊₁ with w each; a lagged friction force at tₙ does not
 * exist). Measuring the slip by vₙ₊₁ rather than by xₙ₊₁ − xₙ (which is h(vₙ + vₙ₊₁)/2
 * under Newmark) keeps the sticking regime, a stiff damper, from ringing under the
 * trapezoidal rule. Lagging makes D a function of x alone within a step (IPC's lagged
 * iteration done once per step): contacts that start during a step get friction from the
 * next step on. */
#include <math.h>
#include <string.h>

#include "elastopt/step.h"
#include "obstacle.h"
#include "term.h"

typedef struct contact {
    int v;
    double mul;                    /* μ λ, N */
    double eps;                    /* ε = ε_v h, m */
    double n[3];
} contact;

typedef struct friction_data {
    int nob;
    const eo_scene_obstacle *ob;   /* borrowed (the scene's) */
    int cap, nc;
    contact *c;                    /* cap = (obstacles with friction) · nv */
    double *xa;                    /* n_full: the anchor x̂ (vₙ₊₁(x̂) = 0) */
    double *work;                  /* n_full */
    double *va;                    /* n_full: vₙ₊₁(xₙ + 1) */
    double s;                      /* hα */
    double wfac;                   /* 2 with a linear term fₙ (Newmark), else 1 */
    int n_full;
    int group;
    int *dofs;                     /* 3·nv free ids */
} friction_data;

/* y, u of contact c at x; returns y */
static double slip(const friction_data *d, const contact *c, const double *x, double u[3])
{
    double r[3], rn = 0, y = 0;
    for (int k = 0; k < 3; k++) {
        r[k] = d->s * (x[3 * c->v + k] - d->xa[3 * c->v + k]);
        rn += r[k] * c->n[k];
    }
    for (int k = 0; k < 3; k++) {
        u[k] = r[k] - rn * c->n[k];
        y += u[k] * u[k];
    }
    return sqrt(y);
}

static double f0(double y, double eps)
{
    return y < eps ? y * y / eps - y * y * y / (3 * eps * eps) : y - eps / 3;
}

static double energy(eo_term *t, const eo_sys *s, const double *x)
{
    const friction_data *d = t->data;
    double e = 0, u[3];
    for (int i = 0; i < d->nc; i++)
        if (eo_sys_vertex_on(s, d->c[i].v)) e += d->c[i].mul * f0(slip(d, d->c + i, x, u), d->c[i].eps);
    return t->weight * d->wfac * e / d->s;
}

static double gradient(eo_term *t, const eo_sys *s, const double *x, double *g)
{
    const friction_data *d = t->data;
    const double w = t->weight * d->wfac;
    double e = 0, u[3];
    for (int i = 0; i < d->nc; i++) {
        const contact *c = d->c + i;
        if (!eo_sys_vertex_on(s, c->v)) continue;
        double y = slip(d, c, x, u);
        e += c->mul * f0(y, c->eps);
        double phi = y < c->eps ? 2 / c->eps - y / (c->eps * c->eps) : 1 / y;
        for (int k = 0; k < 3; k++) g[3 * c->v + k] += w * c->mul * phi * u[k];
    }
    return w * e / d->s;
}

static int hessian(eo_term *t, const eo_sys *s, const double *x, eo_proj proj)
{
    (void)proj; /* PSD */
    const friction_data *d = t->data;
    double He[9], u[3];
    for (int i = 0; i < d->nc; i++) {
        const contact *c = d->c + i;
        if (!eo_sys_vertex_on(s, c->v)) continue;
        double y = slip(d, c, x, u), phi, q;
        if (y < c->eps) {
            phi = 2 / c->eps - y / (c->eps * c->eps);
            q = y > 0 ? -1 / (c->eps * c->eps * y) : 0;
        } else {
            phi = 1 / y;
            q = -1 / (y * y * y);
        }
        const double a = t->weight * d->wfac * d->s * c->mul;
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                He[3 * r + k] = a * (phi * ((r == k) - c->n[r] * c->n[k]) + q * u[r] * u[k]);
        eo_assembler_add(s->as, d->group, c->v, He);
    }
    return EO_OK;
}

static int attach(eo_term *t, eo_sys *s)
{
    friction_data *d = t->data;
    return eo_term_attach_vertex_blocks(s, d->dofs, &d->group);
}

static void destroy(eo_term *t, eo_ctx *ctx)
{
    friction_data *d = t->data;
    if (!d) return;
    eo_free(ctx, d->c);
    eo_free(ctx, d->xa);
    eo_free(ctx, d->work);
    eo_free(ctx, d->va);
    eo_free(ctx, d->dofs);
    eo_free(ctx, d);
}

static const eo_term_ops friction_ops = {
    .name = "friction",
    .energy = energy,
    .gradient = gradient,
    .hessian = hessian,
    .attach = attach,
    .destroy = destroy,
};

void eo_term_friction_lag(eo_term *t, const eo_sys *s, const double *xn, double h, int force_n,
                          eo_velocity_map vel, const void *vctx)
{
    friction_data *d = t->data;
    const int nf = s->n_full;
    /* vₙ₊₁(x) = α (x − x̂): at x = xₙ + 1 (va) and at x = xₙ (work) */
    for (int j = 0; j < nf; j++) d->xa[j] = xn[j] + 1;
    vel(vctx, d->xa, d->va);
    vel(vctx, xn, d->work);
    const double alpha = d->va[0] - d->work[0];
    d->wfac = force_n ? 2 : 1;
    if (alpha > 0 && isfinite(alpha)) {
        d->s = h * alpha;
        for (int j = 0; j < nf; j++) d->xa[j] = xn[j] - d->work[j] / alpha;
    } else { /* no velocity (static): the slip is the displacement over the step */
        d->s = 1;
        memcpy(d->xa, xn, (size_t)nf * sizeof(double));
    }
    d->nc = 0;
    for (int o = 0; o < d->nob; o++) {
        const eo_scene_obstacle *ob = d->ob + o;
        if (!(ob->opts.friction > 0)) continue;
        for (int v = 0; v < s->nv && d->nc < d->cap; v++) {
            if (!eo_sys_vertex_once(s, v)) continue; /* a distributed run: on the vertex's owner */
            contact *c = d->c + d->nc;
            double kap, dd = ob->type->depth(ob->shape, xn + 3 * v, c->n, &kap);
            if (!(dd > 0)) continue;
            c->v = v;
            c->mul = ob->opts.friction * ob->opts.stiffness * dd;
            c->eps = ob->opts.eps_v * h;
            d->nc++;
        }
    }
}

int eo_term_friction_create(eo_sys *s, int nob, const eo_scene_obstacle *ob, eo_term **out)
{
    *out = NULL;
    int nf = 0;
    for (int o = 0; o < nob; o++) nf += ob[o].opts.friction > 0;
    if (!nf || s->nv < 1) return EO_OK;
    int rc = eo_term_alloc(s, &friction_ops, 0, out);
    if (rc < 0) return rc;
    friction_data *d = eo_calloc(s->ctx, 1, sizeof *d);
    if (d) {
        d->nob = nob;
        d->ob = ob;
        d->cap = nf * s->nv;
        d->n_full = s->n_full;
        d->c = eo_malloc(s->ctx, (size_t)d->cap * sizeof *d->c);
        d->xa = eo_calloc(s->ctx, (size_t)s->n_full, sizeof(double));
        d->work = eo_calloc(s->ctx, (size_t)s->n_full, sizeof(double));
        d->va = eo_calloc(s->ctx, (size_t)s->n_full, sizeof(double));
        d->s = d->wfac = 1;
        d->dofs = eo_malloc(s->ctx, (size_t)s->n_full * sizeof(int));
    }
    (*out)->data = d;
    if (!d || !d->c || !d->xa || !d->work || !d->va || !d->dofs) {
        eo_term_destroy(s->ctx, out);
        return eo_error(s->ctx, EO_ERR_NOMEM, "out of memory (friction)");
    }
    return EO_OK;
}

static int type_create(eo_sys *s, const eo_scene *sc, const void *cfg, eo_term **out)
{
    (void)cfg;
    *out = NULL;
    if (!sc->integrator->explicit_step) return eo_term_friction_create(s, sc->ncollision, sc->collision, out);
    for (int o = 0; o < sc->ncollision; o++)
        if (sc->collision[o].opts.friction > 0)
            return eo_error(s->ctx, EO_ERR_INVALID,
                            "collisions.%d.friction acts in implicit integrators only (a lagged potential of the step "
                            "problem); %s is explicit", o, sc->integrator->info.name);
    return EO_OK;
}

const eo_term_type eo_term_type_friction = {
    .info = {.name = "friction", .summary = "lagged smoothed Coulomb friction against the obstacles with `collisions.N.friction` > 0"},
    .flags = EO_TERM_LAGGED | EO_TERM_NO_PD,
    .create = type_create,
};
