/* Projective dynamics as a quasi-Newton method (registry key "projective_dynamics").
 *
 * Problem     min g(x) = ½‖x − x̃‖²_M + w·E(x)   (any objective; the step objective).
 * Matrix      L = a constant SPD approximation of ∇²g, from the objective's optional
 *             op constant_hessian (objective.h). For the step objective
 *                 L = M + w·Σₜ Vₜ kₜ GₜᵀGₜ,   kₜ = λ + 2μ   (problems/pd_matrix.c),
 *             the global matrix of projective dynamics (Bouaziz, Martin, Liu, Kavan &
 *             Pauly, "Projective Dynamics", SIGGRAPH 2014). An objective without the op
 *             gets L = ∇²g(x₀) at the first iterate of each minimization, assembled
 *             as the Hessian fix asks (clamp by default).
 * Factor      the constant L through eo_pd_factor (pd_factor.h, shared with lbfgs
 *             h0 = pd, ncg precond = pd and pd_local_global): the step objective's own
 *             factor when solver.linear is a CHOLMOD method (one factorization per scene,
 *             releases and pins by rank updates/downdates), else L (or L₁ when L =
 *             L₁ ⊗ I₃) factored ONCE with solver.linear and reused while the objective,
 *             the matrix pointer and its version are unchanged; a matrix found not
 *             positive definite is shifted, L + cI, by the shift loop all fixes share
 *             (solvers/hessfix/shift_loop.c; EO_DIVERGED_NOT_PD above shift_max).
 *             Without a constant L, ∇²g(x₀) is factored through the Hessian fix (its op
 *             `factor` with want_direction = 0, solver.h).
 * Direction   lbfgs_history = 0:  p = −L⁻¹∇g.
 *             For a PD-expressible energy E = Σ k/2‖Gx − proj(Gx)‖², ∇g = L x − b(x)
 *             and x + p = L⁻¹ b(x) is exactly the local/global iteration; for any
 *             other material it is the same preconditioned descent step (Liu, Bouaziz
 *             & Kavan, "Quasi-Newton Methods for Real-Time Simulation of Hyperelastic
 *             Materials", ACM TOG 36(3), 2017, §4).
 *             lbfgs_history = m > 0: L-BFGS with the last m pairs s = Δx, y = Δ∇g and
 *             L as the initial Hessian (Liu et al. 2017, §5; Nocedal & Wright Alg. 7.4):
 *                 q = ∇g;  for i newest … oldest:  aᵢ = ρᵢ sᵢᵀq,  q −= aᵢ yᵢ
 *                 r = L⁻¹ q                      (the one solve of the iteration)
 *                 for i oldest … newest:  b = ρᵢ yᵢᵀr,  r += sᵢ (aᵢ − b);   p = −r.
 *             A pair with sᵀy ≤ 1e-10‖s‖‖y‖ is skipped (keeps the update SPD); if p is
 *             not a descent direction the memory is cleared and p = −L⁻¹∇g (counted in
 *             res.n_fallback). The memory is cleared at the start of each minimization.
 * Step        the configured line search from α = 1 (the line search is what makes the
 *             iteration robust for every hyperelastic model, Liu et al. 2017 §4.2).
 * Decrement   λ²/2 = −∇gᵀp/2 = ∇gᵀL⁻¹∇g/2 (m = 0): L is SPD, so this is a proper
 *             metric of ∇g; the newton_decrement rule stops on it. It estimates
 *             g − g* only as well as L approximates ∇²g.
 * Memory      workspace (2m + 4 vectors of n) in setup; the copy of L (and the linear
 *             solver's analysis) once per new pattern; nothing inside iterations. */
#include <stddef.h>
#include <string.h>

#include "descent.h"
#include "lbfgs_memory.h"
#include "pd_factor.h"

/// Projective dynamics / its quasi-Newton form (config `solver.projective_dynamics.*`).
typedef struct eo_projective_dynamics_params {
    int lbfgs_history;   ///< 0: p = −L⁻¹∇g (PD local/global iteration as a descent method);
                         ///< m > 0: L-BFGS with m pairs and L as initial Hessian (Liu et al.
                         ///< 2017) (default 0)
} eo_projective_dynamics_params;

