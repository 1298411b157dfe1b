/* lapack_lu — dense LU with partial pivoting through LAPACKE (dgetrf / dgetrs, the
 * factor-once form of dgesv).
 *
 *   P A = L U  (dense, 2n³/3 flops, 8 n² bytes),  x = U⁻¹ L⁻¹ P b.
 *
 * Works for any non-singular A, definite or not (no positive-definiteness test: an
 * indefinite Hessian is solved, not reported; use lapack or lapack_ldlt for that). The
 * symmetric matrix given by its upper triangle is expanded to the full dense matrix at
 * every factor. dgetrf reports an exactly zero pivot u_kk = 0 (info = k + 1): A is
 * singular and factor returns EO_ERR_LINSOLVE naming column k of U. Small n only:
 * analyze refuses n > max_n.
 *
 * Parameters (solver.lapack_lu.<key>):
 *   max_n   largest dimension accepted                                  default 5000
 */
#include <lapacke.h>
#include <stddef.h>
#include <string.h>

#include "elastopt/linsolve.h"

typedef struct lu_params {
    int max_n; /* largest dimension accepted; default 5000 */
} lu_params;

static const eo_param_desc lu_desc[] = {
    {.key = "max_n", .kind = EO_PARAM_INT, .offset = offsetof(lu_params, max_n), .def.i = 5000,
     .min = 1, .range = EO_RANGE_MIN, .help = "largest n accepted (dense memory is 8 n^2 bytes)"},
    {0},
};

typedef struct lu_state {
    lu_params p;
    int n;
    double *LU;       /* n×n column-major: L (unit, below) and U (on and above) */
    lapack_int *ipiv; /* n row interchanges */
} lu_state;

static int lu_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    ((lu_state *)st)->p = *(const lu_params *)params;
    return EO_OK;
}

static void lu_destroy(void *st, eo_ctx *ctx)
{
    lu_state *s = st;
    eo_free(ctx, s->LU);
    eo_free(ctx, s->ipiv);
    s->LU = NULL;
    s->ipiv = NULL;
}

static int lu_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    lu_state *s = st;
    lu_destroy(s, ctx);
    if (A->n > s->p.max_n)
        return eo_error(ctx, EO_ERR_UNSUPPORTED,
                        "lapack_lu: n = %d exceeds solver.lapack_lu.max_n = %d (dense %.1f MB); use "
                        "umfpack, or raise max_n",
                        A->n, s->p.max_n, 8.0 * A->n * (double)A->n / 1e6);
    s->n = A->n;
    size_t m = (size_t)(A->n ? A->n : 1);
    s->LU = eo_malloc(ctx, m * m * sizeof(double));
    s->ipiv = eo_malloc(ctx, m * sizeof(lapack_int));
    if (!s->LU || !s->ipiv) {
        lu_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "lapack_lu: out of memory for a dense %d×%d matrix", A->n, A->n);
    }
    return EO_OK;
}

static int lu_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)stats;
    lu_state *s = st;
    const size_t n = (size_t)s->n;
    if (n == 0) return EO_OK;
    memset(s->LU, 0, n * n * sizeof(double));
    for (size_t j = 0; j < n; j++)
        for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
            size_t i = (size_t)A->rowind[p];
            s->LU[j * n + i] = s->LU[i * n + j] = A->val[p];
        }
    lapack_int info = LAPACKE_dgetrf(LAPACK_COL_MAJOR, (lapack_int)n, (lapack_int)n, s->LU, (lapack_int)n, s->ipiv);
    if (info > 0) {
        int col = (int)info - 1;
        return eo_error_at(ctx, EO_ERR_LINSOLVE, EO_ERRLOC_ITEM(NULL, -1, "column", col),
                           "lapack_lu: matrix singular (dgetrf: u_kk = 0 at column %d of U)", col);
    }
    if (info < 0) return eo_error(ctx, EO_ERR_LINSOLVE, "lapack_lu: dgetrf argument %d invalid", (int)-info);
    return EO_OK;
}

static int lu_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    lu_state *s = st;
    stats->iterations = 0;
    if (x != b) memcpy(x, b, (size_t)s->n * sizeof(double));
    if (s->n == 0) return EO_OK;
    lapack_int info = LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'N', s->n, 1, s->LU, s->n, s->ipiv, x, s->n);
    if (info != 0) return eo_error(ctx, EO_ERR_LINSOLVE, "lapack_lu: dgetrs failed (info %d)", (int)info);
    return EO_OK;
}

const eo_linsolve_type eo_linsolve_lapack_lu = {
    .info = {.name = "lapack_lu",
             .summary = "dense LAPACK LU dgetrf/dgetrs (any non-singular A; n <= max_n)",
             .params = lu_desc,
             .params_size = sizeof(lu_params)},
    .state_size = sizeof(lu_state),
    .setup = lu_setup,
    .analyze = lu_analyze,
    .factor = lu_factor,
    .solve = lu_solve,
    .destroy = lu_destroy,
};
