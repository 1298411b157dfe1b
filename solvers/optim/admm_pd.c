/* ADMM projective dynamics (registry key "admm_pd").
 *
 * Paper       Overby, Brown, Li & Narain, "ADMM ⊇ Projective Dynamics: Fast Simulation
 *             of Hyperelastic Models with Dynamic Constraints", IEEE TVCG 23(10), 2017
 *             (Algorithm 1; the SCA 2016 paper of Narain, Overby & Brown is its first form).
 * Splitting   the step objective g(x) = ½‖x − x̃‖²_M + w·(Σₑ Vₑψₑ(Fₑ(x)) + R(x)), where
 *             Fₑ(x) = Gₑx + cₑ is the deformation gradient of tet e (objective ops
 *             split_*, objective.h) and R the rest (gravity, Newmark's linear term,
 *             springs, contact), is written with one 9-vector zₑ = Fₑ(x) per tet and
 *             solved by scaled-form ADMM on the augmented Lagrangian
 *                 ½‖x − x̃‖²_M + w·[ Σₑ Vₑψₑ(zₑ) + (Wₑ²/2)‖Fₑ(x) − zₑ + uₑ‖² + R(x) ].
 * Iteration   (the paper's order, from z = F(x₀), u = 0)
 *               local   zₑ ← argmin_z Vₑψₑ(z) + (Wₑ²/2)‖z − (Fₑ(x) + uₑ)‖²
 *                       (eo_material_prox: for isotropic models the paper's reduced
 *                       form, Newton on the three signed singular values of z with v's
 *                       singular vectors; for F-space models Newton on the 9 entries;
 *                       Armijo backtracking; up to local_iters
 *                       iterations to ‖∇‖ ≤ local_tol·kₑ·max(1, ‖v‖), 1e-14 by default:
 *                       the outer gradient cannot fall below what this leaves;
 *                       materials/prox.c)
 *               dual    uₑ ← uₑ + Fₑ(x) − zₑ
 *               global  x ← argmin_x ½‖x − x̃‖²_M + w Σₑ (Wₑ²/2)‖Fₑ(x) − zₑ + uₑ‖² + w R(x)
 *                       with the constant matrix L = M + w Σₑ Wₑ² GₑᵀGₑ (+ the springs'
 *                       PD block), the objective's constant_hessian factored ONCE by
 *                       eo_pd_factor (pd_factor.h; reused across iterations and steps),
 *                       in correction form: x ← x − L⁻¹ r, r the gradient of the
 *                       x-subproblem at x,
 *                         r = ∇g(x) − w Σₑ Gₑᵀ[Vₑ P(Fₑ) − Wₑ²(Fₑ − zₑ + uₑ)].
 *                       This is the exact x-update when R is linear (gravity, Newmark),
 *                       as in the paper; springs and contact enter linearized (one PD
 *                       step on them per iteration).
 *             At a fixed point u = Vₑ P(zₑ)/Wₑ², z = F(x) and ∇g(x) = 0: the iterates
 *             converge to the minimizer of g itself, not of a penalized problem.
 * Weights     Wₑ² = Vₑ·kₑ with kₑ the weight of the objective's constant matrix (problems/
 *             pd_matrix.c: λ + 2μ, the P-wave modulus, for every classical model), so that
 *             the paper's global matrix M + w DᵀWᵀWD IS the objective's L and its factor
 *             is shared. The paper's code (TetEnergyTerm: weight = √(k·V), k the bulk
 *             modulus λ + 2μ/3) uses the same √(stiffness·volume) rule with another
 *             modulus; λ + 2μ is the one pd_matrix.c measured best for PD-type methods.
 * Stopping    after every global step ∇g of the true step objective at the new x is
 *             evaluated (one gradient per iteration, counted) and tested by
 *             eo_solver_stop_check (the metric gradient ratio of the default rule).
 *             ADMM is not a descent method: g need not fall monotonically, and there is
 *             no line search. A barrier material (neo_hookean) can see an inverted
 *             global iterate: g = +∞ ends the run (diverged_nonfinite).
 * Cost        one signed SVD per element and iteration (eo_svd3) dominates: on the
 *             400-tet cantilever an iteration costs ~2 ms (perf: eo_svd3 26%, the prox 14%,
 *             ψ(σ) 7%), ~50x an SVD-free gradient evaluation (F_psi_grad).
 * Differs     the paper runs a fixed iteration count per frame; here the
 *             shared convergence test. Dynamic constraints (the paper's collisions via
 *             a changing D) are not split: a penalty contact term would stay in R and
 *             enter the global step explicitly, with nothing of its stiffness in L; on the
 *             corpus drop scenes (penalty 1e5 N/m per vertex) that diverged (non-finite on
 *             fish, g = 8e29 on mat40). So a scene with `collisions` is refused at
 *             configuration (needs_ops EO_OBJ_NEEDS_NO_CONTACT, exit 2 in the CLI, status
 *             "refused" in the benchmark).
 * Memory      4 vectors of n and 4 of 9E (F, z, u, stresses) in setup/at the first
 *             minimize of a pattern size; nothing inside the iterations. */
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "external.h" /* eo_external_inverted */
#include "pd_factor.h"
#include "elastopt/material.h"

