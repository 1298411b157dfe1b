/* The distributed view of a part's objective: what the library's optimizers minimize when
 * the problem is spread over processes (ctx.h eo_dist_hooks; the PETSc backend).
 *
 * The part's objective (a step objective on the part's local mesh) gives this part's
 * terms only: its g, ∇g and Hessian summed over the parts are the whole problem's. The
 * view has the same n local entries (objective.h, eo_vspace: owned entries and copies of
 * other parts' ones) and gives
 *   value           g summed over the parts (+INFINITY if any part's is)
 *   gradient        ∇g assembled: the parts' partial gradients summed at every copy
 *   hessian         this part's terms (a partial matrix: only a linear solver that takes
 *                   one, eo_linsolve_set_space, solves with it)
 *   hessian_masked, n_elements, element_residual   this part's elements
 *   metric_diag     assembled like ∇g
 *   inverted_count  summed; max_step: the smallest over the parts
 *   rounding_scale  the parts' scales summed (sums over elements and vertices)
 *   characteristic  ‖a‖₂ from the parts' squares, the volume-weighted stiffness
 *   constant_hessian  this part's terms of L, like the Hessian (lbfgs h0 = pd, ncg
 *                   precond = pd factor it with the distributed linear solver)
 * and nothing else (the objective's own factor of L, vertex blocks, split ops, inertia: the
 * optimizers that need them are refused at configuration, solvers/solver.c). Every operation is collective and
 * called by every part with the same decisions, since the optimizers decide on values
 * reduced over the parts. */
#include <math.h>
#include <string.h>

#include "dist_objective.h"

static int fail_all(const eo_vspace *s, int rc)
{
    double bad = rc < 0;
    eo_vreduce(s, &bad, 1, EO_REDUCE_MAX);
    return bad != 0 ? (rc < 0 ? rc : EO_ERR_INVALID) : EO_OK;
}

static double sum_value(const eo_vspace *s, double g)
{
    double v[2] = {isfinite(g) ? g : 0, isfinite(g) ? 0 : 1};
    eo_vreduce(s, v, 2, EO_REDUCE_SUM);
    return v[1] > 0 || isnan(v[0]) ? INFINITY : v[0];
}

static int dv_value(void *data, const double *x, double *g)
{
    eo_dist_view *v = data;
    double gl = INFINITY;
    int rc = eo_objective_value(v->local, x, &gl);
    if ((rc = fail_all(v->space, rc)) < 0) return rc;
    *g = sum_value(v->space, gl);
    return EO_OK;
}

static int dv_gradient(void *data, const double *x, double *g, double *grad)
{
    eo_dist_view *v = data;
    double gl = INFINITY;
    int rc = eo_objective_gradient(v->local, x, &gl, grad);
    if (rc < 0 || !isfinite(gl))
        for (int i = 0; i < v->obj.n; i++) grad[i] = 0;
    if ((rc = fail_all(v->space, rc)) < 0) return rc;
    *g = sum_value(v->space, gl);
    return v->space->assemble(grad, v->space->user);
}

static int dv_hessian(void *data, const double *x, eo_proj proj, eo_csc **H)
{
    eo_dist_view *v = data;
    return fail_all(v->space, eo_objective_hessian(v->local, x, proj, H));
}

static int dv_hessian_masked(void *data, const double *x, const unsigned char *proj_of, eo_csc **H)
{
    eo_dist_view *v = data;
    return fail_all(v->space, eo_objective_hessian_masked(v->local, x, proj_of, H));
}

static int dv_n_elements(void *data) { return eo_objective_n_elements(((eo_dist_view *)data)->local); }

static int dv_element_residual(void *data, const double *vec, double *r)
{
    return eo_objective_element_residual(((eo_dist_view *)data)->local, vec, r);
}

static int dv_metric_diag(void *data, double *d)
{
    eo_dist_view *v = data;
    eo_objective *l = v->local;
    int rc = l->ops->metric_diag ? l->ops->metric_diag(l->data, d) : EO_ERR_UNSUPPORTED;
    if (rc < 0)
        for (int i = 0; i < v->obj.n; i++) d[i] = NAN;
    if ((rc = fail_all(v->space, rc)) < 0) return rc;
    return v->space->assemble(d, v->space->user);
}

static int dv_inverted_count(void *data, const double *x)
{
    eo_dist_view *v = data;
    eo_objective *l = v->local;
    double c = l->ops->inverted_count(l->data, x);
    eo_vreduce(v->space, &c, 1, EO_REDUCE_SUM);
    return isfinite(c) ? (int)c : -1;
}

