/* The projective-dynamics matrix factored once: see pd_factor.h. Moved out of
 * projective_dynamics.c so lbfgs (h0 = pd) and ncg (precond = pd) use the same code. */
#include "pd_factor.h"

#include <math.h>
#include <string.h>

int eo_pd_factor_init(eo_ctx *ctx, int n, const char *who, eo_pd_factor *f)
{
    memset(f, 0, sizeof *f);
    f->n = n;
    f->who = who;
    f->diag = eo_calloc(ctx, (size_t)(n > 0 ? n : 1), sizeof(double));
    if (!f->diag) return eo_error(ctx, EO_ERR_NOMEM, "%s: out of memory (n = %d)", who, n);
    return EO_OK;
}

void eo_pd_factor_deinit(eo_ctx *ctx, eo_pd_factor *f)
{
    eo_free(ctx, f->diag);
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
    eo_csc *A = f->A;
    double s = 0;
    for (int j = 0; j < n; j++) {
        f->diag[j] = A->val[A->colptr[j + 1] - 1];
        s += fabs(f->diag[j]);
    }
    if (!isfinite(s)) {
        f->fail_reason = EO_DIVERGED_NONFINITE;
        return EO_OK;
    }
    s = n > 0 && s > 0 ? s / n : 1;
    eo_hessfix_shift_params hp;
    if (sc->hessfix_params) hp = *(const eo_hessfix_shift_params *)sc->hessfix_params;
    else eo_params_default(eo_hessfix_shift_params_desc, &hp);
    const double c_min = hp.shift_init * s, c_max = hp.shift_max * s;
    double c = 0;
    for (;;) {
        for (int j = 0; j < n; j++) A->val[A->colptr[j + 1] - 1] = f->diag[j] + c;
        rc = eo_linsolve_factor(sc->linear, A);
        res->n_factor++;
        if (rc < 0) {
            res->status = rc;
            f->fail_reason = EO_DIVERGED_LINSOLVE;
            return EO_OK;
        }
        if (rc != EO_WARN_NOT_PD) break;
        c = c * hp.shift_grow > c_min ? c * hp.shift_grow : c_min;
        if (!(c <= c_max)) {
            f->fail_reason = EO_DIVERGED_NOT_PD;
            return EO_OK;
        }
    }
    if (c > 0) {
        res->n_shifted++;
        eo_log(sc->ctx, EO_LOG_DEBUG, "%s: matrix shifted by %g to factor it", f->who, c);
    }
    f->shift = c;
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