/// Parameters (config `solver.admm_pd.*`).
typedef struct eo_admm_pd_params {
    int local_iters;     ///< Newton iterations per element proximal problem (default 20)
    double local_tol;    ///< its tolerance ‖P + k(z − v)‖ ≤ local_tol·k·max(1, ‖v‖) (1e-14)
} eo_admm_pd_params;

static const eo_param_desc admm_desc[] = {
    {.key = "local_iters", .kind = EO_PARAM_INT, .offset = offsetof(eo_admm_pd_params, local_iters), .def.i = 20,
     .min = 1, .max = 1000, .range = EO_RANGE_CLOSED,
     .help = "Newton iterations (at most) of each tet's proximal problem in the local step"},
    {.key = "local_tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(eo_admm_pd_params, local_tol), .def.d = 1e-14,
     .min = 0, .max = 1, .range = EO_RANGE_MIN_OPEN | EO_RANGE_MAX,
     .help = "tolerance of the proximal problem: |P(z) + k(z - v)| <= local_tol k max(1, |v|)"},
    {0},
};

typedef struct admm_state {
    int n;
    double *buf;
    double *grad, *r, *d, *gd;      /* n each */
    double *F, *z, *u, *S;          /* 9E each */
    int ne_cap;
    eo_pd_factor pf;
} admm_state;

static void admm_free(admm_state *st, eo_ctx *ctx)
{
    eo_free(ctx, st->buf);
    eo_free(ctx, st->F);
    st->buf = st->F = NULL;
    st->ne_cap = 0;
    eo_pd_factor_deinit(ctx, &st->pf);
}

static int admm_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    admm_state *st = vst;
    (void)params;
    admm_free(st, ctx);
    memset(st, 0, sizeof *st);
    if (n < 0) return eo_error(ctx, EO_ERR_INVALID, "admm_pd: n = %d < 0", n);
    int rc = eo_pd_factor_init(ctx, n, "admm_pd", &st->pf);
    if (rc < 0) return rc;
    const size_t nn = (size_t)(n > 0 ? n : 1);
    st->buf = eo_calloc(ctx, 4 * nn, sizeof(double));
    if (!st->buf) return eo_error(ctx, EO_ERR_NOMEM, "admm_pd: out of memory (n = %d)", n);
    st->grad = st->buf, st->r = st->buf + nn, st->d = st->buf + 2 * nn, st->gd = st->buf + 3 * nn;
    st->n = n;
    return EO_OK;
}

static void admm_destroy(void *vst, eo_ctx *ctx) { admm_free(vst, ctx); }

/* the element buffers for E elements (once per pattern size, before the iterations) */
static int ensure_elements(admm_state *st, int ne, eo_ctx *ctx)
{
    if (ne <= st->ne_cap) return EO_OK;
    eo_free(ctx, st->F);
    const size_t m = 9 * (size_t)(ne > 0 ? ne : 1);
    st->F = eo_calloc(ctx, 4 * m, sizeof(double));
    if (!st->F) {
        st->ne_cap = 0;
        return eo_error(ctx, EO_ERR_NOMEM, "admm_pd: out of memory (%d elements)", ne);
    }
    st->z = st->F + m, st->u = st->F + 2 * m, st->S = st->F + 3 * m;
    st->ne_cap = ne;
    return EO_OK;
}

static int is_element(const eo_objective_split *sp, int e)
{
    return !(sp->type[e]->flags & EO_MATERIAL_EDGE) && sp->k[e] > 0;
}

