/* Vertex block descent (registry key "vbd").
 *
 * Paper       Chen, Liu, Yang & Yuksel, "Vertex Block Descent", ACM TOG 43(4), 2024: block
 *             coordinate descent on the variational implicit step, one block per vertex,
 *             Gauss–Seidel over a vertex colouring.
 * Iteration   one iteration = one sweep over all colours (serially, colour after colour,
 *             blocks in increasing id inside a colour). For block b (a free vertex) with
 *             every other vertex held at its current position, the objective's op
 *             vertex_block gives Gᵢ (the vertex's inertia, potentials and the energies of
 *             its tets), fᵢ = ∂g/∂xᵢ and the 3×3 block Hᵢ = ∂²g/∂xᵢ² of the Hessian whose
 *             element Hessians are projected (`projection`: clamp by default, PSD-projected
 *             element Hessians; a diagonal block of a PSD matrix plus the mass block is
 *             positive definite, so every Hᵢ is). The update is one Newton step of the block, xᵢ ← xᵢ − Hᵢ⁻¹fᵢ
 *             (a partly constrained vertex: over its free coordinates); a block whose Hᵢ
 *             is not numerically positive definite is skipped (the paper skips
 *             near-singular Hᵢ).
 * Colouring   greedy colouring of the vertex graph (two vertices adjacent when they share
 *             a tet), vertices visited in increasing id, smallest free colour: fixed for a
 *             pattern, so runs are reproducible. The paper colours to run the blocks of one
 *             colour in parallel; here the sweep is serial and the colouring fixes only
 *             the order (a Gauss–Seidel order with the paper's structure).
 * Line search none (the default, the paper's plain block Newton step) or backtracking:
 *             per vertex, the step is halved (at most 30 times, else the vertex stays)
 *             until Gᵢ is finite and satisfies Armijo (c1 = 1e-4; where the predicted
 *             decrease is below 1e-10|Gᵢ|, Gᵢ not raised beyond that) — for barrier
 *             materials, whose Gᵢ is +∞ past inversion, and a decrease of g at every block.
 * Accelerated accelerated = true: the paper's Chebyshev-type over-relaxation on whole
 *             sweeps, x⁽ⁿ⁾ = ωₙ(x̄⁽ⁿ⁾ − x⁽ⁿ⁻²⁾) + x⁽ⁿ⁻²⁾, x̄⁽ⁿ⁾ the sweep from x⁽ⁿ⁻¹⁾,
 *             ω₁ = 1, ω₂ = 2/(2 − ρ²), ωₙ = 4/(4 − ρ²ωₙ₋₁) (chebyshev.h, γ = 1). The
 *             paper's ρ is hand-tuned per scene (rho > 0 here); rho = 0 (the default)
 *             estimates it from the shrinking of the first `delay` + 1 plain sweeps
 *             (chebyshev.h), which the paper does not do; delay = 1 with a given rho is
 *             the paper's schedule exactly. Not in the paper: when an accelerated iterate
 *             raises g (or makes it non-finite), the plain sweep x̄⁽ⁿ⁾ is taken instead and
 *             the acceleration restarts (counted in n_fallback; where g no longer
 *             resolves the change a rise of ‖∇g‖ counts, eo_cheb_accept).
 * Stopping    the configured rule through eo_solver_stop_check with ∇g at the iterate
 *             after every sweep (one gradient evaluation per sweep), the metric gradient
 *             measure (no Newton decrement). The paper runs a fixed iteration count.
 * Differs     the step objective's own initial guess replaces the paper's adaptive
 *             initialization; the consistent mass and Newmark's linear term are handled
 *             exactly (their vertex parts); springs couple vertices like tets (in the
 *             colouring too); no collision detection (the penalty obstacles' vertex parts
 *             are included); damping and friction have no vertex form yet
 *             (EO_ERR_UNSUPPORTED naming the term).
 * Cost        per sweep every tet is evaluated (12×12 Hessian) once for each of its 4
 *             vertices, plus one gradient; no linear solver, no global matrix.
 * Memory      5 vectors of n in setup; the colouring (per pattern, at the first minimize
 *             after a pattern change); nothing inside the iterations. */
#include <stddef.h>
#include <string.h>

#include "chebyshev.h"
#include "descent.h"
#include "external.h" /* eo_external_inverted */