typedef struct pd_state {
    eo_descent_ws w;
    int n, m;
    eo_lbfgs_memory mem;      /* Liu 2017's L-BFGS pairs (m = 0: plain PD) */
    double *store;            /* the memory's storage, then q */
    double *q;                /* n */
    /* the factored matrix: own copy A, and what it was made from */
    eo_csc *A;
    const eo_linsolve *ls;    /* linear solver holding the analysis of A */
    int analyzed, factored;
    int fail_reason;          /* negative reason when no usable factorization */
    double shift;             /* shift c in the factors */
    double projected;         /* fraction of elements the fix projected for them */
    eo_ctx *ctx;
    /* the factorization in progress (for pd_assemble) */
    const eo_solver_ctx *sc;
    const double *x;
    eo_solve_result *res;
    eo_hessfix_env env;
    eo_pd_factor pf;          /* the constant L (objective op constant_hessian) */
    int use_pf;               /* this minimization solves with pf */
} pd_state;

static const eo_param_desc pd_desc[] = {
    {.key = "lbfgs_history", .kind = EO_PARAM_INT,
     .offset = offsetof(eo_projective_dynamics_params, lbfgs_history), .def.i = 0, .min = 0,
     .max = 1000, .range = EO_RANGE_CLOSED,
     .help = "0: p = -L^-1 grad (PD iteration); m > 0: L-BFGS with m pairs, L as initial Hessian"},
    {0},
};

static void pd_free(pd_state *st, eo_ctx *ctx)
{
    eo_descent_ws_deinit(ctx, &st->w);
    eo_free(ctx, st->store);
    st->store = NULL;
    eo_csc_destroy(&st->A);
    eo_pd_factor_deinit(ctx, &st->pf);
}

static int pd_setup(void *vst, const void *params, int n, eo_ctx *ctx)
{
    pd_state *st = vst;
    eo_projective_dynamics_params def;
    const eo_projective_dynamics_params *pp = params;
    if (!pp) {
        eo_params_default(pd_desc, &def);
        pp = &def;
    }
    pd_free(st, ctx);
    memset(st, 0, sizeof *st);
    st->ctx = ctx;
    int rc = eo_descent_ws_init(ctx, n, &st->w);
    if (rc < 0) return rc;
    size_t m = (size_t)pp->lbfgs_history, nn = (size_t)(n > 0 ? n : 1);
    size_t mem = eo_lbfgs_memory_size(n, (int)m);
    st->store = eo_calloc(ctx, mem + nn, sizeof(double));
    if (!st->store)
        return eo_error(ctx, EO_ERR_NOMEM, "projective_dynamics: out of memory (n = %d, m = %zu)", n, m);
    eo_lbfgs_memory_bind(&st->mem, n, (int)m, st->store);
    st->q = st->store + mem;
    st->m = (int)m;
    st->n = n;
    return eo_pd_factor_init(ctx, n, "projective_dynamics", &st->pf);
}

static void pd_destroy(void *vst, eo_ctx *ctx) { pd_free(vst, ctx); }

static int same_pattern(const eo_csc *A, const eo_csc *B)
{
    return A && B && A->n == B->n && A->nnz == B->nnz &&
           memcmp(A->colptr, B->colptr, ((size_t)A->n + 1) * sizeof(int)) == 0 &&
           memcmp(A->rowind, B->rowind, (size_t)A->nnz * sizeof(int)) == 0;
}

