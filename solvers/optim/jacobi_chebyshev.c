/* Block-Jacobi iteration with Chebyshev semi-iterative acceleration (registry key
 * "jacobi_chebyshev").
 *
 * Paper       Wang, "A Chebyshev Semi-Iterative Approach for Accelerating Projective and
 *             Position-based Dynamics", ACM TOG 34(6), 2015: a Jacobi-type iteration whose
 *             error contracts like a linear one is accelerated by the Chebyshev weights
 *             ω₁ = … = ω_S = 1, ω_{S+1} = 2/(2 − ρ²), ω_{k+1} = 4/(4 − ρ²ω_k)
 *             (chebyshev.h), x⁽ᵏ⁺¹⁾ = ω(γ(x̂ − x⁽ᵏ⁾) + x⁽ᵏ⁾ − x⁽ᵏ⁻¹⁾) + x⁽ᵏ⁻¹⁾.
 *             The paper accelerates the Jacobi solve of PD's global step; here the Jacobi
 *             iteration runs directly on the step objective g (the nonlinear block-Jacobi
 *             / diagonal Newton iteration), the same semi-iterative scheme.
 * Iteration   x̂ = x − D⁻¹∇g(x), D the block diagonal of the Hessian of g at x with the
 *             element Hessians projected (`projection`, clamp by default): 3×3 blocks per
 *             vertex when the objective has vertex blocks (the step objective), else the
 *             scalar diagonal. One Hessian assembly per iteration (its diagonal blocks
 *             read through positions found once per pattern), no linear solver. A block
 *             that is not positive definite does not move.
 * Plain       accelerated = false: every ω = 1, the damped block-Jacobi iteration.
 * Relaxation  γ = `gamma` (default 2/3, the classical damped Jacobi: the undamped
 *             iteration diverges where ρ(I − D⁻¹H) > 1, as for stiff tets).
 * ρ           `rho` > 0 as given (Wang's offline estimate), or 0 (default): measured from
 *             the shrinking of the plain corrections over the delay S (chebyshev.h).
 * Restart     an accelerated iterate that raises g (or makes it non-finite) is replaced by
 *             the plain one and the acceleration restarts (S plain iterations, ρ measured
 *             again when automatic): counted in n_fallback. A plain iterate that raises g
 *             is backtracked along the Jacobi direction (γ halved up to 30 times; this
 *             iteration only), the acceleration restarting too.
 * Stopping    the configured rule through eo_solver_stop_check with ∇g at every iterate
 *             (metric gradient measure, no Newton decrement).
 * Memory      5 vectors of n in setup; the block positions per pattern (first minimize
 *             after a pattern change); nothing inside the iterations. */
#include <stddef.h>
#include <string.h>

#include "chebyshev.h"
#include "descent.h"
#include "external.h" /* eo_external_inverted */

typedef struct eo_jacobi_chebyshev_params {
    int accelerated;     /* Chebyshev weights (default true); false: the plain damped iteration */
    double rho;          /* spectral radius estimate; 0 = measured (default 0) */
    int delay;           /* S: plain iterations before the acceleration (default 10) */
    double gamma;        /* under-relaxation (default 2/3) */
    char projection[8];  /* clamp, abs, none */
} eo_jacobi_chebyshev_params;

static const char *const proj_choices[] = {"clamp", "abs", "none", NULL};

static const eo_param_desc jc_desc[] = {
    {.key = "accelerated", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_jacobi_chebyshev_params, accelerated),
     .def.i = 1, .help = "Chebyshev acceleration (false: the plain damped block-Jacobi iteration)"},
    {.key = "rho", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_jacobi_chebyshev_params, rho), .def.d = 0,
     .min = 0, .max = 1, .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "spectral radius estimate of the damped Jacobi iteration, [0, 1); 0 = measured over the delay"},
    {.key = "delay", .kind = EO_PARAM_INT, .offset = offsetof(eo_jacobi_chebyshev_params, delay), .def.i = 10,
     .min = 1, .max = 1000, .range = EO_RANGE_CLOSED, .help = "S: plain iterations before the acceleration starts"},
    {.key = "gamma", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_jacobi_chebyshev_params, gamma),
     .def.d = 2.0 / 3.0, .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX,
     .help = "under-relaxation gamma of the Jacobi step, (0, 1]"},
    {.key = "projection", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_jacobi_chebyshev_params, projection),
     .size = sizeof(((eo_jacobi_chebyshev_params *)0)->projection), .def.s = "clamp", .choices = proj_choices,
     .help = "element Hessians projected before the diagonal blocks are taken: clamp, abs or none"},
    {0},
};

