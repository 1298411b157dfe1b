/* lapack — dense Cholesky with LAPACK (dpotrf / dpotrs), the reference solver.
 *
 *   A = Uᵀ U (dense, O(n³/3) flops, O(n²) memory),  x = U⁻¹ U⁻ᵀ b.
 *
 * dpotrf stops at the first column k whose pivot a_kk − Σ u_ik² is <= 0: the matrix
 * is not positive definite and factor returns EO_WARN_NOT_PD with that column. No
 * permutation, so the column is the matrix's own. Meant for tests and small systems:
 * `analyze` refuses n > max_n (memory 8 n² bytes).
 *
 * Parameters (solver.lapack.<key>):
 *   max_n   largest dimension accepted                                  default 5000
 */
#include <lapacke.h>
#include <stddef.h>
#include <string.h>

#include "elastopt/linsolve.h"

typedef struct lapack_params {
    int max_n; /* largest dimension accepted; default 5000 */
} lapack_params;

static const eo_param_desc lapack_desc[] = {
    {.key = "max_n", .kind = EO_PARAM_INT, .offset = offsetof(lapack_params, max_n), .def.i = 5000,
     .min = 1, .range = EO_RANGE_MIN, .help = "largest n accepted (dense memory is 8 n^2 bytes)"},
    {0},
};

typedef struct lapack_state {
    lapack_params p;
    int n;
    double *U; /* n×n column-major; upper triangle holds the factor */
} lapack_state;

static int lapack_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    ((lapack_state *)st)->p = *(const lapack_params *)params;
    return EO_OK;
}

static int lapack_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    lapack_state *s = st;
    eo_free(ctx, s->U);
    s->U = NULL;
    if (A->n > s->p.max_n)
        return eo_error(ctx, EO_ERR_UNSUPPORTED,
                        "lapack: n = %d exceeds solver.lapack.max_n = %d (dense %.1f MB); use a "
                        "sparse solver such as cholmod, or raise max_n",
                        A->n, s->p.max_n, 8.0 * A->n * (double)A->n / 1e6);
    s->n = A->n;
    s->U = eo_malloc(ctx, (size_t)(A->n ? A->n : 1) * (size_t)(A->n ? A->n : 1) * sizeof(double));
    if (!s->U) return eo_error(ctx, EO_ERR_NOMEM, "lapack: out of memory for a dense %d×%d matrix", A->n, A->n);
    return EO_OK;
}

static int lapack_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    lapack_state *s = st;
    const size_t n = (size_t)s->n;
    memset(s->U, 0, n * n * sizeof(double));
    /* our upper CSC column j = column j of the column-major upper triangle */
    for (size_t j = 0; j < n; j++)
        for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) s->U[j * n + (size_t)A->rowind[p]] = A->val[p];
    if (n == 0) return EO_OK;
    lapack_int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'U', (lapack_int)n, s->U, (lapack_int)n);
    if (info > 0) {
        int col = (int)info - 1;
        stats->not_pd_column = col;
        return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", col),
                           "lapack: matrix not positive definite (dpotrf)");
    }
    if (info < 0) return eo_error(ctx, EO_ERR_LINSOLVE, "lapack: dpotrf argument %d invalid", (int)-info);
    return EO_OK;
}

static int lapack_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    lapack_state *s = st;
    stats->iterations = 0;
    if (x != b) memcpy(x, b, (size_t)s->n * sizeof(double));
    if (s->n == 0) return EO_OK;
    lapack_int info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'U', s->n, 1, s->U, s->n, x, s->n);
    if (info != 0) return eo_error(ctx, EO_ERR_LINSOLVE, "lapack: dpotrs failed (info %d)", (int)info);
    return EO_OK;
}

static void lapack_destroy(void *st, eo_ctx *ctx)
{
    lapack_state *s = st;
    eo_free(ctx, s->U);
    s->U = NULL;
}

const eo_linsolve_type eo_linsolve_lapack = {
    .info = {.name = "lapack",
             .summary = "dense LAPACK Cholesky dpotrf/dpotrs (reference; n <= max_n)",
             .params = lapack_desc,
             .params_size = sizeof(lapack_params)},
    .state_size = sizeof(lapack_state),
    .setup = lapack_setup,
    .analyze = lapack_analyze,
    .factor = lapack_factor,
    .solve = lapack_solve,
    .destroy = lapack_destroy,
};