typedef struct eo_vbd_params {
    int accelerated;      /* Chebyshev over-relaxation of the sweeps (default false) */
    double rho;           /* ρ of the acceleration; 0 = estimated (default 0) */
    int delay;            /* plain sweeps before the acceleration (default 10) */
    char projection[8];   /* element Hessian projection: clamp, abs, none (default clamp) */
    char linesearch[16];  /* per-vertex: none, backtracking (default none) */
} eo_vbd_params;

static const char *const proj_choices[] = {"clamp", "abs", "none", NULL};
static const char *const ls_choices[] = {"none", "backtracking", NULL};

static const eo_param_desc vbd_desc[] = {
    {.key = "accelerated", .kind = EO_PARAM_BOOL, .offset = offsetof(eo_vbd_params, accelerated), .def.i = 0,
     .help = "Chebyshev over-relaxation of whole sweeps (Chen et al. 2024), restarted when g rises"},
    {.key = "rho", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_vbd_params, rho), .def.d = 0, .min = 0, .max = 1,
     .range = EO_RANGE_MIN | EO_RANGE_MAX_OPEN,
     .help = "spectral radius estimate of the acceleration, [0, 1); 0 = measured from the first plain sweeps"},
    {.key = "delay", .kind = EO_PARAM_INT, .offset = offsetof(eo_vbd_params, delay), .def.i = 10, .min = 1,
     .max = 1000, .range = EO_RANGE_CLOSED,
     .help = "plain sweeps before the acceleration starts (1 with a given rho = the paper's schedule)"},
    {.key = "projection", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_vbd_params, projection),
     .size = sizeof(((eo_vbd_params *)0)->projection), .def.s = "clamp", .choices = proj_choices,
     .help = "element Hessians projected before the vertex block is taken: clamp, abs or none"},
    {.key = "linesearch", .kind = EO_PARAM_CHOICE, .offset = offsetof(eo_vbd_params, linesearch),
     .size = sizeof(((eo_vbd_params *)0)->linesearch), .def.s = "none", .choices = ls_choices,
     .help = "per-vertex step: none (the paper) or backtracking (Armijo on the vertex energy)"},
    {0},
};

typedef struct vbd_state {
    int n;
    double *buf, *grad, *gt, *xk, *xm1, *xbar;
    /* colouring of the current blocks */
    int nb, ncol, *order, *cptr, *colour, *used;
    unsigned long version;
    int coloured;
} vbd_state;

static void vbd_free_colour(vbd_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->order);
    eo_free(ctx, st->cptr);
    eo_free(ctx, st->colour);
    eo_free(ctx, st->used);
    st->order = st->cptr = st->colour = st->used = NULL;
    st->coloured = 0;
}

static void vbd_destroy(void *vst, eo_ctx *ctx)
{
    vbd_state *st = vst;
    eo_free(ctx, st->buf);
    st->buf = NULL;
    vbd_free_colour(st, ctx);
}

static int vbd_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    (void)params;
    vbd_state *st = vst;
    vbd_destroy(st, ctx);
    memset(st, 0, sizeof *st);
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "vbd: n = %d < 0", n);
    const size_t nn = (size_t)(n > 0 ? n : 1);
    st->buf = eo_calloc(ctx, 5 * nn, sizeof(double));
    if (!st->buf) return eo_error(ctx, EO_ERR_NOMEM, "vbd: out of memory (n = %d)", n);
    st->grad = st->buf;
    st->gt = st->buf + nn;
    st->xk = st->buf + 2 * nn;
    st->xm1 = st->buf + 3 * nn;
    st->xbar = st->buf + 4 * nn;
    st->n = n;
    return EO_OK;
}