typedef struct jc_state {
    int n;
    double *buf, *grad, *gt, *d, *xm1, *xt;
    /* diagonal blocks: nb blocks of dofs (3 each, -1 unused), positions of their 9
     * entries in the Hessian's values (-1: none) */
    int nb, *dofs, *pos;
    unsigned long version;
    int have_pos, scalar;
} jc_state;

static void jc_free_pos(jc_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->dofs);
    eo_free(ctx, st->pos);
    st->dofs = st->pos = NULL;
    st->have_pos = 0;
}

static void jc_destroy(void *vst, eo_ctx *ctx)
{
    jc_state *st = vst;
    eo_free(ctx, st->buf);
    st->buf = NULL;
    jc_free_pos(st, ctx);
}

static int jc_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    (void)params;
    jc_state *st = vst;
    jc_destroy(st, ctx);
    memset(st, 0, sizeof *st);
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "jacobi_chebyshev: n = %d < 0", n);
    const size_t nn = (size_t)(n > 0 ? n : 1);
    st->buf = eo_calloc(ctx, 5 * nn, sizeof(double));
    if (!st->buf) return eo_error(ctx, EO_ERR_NOMEM, "jacobi_chebyshev: out of memory (n = %d)", n);
    st->grad = st->buf;
    st->gt = st->buf + nn;
    st->d = st->buf + 2 * nn;
    st->xm1 = st->buf + 3 * nn;
    st->xt = st->buf + 4 * nn;
    st->n = n;
    return EO_OK;
}

/* The blocks (vertex blocks, else one per variable) and where their entries lie in H. */
static int jc_positions(jc_state *st, eo_objective *obj, const eo_csc *H, eo_ctx *ctx)
{
    jc_free_pos(st, ctx);
    eo_vertex_blocks vb = {0};
    const int have_vb = obj->ops->vertex_blocks && obj->ops->vertex_block &&
                        obj->ops->vertex_blocks(obj->data, &vb) == EO_OK;
    const int nb = have_vb ? vb.nb : st->n;
    const size_t m = (size_t)(nb > 0 ? nb : 1);
    st->dofs = eo_malloc(ctx, 3 * m * sizeof(int));
    st->pos = eo_malloc(ctx, 9 * m * sizeof(int));
    if (!st->dofs || !st->pos) return eo_error(ctx, EO_ERR_NOMEM, "jacobi_chebyshev: out of memory (%d blocks)", nb);
    for (int b = 0; b < nb; b++)
        for (int c = 0; c < 3; c++) st->dofs[3 * b + c] = have_vb ? vb.dofs[3 * b + c] : c == 0 ? b : -1;
    for (int b = 0; b < nb; b++)
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                const int di = st->dofs[3 * b + r], dj = st->dofs[3 * b + c];
                int p = -1;
                if (di >= 0 && dj >= 0) {
                    const int i = di < dj ? di : dj, j = di < dj ? dj : di; /* upper triangle */
                    for (int q = H->colptr[j]; q < H->colptr[j + 1]; q++)
                        if (H->rowind[q] == i) p = q;
                }
                st->pos[9 * b + 3 * r + c] = p;
            }
    st->nb = nb;
    st->scalar = !have_vb;
    st->version = vb.version;
    st->have_pos = 1;
    return EO_OK;
}

/* d = −D⁻¹∇g blockwise from the assembled H */
static void jc_direction(const jc_state *st, const eo_csc *H, const double *grad, double *d)
{
    for (int b = 0; b < st->nb; b++) {
        const int *dof = st->dofs + 3 * b, *p = st->pos + 9 * b;
        double H3[9], g3[3], d3[3];
        for (int q = 0; q < 9; q++) H3[q] = p[q] >= 0 ? H->val[p[q]] : 0;
        for (int c = 0; c < 3; c++) g3[c] = dof[c] >= 0 ? grad[dof[c]] : 0;
        eo_block3_newton(H3, g3, dof, d3);
        for (int c = 0; c < 3; c++)
            if (dof[c] >= 0) d[dof[c]] = d3[c];
    }
}

#define JC_STALL_LIMIT 20