static int dv_max_step(void *data, const double *x, const double *p, double *alpha_max)
{
    eo_dist_view *v = data;
    double a = INFINITY;
    int rc = eo_objective_max_step(v->local, x, p, &a);
    if ((rc = fail_all(v->space, rc)) < 0) return rc;
    eo_vreduce(v->space, &a, 1, EO_REDUCE_MIN);
    *alpha_max = a;
    return EO_OK;
}

static int dv_rounding_scale(void *data, const double *x, double s[3])
{
    eo_dist_view *v = data;
    int rc = eo_objective_rounding_scale(v->local, x, s);
    if ((rc = fail_all(v->space, rc)) < 0) return rc;
    eo_vreduce(v->space, s, 3, EO_REDUCE_SUM);
    return EO_OK;
}

static int dv_characteristic(void *data, eo_objective_characteristic *out)
{
    eo_dist_view *v = data;
    int rc = eo_objective_characteristic_get(v->local, out);
    if ((rc = fail_all(v->space, rc)) < 0) return rc;
    /* ‖a‖₂ from the parts' squares (a vertex shared by parts counted by each), the
     * volume-weighted mean stiffness from the parts' sums */
    double sv[3] = {out->grad * out->grad, out->stiffness * out->volume, out->volume};
    eo_vreduce(v->space, sv, 3, EO_REDUCE_SUM);
    out->grad = sqrt(sv[0]);
    out->volume = sv[2];
    out->stiffness = sv[2] > 0 ? sv[1] / sv[2] : out->stiffness;
    return EO_OK;
}

/* The part's constant matrix L (its elements' terms, like the Hessian: a linear solver
 * that takes parts factors it); a new version on any part is a new version for all. */
static int dv_constant_hessian(void *data, eo_csc **L, unsigned long *version)
{
    eo_dist_view *v = data;
    int rc = eo_objective_constant_hessian(v->local, L, version);
    if ((rc = fail_all(v->space, rc)) < 0) return rc;
    double ver = (double)*version;
    eo_vreduce(v->space, &ver, 1, EO_REDUCE_MAX);
    *version = (unsigned long)ver;
    return EO_OK;
}

int eo_dist_view_consistent(const eo_vspace *s, double *x)
{
    for (int i = 0; i < s->n; i++)
        if (!s->own[i]) x[i] = 0;
    return s->assemble(x, s->user);
}

int eo_dist_view_init(eo_dist_view *v, eo_ctx *ctx, eo_objective *local)
{
    const eo_dist_hooks *h = eo_ctx_dist(ctx);
    if (!h || !h->space)
        return eo_error(ctx, EO_ERR_UNSUPPORTED, "solver: a distributed problem needs a backend that numbers its "
                        "vectors over the processes (solver.backend=petsc)");
    const eo_vspace *s = NULL;
    int rc = h->space(ctx, local, &s, h->user);
    if (rc < 0) return rc;
    if (!s || s->n != local->n || !s->own || !s->assemble || !s->reduce)
        return eo_error(ctx, EO_ERR_INVALID, "solver: the backend's vector space does not fit the objective "
                        "(n = %d, space n = %d)", local->n, s ? s->n : -1);
    static const eo_objective_ops all = {
        .value = dv_value, .gradient = dv_gradient, .hessian = dv_hessian, .metric_diag = dv_metric_diag,
        .inverted_count = dv_inverted_count, .n_elements = dv_n_elements, .hessian_masked = dv_hessian_masked,
        .element_residual = dv_element_residual, .rounding_scale = dv_rounding_scale, .max_step = dv_max_step,
        .characteristic = dv_characteristic, .constant_hessian = dv_constant_hessian};
    v->ctx = ctx;
    v->local = local;
    v->space = s;
    /* the optional ops where the part's objective has them (the same on every part: the
     * same kind of objective) */
    const eo_objective_ops *lo = local->ops;
    v->ops = all;
    if (!lo->metric_diag) v->ops.metric_diag = NULL;
    if (!lo->inverted_count) v->ops.inverted_count = NULL;
    if (!lo->n_elements || !lo->hessian_masked || !lo->element_residual)
        v->ops.n_elements = NULL, v->ops.hessian_masked = NULL, v->ops.element_residual = NULL;
    if (!lo->rounding_scale) v->ops.rounding_scale = NULL;
    if (!lo->max_step) v->ops.max_step = NULL;
    if (!lo->characteristic) v->ops.characteristic = NULL;
    if (!lo->constant_hessian) v->ops.constant_hessian = NULL;
    v->obj = (eo_objective){.n = local->n, .ops = &v->ops, .data = v, .space = s};
    return EO_OK;
}