/* Copy src into the own matrix A (new pattern: clone + analyze). */
static int load(pd_state *st, const eo_solver_ctx *sc, const eo_csc *src, eo_solve_result *res,
                int *reason)
{
    const int n = st->n;
    int rc;
    if (!src || src->n != n)
        return eo_error(sc->ctx, EO_ERR_INVALID,
                        "projective_dynamics: matrix has n = %d, objective has n = %d",
                        src ? src->n : -1, n);
    if (same_pattern(st->A, src) && st->analyzed && st->ls == sc->linear) {
        memcpy(st->A->val, src->val, (size_t)src->nnz * sizeof(double));
        return EO_OK;
    }
    for (int j = 0; j < n; j++) {
        int e = src->colptr[j + 1] - 1;
        if (e < src->colptr[j] || src->rowind[e] != j)
            return eo_error(sc->ctx, EO_ERR_INVALID,
                            "projective_dynamics: matrix column %d has no stored diagonal", j);
    }
    st->analyzed = 0;
    eo_csc_destroy(&st->A);
    rc = eo_csc_clone(sc->ctx, src, &st->A);
    if (rc < 0) return rc;
    rc = eo_linsolve_analyze(sc->linear, st->A);
    if (rc < 0) {
        res->status = rc;
        *reason = EO_DIVERGED_LINSOLVE;
        return EO_OK;
    }
    st->analyzed = 1;
    st->ls = sc->linear;
    return EO_OK;
}

/* eo_hessfix_assemble_fn: the Hessian at x₀ as the fix asks, copied into the own
 * matrix A. */
static int pd_assemble(void *user, eo_proj proj, const unsigned char *proj_of, eo_csc **out,
                       int *reason)
{
    pd_state *st = user;
    const eo_solver_ctx *sc = st->sc;
    eo_csc *H = NULL;
    int rc = proj_of ? eo_objective_hessian_masked(sc->obj, st->x, proj_of, &H)
                     : eo_objective_hessian(sc->obj, st->x, proj, &H);
    if (rc < 0) return rc;
    rc = load(st, sc, H, st->res, reason);
    if (rc < 0) return rc;
    *out = st->A;
    return EO_OK;
}

/* Factor the matrix through the Hessian fix (factors only). Sets st->factored or
 * st->fail_reason. */
static int factor(pd_state *st, const eo_solver_ctx *sc)
{
    st->factored = 0;
    st->fail_reason = 0;
    st->shift = 0;
    eo_hessfix_out out = {.shift = 0, .projected = 0, .factored = 0, .reason = 0};
    int rc = sc->hessfix->factor(sc->hessfix_state, sc->hessfix_params, &st->env, st->q, &out);
    if (rc < 0) return rc;
    st->projected = out.projected;
    if (out.factored) {
        st->shift = out.shift;
        st->factored = 1;
    } else {
        st->fail_reason = out.reason ? out.reason : EO_DIVERGED_NOT_PD;
    }
    return EO_OK;
}

static int pd_begin(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                    double g, const double *grad, eo_solve_result *res)
{
    pd_state *st = vst;
    const eo_projective_dynamics_params *pp = params;
    eo_lbfgs_memory_clear(&st->mem);
    if (pp->lbfgs_history != st->m)
        return eo_error(sc->ctx, EO_ERR_INVALID,
                        "projective_dynamics: set up for lbfgs_history %d, called with %d", st->m,
                        pp->lbfgs_history);
    if (!sc->linear) return eo_error(sc->ctx, EO_ERR_INVALID, "projective_dynamics needs a linear solver");
    if (!sc->hessfix) return eo_error(sc->ctx, EO_ERR_INVALID, "projective_dynamics needs a Hessian fix");
    st->sc = sc;
    st->x = x;
    st->res = res;
    st->env = (eo_hessfix_env){.obj = sc->obj, .linear = sc->linear, .ctx = sc->ctx, .n = st->n,
                               .x = x, .g = g, .grad = grad, .want_direction = 0,
                               .descent_eps = 0, .assemble = pd_assemble, .user = st, .res = res};
    int rc;
    if (sc->hessfix->begin) {
        rc = sc->hessfix->begin(sc->hessfix_state, sc->hessfix_params, &st->env);
        if (rc < 0) return rc;
    }
    st->use_pf = sc->obj->ops->constant_hessian != NULL;
    if (st->use_pf) { /* the constant L: once per scene (pd_factor.h) */
        rc = eo_pd_factor_prepare(&st->pf, sc, x, res);
        if (rc < 0) return rc;
        st->factored = st->pf.factored;
        st->fail_reason = st->pf.fail_reason;
        st->shift = st->pf.shift;
        st->projected = 0;
        return EO_OK;
    }
    /* no constant matrix: the Hessian at the first iterate, as the fix asks */
    return factor(st, sc);
}

