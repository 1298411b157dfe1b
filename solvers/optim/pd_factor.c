/* The projective-dynamics matrix factored once: see pd_factor.h. Moved out of
 * projective_dynamics.c so lbfgs (h0 = pd) and ncg (precond = pd) use the same code. */
#include "pd_factor.h"
#include "../hessfix/shift_loop.h"

#include <math.h>
#include <string.h>

int eo_pd_factor_init(eo_ctx *ctx, int n, const char *who, eo_pd_factor *f)
{
    memset(f, 0, sizeof *f);
    f->n = n;
    f->who = who;
    if (n > 0 && n % 3 == 0) {
        f->bs = eo_malloc(ctx, 2 * (size_t)(n / 3) * sizeof(double));
        if (!f->bs) return eo_error(ctx, EO_ERR_NOMEM, "%s: out of memory (n = %d)", who, n);
        f->xs = f->bs + n / 3;
    }
    return eo_shift_ws_setup(&f->ws, n, ctx);
}

void eo_pd_factor_deinit(eo_ctx *ctx, eo_pd_factor *f)
{
    eo_shift_ws_destroy(&f->ws, ctx);
    eo_csc_destroy(&f->A);
    eo_free(ctx, f->bs);
    memset(f, 0, sizeof *f);
}

static int same_pattern(const eo_csc *A, const eo_csc *B)
{
    return A && B && A->n == B->n && A->nnz == B->nnz &&
           memcmp(A->colptr, B->colptr, ((size_t)A->n + 1) * sizeof(int)) == 0 &&
           memcmp(A->rowind, B->rowind, (size_t)A->nnz * sizeof(int)) == 0;
}

/* Copy src into the own matrix A (new pattern: clone + analyze) and factor it with the
 * shift loop. */
static int factor_own(eo_pd_factor *f, const eo_solver_ctx *sc, const eo_csc *src, eo_solve_result *res)
{
    const int n = src->n;
    int rc;
    if (same_pattern(f->A, src) && f->analyzed && f->ls == sc->linear) {
        memcpy(f->A->val, src->val, (size_t)src->nnz * sizeof(double));
    } else {
        for (int j = 0; j < n; j++) {
            int e = src->colptr[j + 1] - 1;
            if (e < src->colptr[j] || src->rowind[e] != j)
                return eo_error(sc->ctx, EO_ERR_INVALID, "%s: matrix column %d has no stored diagonal",
                                f->who, j);
        }
        f->analyzed = 0;
        eo_csc_destroy(&f->A);
        rc = eo_csc_clone(sc->ctx, src, &f->A);
        if (rc < 0) return rc;
        rc = eo_linsolve_analyze(sc->linear, f->A);
        if (rc < 0) {
            res->status = rc;
            f->fail_reason = EO_DIVERGED_LINSOLVE;
            return EO_OK;
        }
        f->analyzed = 1;
        f->ls = sc->linear;
    }
    /* the shared c·I shift loop of the Hessian fixes (factors only, no direction) */
    eo_hessfix_shift_params hp;
    eo_shift_params_get(sc->hessfix_params, &hp);
    eo_hessfix_env env = {.obj = sc->obj, .linear = sc->linear, .ctx = sc->ctx, .n = n, .want_direction = 0,
                          .res = res};
    eo_hessfix_out out = {0};
    eo_shift_ws_begin(&f->ws);
    rc = eo_shift_factor(&f->ws, &hp, 1, &env, f->A, NULL, &out);
    if (rc < 0) return rc;
    if (!rc) {
        f->fail_reason = out.reason ? out.reason : EO_DIVERGED_NOT_PD;
        return EO_OK;
    }
    f->shift = out.shift;
    f->factored = 1;
    return EO_OK;
}

/* Copy src, or L₁ if src = L₁ ⊗ I₃ (and the linear solver takes any matrix), into the own
 * matrix A (new pattern: clone + analyze) and factor it, shifting if it is not positive
 * definite. Sets f->factored or f->fail_reason. */