/* local + dual step, then the stresses S of the x-subproblem's gradient:
 * Sₑ = Vₑ[P(Fₑ) − kₑ(Fₑ − zₑ + uₑ)]. Returns EO_OK (*reason = EO_DIVERGED_NONFINITE
 * where ψ is +∞) or a negative status. */
static int local_step(admm_state *st, const eo_admm_pd_params *pp, const eo_objective_split *sp, eo_ctx *ctx,
                      long *local_iters, int *reason)
{
    for (int e = 0; e < sp->ne; e++) {
        double *F = st->F + 9 * (size_t)e, *z = st->z + 9 * (size_t)e, *u = st->u + 9 * (size_t)e,
               *S = st->S + 9 * (size_t)e;
        if (!is_element(sp, e)) {
            memset(S, 0, 9 * sizeof(double));
            continue;
        }
        const eo_material_type *mt = sp->type[e];
        const eo_material_coef *c = sp->coef[e];
        const double k = sp->k[e], V = sp->vol[e];
        double v[9];
        for (int i = 0; i < 9; i++) v[i] = F[i] + u[i];
        int it = 0;
        int rc = eo_material_prox(mt, c, v, k, pp->local_iters, pp->local_tol, z, &it);
        *local_iters += it;
        if (rc == EO_ERR_NONFINITE) {
            *reason = EO_DIVERGED_NONFINITE;
            return EO_OK;
        }
        if (rc < 0) return eo_error(ctx, rc, "admm_pd: proximal problem of element %d failed", e);
        for (int i = 0; i < 9; i++) u[i] += F[i] - z[i];
        eo_material_eval ev;
        rc = eo_material_evaluate(mt, c, F, EO_EVAL_GRAD, EO_PROJ_NONE, &ev);
        if (rc < 0) return eo_error(ctx, rc, "admm_pd: material of element %d", e);
        if (!isfinite(ev.psi)) {
            *reason = EO_DIVERGED_NONFINITE;
            return EO_OK;
        }
        for (int i = 0; i < 9; i++) S[i] = V * (ev.P[i] - k * (F[i] - z[i] + u[i]));
    }
    return EO_OK;
}