/* Greedy colouring of the block graph and the sweep order (by colour, then block id). */
static int vbd_colour(vbd_state *st, const eo_vertex_blocks *vb, eo_ctx *ctx)
{
    vbd_free_colour(st, ctx);
    const int nb = vb->nb;
    const size_t m = (size_t)(nb > 0 ? nb : 1);
    st->order = eo_malloc(ctx, m * sizeof(int));
    st->colour = eo_malloc(ctx, m * sizeof(int));
    st->used = eo_malloc(ctx, (m + 1) * sizeof(int));
    st->cptr = eo_calloc(ctx, m + 2, sizeof(int));
    if (!st->order || !st->colour || !st->used || !st->cptr)
        return eo_error(ctx, EO_ERR_NOMEM, "vbd: out of memory (colouring %d vertices)", nb);
    int ncol = 0;
    for (int b = 0; b <= nb; b++) st->used[b] = -1;
    for (int b = 0; b < nb; b++) {
        for (int q = vb->adj_ptr[b]; q < vb->adj_ptr[b + 1]; q++) {
            const int u = vb->adj[q];
            if (u < b) st->used[st->colour[u]] = b;
        }
        int c = 0;
        while (st->used[c] == b) c++;
        st->colour[b] = c;
        if (c + 1 > ncol) ncol = c + 1;
    }
    for (int b = 0; b < nb; b++) st->cptr[st->colour[b] + 1]++;
    for (int c = 0; c < ncol; c++) st->cptr[c + 1] += st->cptr[c];
    for (int c = 0; c < ncol; c++) st->used[c] = st->cptr[c]; /* next slot of colour c */
    for (int b = 0; b < nb; b++) st->order[st->used[st->colour[b]]++] = b;
    st->nb = nb;
    st->ncol = ncol;
    st->version = vb->version;
    st->coloured = 1;
    eo_log(ctx, EO_LOG_DEBUG, "vbd: %d vertices in %d colours", nb, ncol);
    return EO_OK;
}

static eo_proj proj_of(const char *s)
{
    return strcmp(s, "abs") == 0 ? EO_PROJ_ABS : strcmp(s, "none") == 0 ? EO_PROJ_NONE : EO_PROJ_CLAMP;
}

/* One Gauss–Seidel sweep over the colours, x in place. *skipped: blocks without a
 * positive definite Hᵢ; *rejected: backtracking that found no acceptable step. */
static int vbd_sweep(const vbd_state *st, eo_objective *obj, const eo_vertex_blocks *vb, double *x, eo_proj proj,
                     int backtrack, long *skipped, long *rejected)
{
    for (int q = 0; q < st->nb; q++) {
        const int b = st->order[q], *dof = vb->dofs + 3 * b;
        double e, g3[3], H3[9], d[3];
        int rc = eo_objective_vertex_block(obj, x, b, proj, &e, g3, H3);
        if (rc < 0) return rc;
        if (!eo_block3_newton(H3, g3, dof, d)) {
            (*skipped)++;
            continue;
        }
        if (!backtrack) {
            for (int c = 0; c < 3; c++)
                if (dof[c] >= 0) x[dof[c]] += d[c];
            continue;
        }
        double x0[3] = {0, 0, 0}, slope = 0, a = 1;
        for (int c = 0; c < 3; c++)
            if (dof[c] >= 0) {
                x0[c] = x[dof[c]];
                slope += g3[c] * d[c];
            }
        int ok = 0;
        for (int t = 0; t < 30 && !ok; t++, a *= 0.5) {
            for (int c = 0; c < 3; c++)
                if (dof[c] >= 0) x[dof[c]] = x0[c] + a * d[c];
            double e1;
            if ((rc = eo_objective_vertex_block(obj, x, b, proj, &e1, NULL, NULL)) < 0) return rc;
            /* Armijo, or where G cannot resolve the predicted decrease (it carries the
             * energies of the vertex's whole tets): not raised beyond that resolution */
            const double res = 1e-10 * fabs(e);
            ok = isfinite(e1) && (e1 <= e + 1e-4 * a * slope || (-a * slope <= res && e1 <= e + res));
        }
        if (!ok) {
            (*rejected)++;
            for (int c = 0; c < 3; c++)
                if (dof[c] >= 0) x[dof[c]] = x0[c];
        }
    }
    return EO_OK;
}

/* sweeps without a strict decrease of g and no new smallest ‖∇g‖ before
 * EO_DIVERGED_STAGNATED (the tolerance is below what g and ∇g resolve) */
#define VBD_STALL_LIMIT 20

