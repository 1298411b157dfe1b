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
    return eo_shift_ws_setup(&f->ws, n, ctx);
}

void eo_pd_factor_deinit(eo_ctx *ctx, eo_pd_factor *f)
{
    eo_shift_ws_destroy(&f->ws, ctx);
    eo_csc_destroy(&f->A);
    memset(f, 0, sizeof *f);
}

static int same_pattern(const eo_csc *A, const eo_csc *B)
{
    return A && B && A->n == B->n && A->nnz == B->nnz &&
           memcmp(A->colptr, B->colptr, ((size_t)A->n + 1) * sizeof(int)) == 0 &&
           memcmp(A->rowind, B->rowind, (size_t)A->nnz * sizeof(int)) == 0;
}

/* Copy src into the own matrix A (new pattern: clone + analyze) and factor it, shifting
 * if it is not positive definite. Sets f->factored or f->fail_reason. */
static int load_and_factor(eo_pd_factor *f, const eo_solver_ctx *sc, const eo_csc *src,
                           eo_solve_result *res)
{
    const int n = f->n;
    int rc;
    f->factored = 0;
    f->fail_reason = 0;
    f->shift = 0;
    if (!src || src->n != n)
        return eo_error(sc->ctx, EO_ERR_INVALID, "%s: matrix has n = %d, objective has n = %d",
                        f->who, src ? src->n : -1, n);
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

int eo_pd_factor_prepare(eo_pd_factor *f, const eo_solver_ctx *sc, const double *x,
                         eo_solve_result *res)
{
    if (!sc->linear) return eo_error(sc->ctx, EO_ERR_INVALID, "%s needs a linear solver", f->who);
    eo_csc *L = NULL;
    unsigned long ver = 0;
    int rc = eo_objective_constant_hessian(sc->obj, &L, &ver);
    if (rc == EO_OK) {
        if (f->factored && f->obj == sc->obj && f->src == L && f->version == ver &&
            f->ls == sc->linear && f->A && f->A->n == f->n)
            return EO_OK; /* the factors of the previous minimization are still L's */
        f->obj = NULL;
        rc = load_and_factor(f, sc, L, res);
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
    return load_and_factor(f, sc, H, res);
}

int eo_pd_factor_solve(const eo_pd_factor *f, const eo_solver_ctx *sc, const double *b, double *r,
                       eo_solve_result *res)
{
    (void)f;
    int rc = eo_linsolve_solve(sc->linear, b, r);
    if (rc < 0) {
        res->status = rc;
        return EO_DIVERGED_LINSOLVE;
    }
    if (rc == EO_WARN_NOT_PD) return EO_DIVERGED_NOT_PD;
    return 0;
}
