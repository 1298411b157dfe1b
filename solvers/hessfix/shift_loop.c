/* The c·I shift loop shared by every Hessian fix (002 Note 4; Nocedal & Wright,
 * Numerical Optimization, Alg. 3.3 "Cholesky with added multiple of the identity", with
 * the shift carried over between iterations).
 *
 * If A = QΛQᵀ then A + cI = Q(Λ + cI)Qᵀ is positive definite once c > −λ_min. The loop
 * starts at the shift carried over from the previous direction (0 at the start of a
 * minimization), grows it by shift_grow from c_min = shift_init·s (s = mean |A_ii|, 1 if
 * 0) on EO_WARN_NOT_PD or a non-descent direction, gives up above shift_max·s, and after a
 * success carries c/shift_shrink (0 below c_min) to the next direction. The shift is
 * written on the stored diagonal (the last entry of each CSC column, sparse.h) and the
 * original diagonal restored after the factorization and solve: no copy of A, no
 * allocation. See shift_loop.h for the contract. */
#include <math.h>
#include <string.h>

#include "shift_loop.h"

int eo_shift_ws_setup(eo_shift_ws *w, int n, eo_ctx *ctx)
{
    eo_free(ctx, w->diag);
    memset(w, 0, sizeof *w);
    w->diag = eo_calloc(ctx, 2 * (size_t)(n > 0 ? n : 1), sizeof(double));
    if (w->diag) w->dsum = w->diag + (n > 0 ? n : 1);
    if (!w->diag) return eo_error(ctx, EO_ERR_NOMEM, "hessian fix: out of memory (n = %d)", n);
    w->n = n;
    return EO_OK;
}

void eo_shift_ws_destroy(eo_shift_ws *w, eo_ctx *ctx)
{
    eo_free(ctx, w->diag);
    memset(w, 0, sizeof *w);
}

void eo_shift_params_get(const eo_hessfix_shift_params *p, eo_hessfix_shift_params *hp)
{
    if (p) *hp = *p;
    else eo_params_default(eo_hessfix_shift_params_desc, hp);
}

/* A_jj = d_j + c; on a distributed space A is a part's matrix: c goes on the owned
 * diagonal entries only, so that the parts' matrices add up to H + cI */
static void set_diag(eo_csc *A, const double *d, double c, const eo_vspace *vs)
{
    if (vs) {
        for (int j = 0; j < A->n; j++) A->val[A->colptr[j + 1] - 1] = d[j] + (vs->own[j] ? c : 0);
        return;
    }
    for (int j = 0; j < A->n; j++) A->val[A->colptr[j + 1] - 1] = d[j] + c;
}