static int admm_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x, eo_solve_result *res)
{
    admm_state *st = vst;
    eo_admm_pd_params def;
    const eo_admm_pd_params *pp = params;
    if (!pp) {
        eo_params_default(admm_desc, &def);
        pp = &def;
    }
    eo_objective *obj = sc->obj;
    const int n = obj->n;
    const double t0 = eo_wtime();
    const long nv0 = obj->n_value, ng0 = obj->n_gradient, nh0 = obj->n_hessian;
    double g = NAN, gn = NAN, gn0 = NAN, g_prev = NAN, step_norm = NAN, last_dec = NAN;
    int rc = EO_OK, reason = 0, k = 0;
    long local_iters = 0;
    eo_objective_split sp;
    memset(res, 0, sizeof *res);
    res->decrement = NAN;
    if (n != st->n) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "admm_pd set up for n = %d; called with %d", st->n, n);
        goto done;
    }
    if (!sc->linear) {
        rc = eo_error(sc->ctx, EO_ERR_INVALID, "admm_pd needs a linear solver");
        goto done;
    }
    rc = eo_objective_split_get(obj, &sp);
    if (rc == EO_ERR_UNSUPPORTED) {
        rc = eo_error(sc->ctx, EO_ERR_UNSUPPORTED,
                      "admm_pd needs an objective with elastic elements (the split ops of a step problem)");
        goto done;
    }
    if (rc < 0) goto done;
    rc = ensure_elements(st, sp.ne, sc->ctx);
    if (rc < 0) goto done;
    rc = eo_objective_gradient(obj, x, &g, st->grad);
    if (rc < 0) goto done;
    gn = gn0 = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
    rc = obj->ops->split_apply(obj->data, x, st->F);
    if (rc < 0) goto done;
    memcpy(st->z, st->F, 9 * (size_t)sp.ne * sizeof(double));
    memset(st->u, 0, 9 * (size_t)sp.ne * sizeof(double));
    rc = eo_pd_factor_prepare(&st->pf, sc, x, res);
    if (rc < 0) goto done;
    if (!st->pf.factored) reason = st->pf.fail_reason ? st->pf.fail_reason : EO_DIVERGED_LINSOLVE;
    double dec0 = NAN, dec_prev = NAN;
    for (k = 0;; k++) {
        eo_iter_info info = {.iteration = k, .g = g, .grad_norm = gn, .decrement = NAN, .alpha = NAN,
                             .ls_evals = 0, .shift = st->pf.shift, .inverted = eo_external_inverted(sc, x),
                             .reason = 0, .x = x};
        eo_stop_info si = {.iteration = k, .g = g, .g_prev = g_prev, .grad_norm = gn, .grad_norm0 = gn0,
                           .decrement = NAN, .decrement0 = dec0, .decrement_prev = dec_prev,
                           .step_norm = step_norm, .x_norm = eo_norm2(n, x), .tol = sc->tol};
        if (!reason && (!isfinite(g) || !isfinite(gn))) reason = EO_DIVERGED_NONFINITE;
        if (!reason) reason = eo_solver_stop_check(sc, &si, x, st->grad);
        if (!reason && sc->stop->needs_direction) { /* λ²/2 = ∇gᵀL⁻¹∇g/2 for a decrement rule */
            int sr = eo_pd_factor_solve(&st->pf, sc, st->grad, st->gd, res);
            if (sr < 0) reason = sr;
            else {
                info.decrement = last_dec = eo_dot(n, st->grad, st->gd) / 2;
                if (k == 0) si.decrement0 = dec0 = last_dec;
                si.decrement = last_dec;
                reason = eo_solver_stop_check(sc, &si, x, st->grad);
            }
        }
        if (!reason && sc->time_budget > 0 && eo_wtime() - t0 > sc->time_budget) reason = EO_DIVERGED_TIME_BUDGET;
        if (!reason && k >= sc->max_iters) reason = EO_DIVERGED_MAX_ITERS;
        if (!reason) {
            rc = local_step(st, pp, &sp, sc->ctx, &local_iters, &reason);
            if (rc < 0) goto done;
        }
        if (!reason) { /* global step: r = ∇g − w Gᵀ S, x ← x − L⁻¹ r */
            rc = obj->ops->split_adjoint(obj->data, st->S, st->r);
            if (rc < 0) goto done;
            for (int i = 0; i < n; i++) st->r[i] = st->grad[i] - sp.w * st->r[i];
            int sr = eo_pd_factor_solve(&st->pf, sc, st->r, st->d, res);
            if (sr < 0) reason = sr;
        }
        if (reason) {
            info.reason = reason;
            eo_solver_report(sc, t0, &info);
            break;
        }
        info.alpha = 1;
        info.ls_evals = 1;
        if (eo_solver_report(sc, t0, &info)) {
            reason = EO_DIVERGED_EXTERNAL;
            break;
        }
        double s2 = 0;
        for (int i = 0; i < n; i++) {
            x[i] -= st->d[i];
            s2 += st->d[i] * st->d[i];
        }
        step_norm = sqrt(s2);
        g_prev = g;
        rc = eo_objective_gradient(obj, x, &g, st->grad);
        if (rc < 0) goto done;
        gn = isfinite(g) ? eo_norm2(n, st->grad) : NAN;
        rc = obj->ops->split_apply(obj->data, x, st->F);
        if (rc < 0) goto done;
        dec_prev = last_dec;
        last_dec = NAN;
    }
    eo_log(sc->ctx, EO_LOG_DEBUG, "admm_pd: %d iterations, %ld local Newton iterations over %d elements", k,
           local_iters, sp.ne);
done:
    res->reason = reason;
    res->iterations = k;
    res->g = g;
    res->grad_norm = gn;
    res->decrement = last_dec;
    eo_solve_result_finish(res, obj, nv0, ng0, nh0, t0, rc);
    return rc < 0 ? rc : EO_OK;
}

const eo_optimizer_type eo_optimizer_admm_pd = {
    .info = {.name = "admm_pd",
             .summary = "ADMM projective dynamics (Overby 2017): per-tet proximal steps on any hyperelastic "
                        "material, dual update, constant matrix factored once",
             .params = admm_desc,
             .params_size = sizeof(eo_admm_pd_params)},
    .state_size = sizeof(admm_state),
    .needs_linear = 1,
    .needs_hessian = 0,
    .needs_ops = EO_OBJ_NEEDS_SPLIT | EO_OBJ_NEEDS_NO_CONTACT,
    .setup = admm_setup,
    .minimize = admm_minimize,
    .destroy = admm_destroy,
};