static int load_and_factor(eo_pd_factor *f, const eo_solver_ctx *sc, const eo_csc *src, int try_scalar,
                           eo_solve_result *res)
{
    int rc;
    f->factored = 0;
    f->fail_reason = 0;
    f->shift = 0;
    if (!src || src->n != f->n)
        return eo_error(sc->ctx, EO_ERR_INVALID, "%s: matrix has n = %d, objective has n = %d",
                        f->who, src ? src->n : -1, f->n);
    eo_csc *L1 = NULL;
    f->scalar = 0;
    if (try_scalar && f->bs && !sc->obj->space && !eo_linsolve_get_type(sc->linear)->set_coordinates) {
        rc = eo_csc_kron_i3(sc->ctx, src, 1e-13, &L1);
        if (rc < 0) return rc;
        if (rc == 1) {
            src = L1;
            f->scalar = 1;
        }
    }
    rc = factor_own(f, sc, src, res);
    eo_csc_destroy(&L1);
    return rc;
}

int eo_pd_factor_prepare(eo_pd_factor *f, const eo_solver_ctx *sc, const double *x,
                         eo_solve_result *res)
{
    if (!sc->linear) return eo_error(sc->ctx, EO_ERR_INVALID, "%s needs a linear solver", f->who);
    int rc;
    f->external = 0;
    if (eo_linsolve_allows_own_factor(sc->linear)) {
        /* the objective's own CHOLMOD factor of L, kept across constraint changes */
        rc = eo_objective_constant_factor(sc->obj);
        if (rc >= 0) {
            res->n_factor += rc;
            f->external = f->factored = 1;
            f->fail_reason = 0;
            f->shift = 0;
            f->obj = NULL; /* the own factor (if any) is no longer the current one */
            return EO_OK;
        }
        if (rc != EO_ERR_UNSUPPORTED && rc != EO_ERR_INVALID) return rc;
        /* none, or L not positive definite: the own factor below (shifted if need be) */
    }
    eo_csc *L = NULL;
    unsigned long ver = 0;
    rc = eo_objective_constant_hessian(sc->obj, &L, &ver);
    if (rc == EO_OK) {
        int reuse = f->factored && f->obj == sc->obj && f->src == L && f->version == ver &&
                    f->ls == sc->linear && f->A && f->A->n == (f->scalar ? f->n / 3 : f->n);
        if (sc->obj->space) { /* a distributed objective: every part refactors with the others */
            double r = reuse;
            eo_vreduce(sc->obj->space, &r, 1, EO_REDUCE_MIN);
            reuse = r == 1;
        }
        if (reuse) return EO_OK; /* the factors of the previous minimization are still L's */
        f->obj = NULL;
        rc = load_and_factor(f, sc, L, 1, res);
        if (rc < 0) return rc;
        if (f->factored) {
            f->obj = sc->obj;
            f->src = L;
            f->version = ver;
        }
        return EO_OK;
    }
    if (rc != EO_ERR_UNSUPPORTED) return rc;
    /* no constant matrix: the (projected) Hessian at the first iterate */
    eo_csc *H = NULL;
    f->obj = NULL;
    rc = eo_objective_hessian(sc->obj, x, sc->hessfix->elem_proj, &H);
    if (rc < 0) return rc;
    return load_and_factor(f, sc, H, 0, res); /* a Hessian: not of the L₁ ⊗ I₃ form */
}

/* One solve with the linear solver: 0 or a negative reason. */
static int solve1(const eo_solver_ctx *sc, const double *b, double *r, eo_solve_result *res)
{
    int rc = eo_linsolve_solve(sc->linear, b, r);
    if (rc < 0) {
        res->status = rc;
        return EO_DIVERGED_LINSOLVE;
    }
    if (rc == EO_WARN_NOT_PD) return EO_DIVERGED_NOT_PD;
    return 0;
}

int eo_pd_factor_solve(const eo_pd_factor *f, const eo_solver_ctx *sc, const double *b, double *r,
                       eo_solve_result *res)
{
    if (f->external) {
        int rc = sc->obj->ops->constant_solve(sc->obj->data, b, r);
        if (rc < 0) {
            res->status = rc;
            return EO_DIVERGED_LINSOLVE;
        }
        return 0;
    }
    if (!f->scalar) return solve1(sc, b, r, res);
    const int m = f->n / 3;
    for (int c = 0; c < 3; c++) { /* (L₁ ⊗ I₃)⁻¹ b: coordinate c of every node at once */
        for (int v = 0; v < m; v++) f->bs[v] = b[3 * v + c];
        int reason = solve1(sc, f->bs, f->xs, res);
        if (reason) return reason;
        for (int v = 0; v < m; v++) r[3 * v + c] = f->xs[v];
    }
    return 0;
}