int eo_shift_factor(eo_shift_ws *w, const eo_hessfix_shift_params *hp, int shifting,
                    const eo_hessfix_env *env, eo_csc *A, double *p, eo_hessfix_out *out)
{
    const int n = env->n;
    eo_solve_result *res = env->res;
    out->factored = 0;
    out->shift = 0;
    if (!A || A->n != n || n > w->n)
        return eo_error(env->ctx, EO_ERR_INVALID, "hessian fix: matrix has n = %d, objective has n = %d",
                        A ? A->n : -1, n);
    const eo_vspace *vs = env->obj ? env->obj->space : NULL;
    double s = 0;
    long nall = n;
    for (int j = 0; j < n; j++) {
        w->diag[j] = A->val[A->colptr[j + 1] - 1];
        s += fabs(w->diag[j]);
    }
    if (vs) { /* mean |H_jj| of the whole matrix: the parts' diagonals summed first */
        memcpy(w->dsum, w->diag, (size_t)n * sizeof(double));
        if (vs->assemble(w->dsum, vs->user) < 0) w->dsum[0] = NAN;
        s = 0;
        for (int j = 0; j < n; j++)
            if (vs->own[j]) s += fabs(w->dsum[j]);
        eo_vreduce(vs, &s, 1, EO_REDUCE_SUM);
        nall = vs->nglobal;
    }
    if (!isfinite(s)) {
        out->reason = EO_DIVERGED_NONFINITE;
        return 0;
    }
    s = nall > 0 && s > 0 ? s / nall : 1;
    const double c_min = hp->shift_init * s, c_max = hp->shift_max * s;
    const double gnorm = env->want_direction ? sqrt(eo_vdot(vs, n, env->grad, env->grad)) : 0;
    double c = shifting ? w->c_next : 0;

    for (;;) {
        int good = 0;
        if (c > 0) set_diag(A, w->diag, c, vs);
        int frc = eo_linsolve_factor(env->linear, A);
        res->n_factor++;
        if (frc >= 0 && frc != EO_WARN_NOT_PD) {
            if (!env->want_direction) {
                good = 1;
            } else {
                frc = eo_linsolve_solve(env->linear, env->grad, p);
                if (frc == EO_WARN_NOT_PD) out->neg_curvature = 1; /* cg/pcg: pᵀAp ≤ 0 */
                if (frc >= 0 && frc != EO_WARN_NOT_PD) {
                    for (int i = 0; i < n; i++) p[i] = -p[i];
                    double dg = eo_vdot(vs, n, env->grad, p), pn = sqrt(eo_vdot(vs, n, p, p));
                    good = isfinite(dg) && isfinite(pn) && dg < -env->descent_eps * gnorm * pn;
                }
            }
        }
        if (c > 0) set_diag(A, w->diag, 0, vs);
        if (frc < 0) {
            res->status = frc;
            out->reason = EO_DIVERGED_LINSOLVE;
            return 0;
        }
        if (good) break;
        if (!shifting) return 0;
        c = c * hp->shift_grow > c_min ? c * hp->shift_grow : c_min;
        if (!(c <= c_max)) {
            out->reason = EO_DIVERGED_NOT_PD;
            out->shift = c;
            return 0;
        }
    }
    if (c > 0) {
        res->n_shifted++;
        w->c_next = c / hp->shift_shrink >= c_min ? c / hp->shift_shrink : 0;
        eo_log(env->ctx, EO_LOG_DEBUG, "hessian fix: system shifted by %g", c);
    } else {
        w->c_next = 0;
    }
    out->shift = c;
    out->factored = 1;
    return 1;
}

int eo_shift_assemble_factor(eo_shift_ws *w, const eo_hessfix_shift_params *hp, int shifting,
                             const eo_hessfix_env *env, eo_proj proj,
                             const unsigned char *proj_of, double *p, eo_hessfix_out *out)
{
    eo_csc *A = NULL;
    int reason = 0;
    int rc = env->assemble(env->user, proj, proj_of, &A, &reason);
    if (rc < 0) return rc;
    if (reason) {
        out->reason = reason;
        out->factored = 0;
        return 0;
    }
    /* the true Hessian (no projection, or a partial one) may be indefinite: a failed
     * factorization is the fix's normal path, counted and not printed; a projected one
     * failing is a surprise (warned once by the linear solver) */
    int old = eo_linsolve_set_expect_not_pd(env->linear, proj == EO_PROJ_NONE);
    int r = eo_shift_factor(w, hp, shifting, env, A, p, out);
    eo_linsolve_set_expect_not_pd(env->linear, old);
    return r;
}

void eo_shift_fallback(eo_shift_ws *w, const eo_hessfix_env *env, double *p, eo_hessfix_out *out)
{
    for (int i = 0; i < env->n; i++) p[i] = -env->grad[i];
    env->res->n_fallback++;
    eo_log(env->ctx, EO_LOG_DEBUG, "hessian fix: Hessian not positive definite, steepest descent");
    w->c_next = 0;
    out->shift = 0;
    out->factored = 0;
}

double eo_csc_quad_space(const eo_csc *A, const double *p, const eo_vspace *vs)
{
    double q = eo_csc_quad_upper(A, p);
    eo_vreduce(vs, &q, 1, EO_REDUCE_SUM); /* a part's matrix: the parts' forms add up */
    return q;
}

double eo_csc_quad_upper(const eo_csc *A, const double *p)
{
    double q = 0;
    for (int j = 0; j < A->n; j++)
        for (int e = A->colptr[j]; e < A->colptr[j + 1]; e++) {
            int i = A->rowind[e];
            double v = A->val[e] * p[i] * p[j];
            q += i == j ? v : 2 * v;
        }
    return q;
}

int eo_shift_op_setup(void *st, const void *params, int n, eo_ctx *ctx)
{
    (void)params;
    return eo_shift_ws_setup(st, n, ctx);
}

int eo_shift_op_begin(void *st, const void *params, const eo_hessfix_env *env)
{
    (void)params, (void)env;
    eo_shift_ws_begin(st);
    return EO_OK;
}

void eo_shift_op_destroy(void *st, eo_ctx *ctx) { eo_shift_ws_destroy(st, ctx); }