static int vbd_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    vbd_state *st = vst;
    eo_vbd_params def;
    const eo_vbd_params *pp = params;
    if (!pp) {
        eo_params_default(vbd_desc, &def);
        pp = &def;
    }
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, gn_best = INFINITY;
    int rc = EO_OK, reason = 0, k = 0, stalled = 0;
    long skipped = 0, rejected = 0;
    const eo_proj proj = proj_of(pp->projection);
    const int backtrack = strcmp(pp->linesearch, "backtracking") == 0;
    eo_cheb cheb;
    eo_cheb_start(&cheb, pp->rho, pp->delay);
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "vbd set up for n = %d, called with %d", st->n, n);
        goto done;
    }
    eo_vertex_blocks vb;
    rc = eo_objective_vertex_blocks(obj, &vb);
    if (rc == EO_ERR_UNSUPPORTED && !obj->ops->vertex_blocks)
        rc = eo_error(sc->ctx, EO_ERR_UNSUPPORTED, "vbd needs an objective with vertex blocks (a step problem)");
    if (rc < 0) goto done;
    if (!st->coloured || st->version != vb.version || st->nb != vb.nb) {
        if ((rc = vbd_colour(st, &vb, sc->ctx)) < 0) goto done;
    }
    rc = eo_objective_gradient(obj, x, &g, st->grad);
    if (rc < 0) goto done;
    gn = gn0 = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
    memcpy(st->xm1, x, (size_t)n * sizeof(double));
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .inverted = eo_external_inverted(sc, x), .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .decrement0 = 0, .decrement_prev = 0, .step_norm = step_norm,
                           .x_norm = eo_norm2(n, x), .tol = sc->tol};
        if (!reason && (!isfinite(g) || !isfinite(gn))) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, st->grad);
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason && stalled >= VBD_STALL_LIMIT) reason = EO_DIVERGED_STAGNATED;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        /* the sweep x_k -> x̄ (in x), then the over-relaxation from x_{k-1} */
        memcpy(st->xk, x, (size_t)n * sizeof(double));
        if ((rc = vbd_sweep(st, obj, &vb, x, proj, backtrack, &skipped, &rejected)) < 0) goto done;
        double omega = 1;
        if (pp->accelerated) {
            double s2 = 0;
            for (int i = 0; i < n; i++) s2 += (x[i] - st->xk[i]) * (x[i] - st->xk[i]);
            omega = eo_cheb_next(&cheb, sqrt(s2));
        }
        if (omega != 1) {
            memcpy(st->xbar, x, (size_t)n * sizeof(double));
            for (int i = 0; i < n; i++) x[i] = omega * (x[i] - st->xm1[i]) + st->xm1[i];
        }
        double gt = NAN;
        int nev = 1;
        if ((rc = eo_objective_gradient(obj, x, &gt, st->gt)) < 0) goto done;
        if (omega != 1 && !eo_cheb_accept(g, gn, gt, eo_norm2(n, st->gt))) { /* restart from the plain sweep */
            memcpy(x, st->xbar, (size_t)n * sizeof(double));
            nev++;
            if ((rc = eo_objective_gradient(obj, x, &gt, st->gt)) < 0) goto done;
            eo_cheb_restart(&cheb);
            res->n_fallback++;
            omega = 1;
        }
        info.alpha = omega;
        info.ls_evals = nev;
        if (gn < gn_best) gn_best = gn;
        if (eo_solver_report(sc, t0, &info)) {
            memcpy(x, st->xk, (size_t)n * sizeof(double));
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        double s2 = 0;
        for (int i = 0; i < n; i++) s2 += (x[i] - st->xk[i]) * (x[i] - st->xk[i]);
        step_norm = sqrt(s2);
        double *t = st->xm1; /* x_{k-1} <- x_k */
        st->xm1 = st->xk;
        st->xk = t;
        t = st->grad;
        st->grad = st->gt;
        st->gt = t;
        g_prev = g;
        g = gt;
        gn = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
        stalled = (g < g_prev || gn < gn_best) ? 0 : stalled + 1;
    }
    if (skipped || rejected)
        eo_log(sc->ctx, EO_LOG_DEBUG, "vbd: %ld vertex updates skipped (H not positive definite), %ld without an "
               "acceptable step", skipped, rejected);
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_vbd = {
    .info = {.name = "vbd",
             .summary = "vertex block descent (Chen 2024): per-vertex 3x3 Newton steps in a Gauss-Seidel sweep over "
                        "a vertex colouring, optional Chebyshev acceleration",
             .params = vbd_desc,
             .params_size = sizeof(eo_vbd_params)},
    .state_size = sizeof(vbd_state),
    .needs_linear = 0,
    .needs_hessian = 0,
    .needs_ops = EO_OBJ_NEEDS_VERTEX,
    .linesearch = "none",
    .setup = vbd_setup,
    .minimize = vbd_minimize,
    .destroy = vbd_destroy,
};
