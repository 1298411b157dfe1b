/* lapack_ldlt — dense symmetric-indefinite LDLᵀ with Bunch–Kaufman pivoting through
 * LAPACKE (dsytrf / dsytrs).
 *
 *   P A Pᵀ = U D Uᵀ,  D block diagonal with 1×1 and 2×2 blocks,  x = A⁻¹ b
 *   (Bunch & Kaufman 1977; n³/3 flops, 8 n² bytes).
 *
 * Inertia (Sylvester's law: A and D have the same numbers of negative, zero and
 * positive eigenvalues): a 1×1 block d counts by its sign; a 2×2 block [a b; b c] has
 * one negative and one positive eigenvalue when ac − b² < 0, else two of the sign of
 * a + c (and a zero when ac − b² = 0). The counts are in stats.n_negative / n_zero.
 * A is positive definite iff both are 0. Otherwise factor returns EO_WARN_NOT_PD, as
 * the Cholesky solvers do, with the first non-positive D block in stats.not_pd_column
 * (an index in the pivoted order: Bunch–Kaufman interchanges rows, so it is not the
 * matrix's own column), and the factor is not used — unless allow_indefinite is set:
 * then a non-singular indefinite A is accepted (EO_OK, inertia still reported) and
 * solved. A zero pivot (info > 0, singular A) is EO_WARN_NOT_PD either way.
 * Small n only: analyze refuses n > max_n.
 *
 * Parameters (solver.lapack_ldlt.<key>):
 *   max_n             largest dimension accepted                        default 5000
 *   allow_indefinite  accept (and solve with) an indefinite A           default false
 */
#include <lapacke.h>
#include <stddef.h>
#include <string.h>

#include "elastopt/linsolve.h"

typedef struct ldlt_params {
    int max_n;            /* largest dimension accepted; default 5000 */
    int allow_indefinite; /* accept negative eigenvalues; default false */
} ldlt_params;

static const eo_param_desc ldlt_desc[] = {
    {.key = "max_n", .kind = EO_PARAM_INT, .offset = offsetof(ldlt_params, max_n), .def.i = 5000,
     .min = 1, .range = EO_RANGE_MIN, .help = "largest n accepted (dense memory is 8 n^2 bytes)"},
    {.key = "allow_indefinite", .kind = EO_PARAM_BOOL,
     .offset = offsetof(ldlt_params, allow_indefinite), .def.i = 0,
     .help = "accept and solve a non-singular indefinite matrix (inertia still reported); "
             "false: report EO_WARN_NOT_PD like Cholesky"},
    {0},
};

typedef struct ldlt_state {
    ldlt_params p;
    int n;
    double *F;        /* n×n column-major; upper triangle holds U and D */
    lapack_int *ipiv; /* n: Bunch–Kaufman interchanges and block structure */
} ldlt_state;

static int ldlt_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    ((ldlt_state *)st)->p = *(const ldlt_params *)params;
    return EO_OK;
}

static void ldlt_destroy(void *st, eo_ctx *ctx)
{
    ldlt_state *s = st;
    eo_free(ctx, s->F);
    eo_free(ctx, s->ipiv);
    s->F = NULL;
    s->ipiv = NULL;
}

static int ldlt_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    ldlt_state *s = st;
    ldlt_destroy(s, ctx);
    if (A->n > s->p.max_n)
        return eo_error(ctx, EO_ERR_UNSUPPORTED,
                        "lapack_ldlt: n = %d exceeds solver.lapack_ldlt.max_n = %d (dense %.1f MB); use "
                        "cholmod_ldlt, or raise max_n",
                        A->n, s->p.max_n, 8.0 * A->n * (double)A->n / 1e6);
    s->n = A->n;
    size_t m = (size_t)(A->n ? A->n : 1);
    s->F = eo_malloc(ctx, m * m * sizeof(double));
    s->ipiv = eo_malloc(ctx, m * sizeof(lapack_int));
    if (!s->F || !s->ipiv) {
        ldlt_destroy(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "lapack_ldlt: out of memory for a dense %d×%d matrix", A->n, A->n);
    }
    return EO_OK;
}