static int jc_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    jc_state *st = vst;
    eo_jacobi_chebyshev_params def;
    const eo_jacobi_chebyshev_params *pp = params;
    if (!pp) {
        eo_params_default(jc_desc, &def);
        pp = &def;
    }
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, gn_best = INFINITY;
    int rc = EO_OK, reason = 0, k = 0, stalled = 0;
    const eo_proj proj = strcmp(pp->projection, "abs") == 0    ? EO_PROJ_ABS
                         : strcmp(pp->projection, "none") == 0 ? EO_PROJ_NONE
                                                               : EO_PROJ_CLAMP;
    const double gamma = pp->gamma;
    eo_cheb cheb;
    eo_cheb_start(&cheb, pp->rho, pp->delay);
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "jacobi_chebyshev set up for n = %d, called with %d", st->n, n);
        goto done;
    }
    rc = eo_objective_gradient(obj, x, &g, st->grad);
    if (rc < 0) goto done;
    gn = gn0 = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
    memcpy(st->xm1, x, (size_t)n * sizeof(double));
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .inverted = eo_external_inverted(sc, x), .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .step_norm = step_norm, .x_norm = eo_norm2(n, x), .tol = sc->tol};
        if (!reason && (!isfinite(g) || !isfinite(gn))) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, st->grad);
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason && stalled >= JC_STALL_LIMIT) reason = EO_DIVERGED_STAGNATED;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        eo_csc *H = NULL;
        if ((rc = eo_objective_hessian(obj, x, proj, &H)) < 0) goto done;
        if (!st->have_pos || st->scalar != !(obj->ops->vertex_blocks && obj->ops->vertex_block)) {
            if ((rc = jc_positions(st, obj, H, sc->ctx)) < 0) goto done;
        } else if (!st->scalar) {
            eo_vertex_blocks vb;
            if (obj->ops->vertex_blocks(obj->data, &vb) == EO_OK && vb.version != st->version &&
                (rc = jc_positions(st, obj, H, sc->ctx)) < 0)
                goto done;
        }
        jc_direction(st, H, st->grad, st->d);
        const double dn = eo_norm2(n, st->d);
        const double omega = pp->accelerated ? eo_cheb_next(&cheb, gamma * dn) : 1;
        double gt = NAN, a = gamma;
        int nev = 1, accel = 0;
        if (omega != 1) { /* x⁺ = ω(x + γd − x₋₁) + x₋₁ */
            for (int i = 0; i < n; i++) st->xt[i] = omega * (x[i] + gamma * st->d[i] - st->xm1[i]) + st->xm1[i];
            if ((rc = eo_objective_gradient(obj, st->xt, &gt, st->gt)) < 0) goto done;
            accel = eo_cheb_accept(g, gn, gt, eo_norm2(n, st->gt));
            if (!accel) {
                eo_cheb_restart(&cheb);
                res->n_fallback++;
            }
        }
        if (!accel) { /* the plain damped step, backtracked while it raises g */
            int ok = 0;
            for (int t = 0; t < 30 && !ok; t++) {
                if (t) a *= 0.5;
                for (int i = 0; i < n; i++) st->xt[i] = x[i] + a * st->d[i];
                nev += t > 0 || omega != 1;
                if ((rc = eo_objective_gradient(obj, st->xt, &gt, st->gt)) < 0) goto done;
                ok = isfinite(gt) && gt <= g + 1e-12 * fabs(g);
            }
            if (!ok) {
                info.ls_evals = nev;
                reason = info.reason = EO_DIVERGED_LINESEARCH;
                eo_solver_report(sc, t0, &info);
                break;
            }
            if (a != gamma) eo_cheb_restart(&cheb);
        }
        info.alpha = accel ? omega : a;
        info.ls_evals = nev;
        if (gn < gn_best) gn_best = gn;
        if (eo_solver_report(sc, t0, &info)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        double s2 = 0;
        for (int i = 0; i < n; i++) {
            const double s = st->xt[i] - x[i];
            s2 += s * s;
            st->xm1[i] = x[i];
            x[i] = st->xt[i];
        }
        step_norm = sqrt(s2);
        double *t = st->grad;
        st->grad = st->gt;
        st->gt = t;
        g_prev = g;
        g = gt;
        gn = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
        stalled = (g < g_prev || gn < gn_best) ? 0 : stalled + 1;
    }
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_jacobi_chebyshev = {
    .info = {.name = "jacobi_chebyshev",
             .summary = "damped block-Jacobi steps x - gamma D^-1 grad g with Chebyshev semi-iterative acceleration "
                        "(Wang 2015), rho measured or given, restart when g rises",
             .params = jc_desc,
             .params_size = sizeof(eo_jacobi_chebyshev_params)},
    .state_size = sizeof(jc_state),
    .needs_ops = EO_OBJ_NEEDS_VERTEX,
    .needs_linear = 0,
    .needs_hessian = 1,
    .linesearch = "none",
    .setup = jc_setup,
    .minimize = jc_minimize,
    .destroy = jc_destroy,
};