/* r = A⁻¹ b (b and r distinct). Returns a negative reason on failure, else 0. */
static int solve(pd_state *st, const eo_solver_ctx *sc, const double *b, double *r, eo_solve_result *res)
{
    if (st->use_pf) return eo_pd_factor_solve(&st->pf, sc, b, r, res);
    int rc = eo_linsolve_solve(sc->linear, b, r);
    if (rc < 0) {
        res->status = rc;
        return EO_DIVERGED_LINSOLVE;
    }
    if (rc == EO_WARN_NOT_PD) return EO_DIVERGED_NOT_PD;
    return 0;
}

static int pd_direction(void *vst, const void *params, const eo_solver_ctx *sc, const double *x,
                        double g, const double *grad, double *p, eo_direction_out *out,
                        eo_solve_result *res)
{
    pd_state *st = vst;
    eo_lbfgs_memory *h = &st->mem;
    const int n = st->n;
    (void)params, (void)x, (void)g;
    out->alpha0 = 1;
    out->shift = st->shift;
    out->projected = st->projected;
    if (!st->factored) {
        out->reason = st->fail_reason ? st->fail_reason : EO_DIVERGED_LINSOLVE;
        return EO_OK;
    }
    double *q = st->q;
    if (h->count > 0) {
        for (int i = 0; i < n; i++) q[i] = grad[i];
        eo_lbfgs_memory_first_loop(h, q);
        int reason = solve(st, sc, q, p, res); /* r = L⁻¹ q */
        if (reason) {
            out->reason = reason;
            return EO_OK;
        }
        eo_lbfgs_memory_second_loop(h, p);
        for (int i = 0; i < n; i++) p[i] = -p[i];
        if (eo_is_descent(NULL, n, grad, p)) return EO_OK;
        eo_lbfgs_memory_clear(h); /* not a descent direction: plain PD step */
        res->n_fallback++;
    }
    int reason = solve(st, sc, grad, p, res);
    if (reason) {
        out->reason = reason;
        return EO_OK;
    }
    for (int i = 0; i < n; i++) p[i] = -p[i];
    return EO_OK;
}

static void pd_accepted(void *vst, const void *params, const double *x, const double *x_new,
                        const double *grad, const double *grad_new, const double *p, double alpha)
{
    pd_state *st = vst;
    (void)params, (void)p, (void)alpha;
    eo_lbfgs_memory_push(&st->mem, x, x_new, grad, grad_new);
}

static const eo_descent_ops pd_ops = {
    .begin = pd_begin,
    .direction = pd_direction,
    .accepted = pd_accepted,
};

static int pd_minimize(void *vst, const void *params, const eo_solver_ctx *sc, double *x,
                       eo_solve_result *res)
{
    pd_state *st = vst;
    eo_projective_dynamics_params def;
    if (!params) {
        eo_params_default(pd_desc, &def);
        params = &def;
    }
    return eo_descent_minimize(&pd_ops, st, params, sc, &st->w, x, res);
}

const eo_optimizer_type eo_optimizer_projective_dynamics = {
    .info = {.name = "projective_dynamics",
             .summary = "projective dynamics: p = -L^-1 grad with a constant matrix L factored once "
                        "(Liu 2017 L-BFGS on top with lbfgs_history > 0), line search",
             .params = pd_desc,
             .params_size = sizeof(eo_projective_dynamics_params)},
    .state_size = sizeof(pd_state),
    .needs_ops = EO_OBJ_NEEDS_CONSTANT,
    .needs_linear = 1,
    .needs_hessian = 1,
    .setup = pd_setup,
    .minimize = pd_minimize,
    .destroy = pd_destroy,
};