/* Inertia of D; *first = first block with a non-positive eigenvalue (-1 if none). */
static void inertia(const ldlt_state *s, int *neg, int *zero, int *first)
{
    const int n = s->n;
    const double *F = s->F;
    *neg = *zero = 0;
    *first = -1;
    for (int k = 0; k < n;) {
        int nn = 0, nz = 0, w = 1;
        if (s->ipiv[k] > 0 || k + 1 == n) {
            double d = F[(size_t)k * n + k];
            nn = d < 0;
            nz = d == 0;
        } else { /* 2×2 block on rows k, k+1 (both ipiv entries negative) */
            double a = F[(size_t)k * n + k], b = F[(size_t)(k + 1) * n + k], c = F[(size_t)(k + 1) * n + k + 1];
            double det = a * c - b * b;
            if (det < 0) nn = 1;
            else if (det == 0) nz = 1, nn = a + c < 0;
            else nn = a + c < 0 ? 2 : 0;
            w = 2;
        }
        if ((nn || nz) && *first < 0) *first = k;
        *neg += nn;
        *zero += nz;
        k += w;
    }
}

static int ldlt_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    ldlt_state *s = st;
    const size_t n = (size_t)s->n;
    stats->n_negative = stats->n_zero = 0;
    if (n == 0) return EO_OK;
    memset(s->F, 0, n * n * sizeof(double));
    for (size_t j = 0; j < n; j++)
        for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) s->F[j * n + (size_t)A->rowind[p]] = A->val[p];
    lapack_int info = LAPACKE_dsytrf(LAPACK_COL_MAJOR, 'U', (lapack_int)n, s->F, (lapack_int)n, s->ipiv);
    if (info < 0) return eo_error(ctx, EO_ERR_LINSOLVE, "lapack_ldlt: dsytrf argument %d invalid", (int)-info);
    int neg, zero, first;
    inertia(s, &neg, &zero, &first);
    stats->n_negative = neg;
    stats->n_zero = zero;
    if (info > 0 || zero > 0 || (neg > 0 && !s->p.allow_indefinite)) {
        stats->not_pd_column = first >= 0 ? first : (int)info - 1;
        return eo_error_at(ctx, EO_WARN_NOT_PD, EO_ERRLOC_ITEM(NULL, -1, "column", stats->not_pd_column),
                           "lapack_ldlt: matrix not positive definite: inertia %d negative, %d zero, %d "
                           "positive eigenvalues (first non-positive D block at pivoted column %d)%s",
                           neg, zero, (int)n - neg - zero, stats->not_pd_column,
                           zero ? "; singular" : "");
    }
    return EO_OK;
}

static int ldlt_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    ldlt_state *s = st;
    stats->iterations = 0;
    if (x != b) memcpy(x, b, (size_t)s->n * sizeof(double));
    if (s->n == 0) return EO_OK;
    lapack_int info = LAPACKE_dsytrs(LAPACK_COL_MAJOR, 'U', s->n, 1, s->F, s->n, s->ipiv, x, s->n);
    if (info != 0) return eo_error(ctx, EO_ERR_LINSOLVE, "lapack_ldlt: dsytrs failed (info %d)", (int)info);
    return EO_OK;
}

const eo_linsolve_type eo_linsolve_lapack_ldlt = {
    .info = {.name = "lapack_ldlt",
             .summary = "dense LAPACK Bunch-Kaufman LDL' dsytrf/dsytrs with inertia (n <= max_n)",
             .params = ldlt_desc,
             .params_size = sizeof(ldlt_params)},
    .state_size = sizeof(ldlt_state),
    .setup = ldlt_setup,
    .analyze = ldlt_analyze,
    .factor = ldlt_factor,
    .solve = ldlt_solve,
    .destroy = ldlt_destroy,
};
