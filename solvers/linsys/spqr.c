/* spqr — sparse QR factorization of the full symmetric matrix (SuiteSparseQR).
 *
 *   A E = Q R,  Q orthogonal (Householder vectors), R upper triangular, E a
 *   fill-reducing column permutation;   x = E R⁻¹ Qᵀ b.
 *
 * QR needs no positive definiteness: it is the robust fallback for indefinite or
 * rank-deficient systems and a reference for comparisons (several times the cost of
 * Cholesky). Columns whose norm falls below `tol` are treated as dependent (rank
 * revealing); for a rank-deficient A the result is a basic solution and solve
 * reports EO_WARN_NOT_CONVERGED if the residual is not small. The symmetric upper CSC
 * is expanded to both triangles once in `analyze` (SuiteSparseQR_C_symbolic);
 * `factor` gathers values and calls SuiteSparseQR_C_numeric. SuiteSparseQR uses the
 * long-index CHOLMOD interface (cholmod_l_*), so indices are copied to long once.
 * solve allocates through CHOLMOD (SuiteSparseQR_C_qmult / _solve return new arrays).
 *
 * Parameters (solver.spqr.<key>):
 *   tol       column 2-norm below which a column counts as dependent; < 0 = SPQR's
 *             default (20 (m+n) eps max column norm)                    default -1
 *   ordering  "default" (SPQR's choice: COLAMD/METIS), "amd", "colamd", "fixed"
 */
#include <math.h>
#include <stddef.h>
#include <string.h>
#include <suitesparse/SuiteSparseQR_C.h>

#include "elastopt/linsolve.h"

typedef struct spqr_params {
    double tol;        /* dependent-column threshold; default -1 (SPQR default) */
    char ordering[16]; /* column ordering; default "default" */
} spqr_params;

static const char *const orderings[] = {"default", "amd", "colamd", "fixed", NULL};

static const eo_param_desc spqr_desc[] = {
    {.key = "tol", .kind = EO_PARAM_DOUBLE, .offset = offsetof(spqr_params, tol), .def.d = -1,
     .help = "column 2-norm treated as zero (rank detection); < 0: SPQR's default"},
    {.key = "ordering", .kind = EO_PARAM_CHOICE, .offset = offsetof(spqr_params, ordering),
     .size = sizeof(((spqr_params *)0)->ordering), .def.s = "default", .choices = orderings,
     .help = "column ordering: default (SPQR's choice), amd, colamd, fixed"},
    {0},
};

typedef struct spqr_state {
    spqr_params p;
    cholmod_common c;
    int started;
    int n;
    eo_csc_full *F;
    SuiteSparse_long *Fp, *Fi; /* long copies of F's pattern */
    cholmod_sparse S;          /* header over Fp, Fi, F->val */
    SuiteSparseQR_C_factorization *QR;
} spqr_state;

static int spqr_setup(void *st, const void *params, eo_ctx *ctx)
{
    (void)ctx;
    spqr_state *s = st;
    s->p = *(const spqr_params *)params;
    cholmod_l_start(&s->c);
    s->c.print = 0;
    s->c.error_handler = NULL;
    s->started = 1;
    return EO_OK;
}

static int ordering_code(const char *o)
{
    if (strcmp(o, "amd") == 0) return SPQR_ORDERING_AMD;
    if (strcmp(o, "colamd") == 0) return SPQR_ORDERING_COLAMD;
    if (strcmp(o, "fixed") == 0) return SPQR_ORDERING_FIXED;
    return SPQR_ORDERING_DEFAULT;
}

static void release(spqr_state *s, eo_ctx *ctx)
{
    if (s->QR) SuiteSparseQR_C_free(&s->QR, &s->c);
    eo_csc_full_destroy(&s->F);
    eo_free(ctx, s->Fp);
    eo_free(ctx, s->Fi);
    s->Fp = s->Fi = NULL;
}

static int spqr_analyze(void *st, const eo_csc *A, eo_ctx *ctx)
{
    spqr_state *s = st;
    release(s, ctx);
    s->n = A->n;
    int rc = eo_csc_full_create(ctx, A, &s->F);
    if (rc < 0) return rc;
    s->Fp = eo_malloc(ctx, ((size_t)A->n + 1) * sizeof(SuiteSparse_long));
    s->Fi = eo_malloc(ctx, (size_t)(s->F->nnz ? s->F->nnz : 1) * sizeof(SuiteSparse_long));
    if (!s->Fp || !s->Fi) {
        release(s, ctx);
        return eo_error(ctx, EO_ERR_NOMEM, "spqr: out of memory");
    }
    for (int j = 0; j <= A->n; j++) s->Fp[j] = s->F->colptr[j];
    for (int q = 0; q < s->F->nnz; q++) s->Fi[q] = s->F->rowind[q];
    memset(&s->S, 0, sizeof s->S);
    s->S.nrow = s->S.ncol = (size_t)A->n;
    s->S.nzmax = (size_t)s->F->nnz;
    s->S.p = s->Fp;
    s->S.i = s->Fi;
    s->S.x = s->F->val;
    s->S.stype = 0; /* unsymmetric storage: QR needs the whole matrix */
    s->S.itype = CHOLMOD_LONG;
    s->S.xtype = CHOLMOD_REAL;
    s->S.dtype = CHOLMOD_DOUBLE;
    s->S.sorted = 1;
    s->S.packed = 1;
    s->QR = SuiteSparseQR_C_symbolic(ordering_code(s->p.ordering), 1, &s->S, &s->c);
    if (!s->QR) {
        int st2 = s->c.status;
        release(s, ctx);
        return eo_error(ctx, st2 == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "spqr: symbolic analysis failed (CHOLMOD status %d)", st2);
    }
    return EO_OK;
}

static int spqr_factor(void *st, const eo_csc *A, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    (void)stats;
    spqr_state *s = st;
    eo_csc_full_fill(s->F, A);
    double tol = s->p.tol < 0 ? SPQR_DEFAULT_TOL : s->p.tol;
    if (!SuiteSparseQR_C_numeric(tol, &s->S, s->QR, &s->c))
        return eo_error(ctx, s->c.status == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "spqr: numeric factorization failed (CHOLMOD status %d)", s->c.status);
    long rank = (long)s->c.SPQR_istat[4];
    if (rank < A->n)
        eo_log(ctx, EO_LOG_DEBUG, "spqr: numerical rank %ld < n = %d", rank, A->n);
    return EO_OK;
}

static int spqr_solve(void *st, const double *b, double *x, eo_linsolve_stats *stats, eo_ctx *ctx)
{
    spqr_state *s = st;
    const int n = s->n;
    cholmod_dense B;
    memset(&B, 0, sizeof B);
    B.nrow = B.nzmax = B.d = (size_t)n;
    B.ncol = 1;
    B.x = (void *)(size_t)b; /* read only */
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *Y = SuiteSparseQR_C_qmult(SPQR_QTX, s->QR, &B, &s->c);
    cholmod_dense *X = Y ? SuiteSparseQR_C_solve(SPQR_RETX_EQUALS_B, s->QR, Y, &s->c) : NULL;
    cholmod_l_free_dense(&Y, &s->c);
    if (!X)
        return eo_error(ctx, s->c.status == CHOLMOD_OUT_OF_MEMORY ? EO_ERR_NOMEM : EO_ERR_LINSOLVE,
                        "spqr: solve failed (CHOLMOD status %d)", s->c.status);
    memcpy(x, X->x, (size_t)n * sizeof(double));
    cholmod_l_free_dense(&X, &s->c);
    /* residual ‖b − Ax‖/‖b‖ (rank-deficient or inconsistent systems show here) */
    double rr = 0, bb = 0;
    for (int j = 0; j < n; j++) bb += b[j] * b[j];
    /* use the full matrix rows: r_i = b_i − Σ_j F(i,j) x_j */
    for (int i = 0; i < n; i++) {
        double r = b[i];
        for (int q = s->F->colptr[i]; q < s->F->colptr[i + 1]; q++) r -= s->F->val[q] * x[s->F->rowind[q]];
        rr += r * r;
    }
    stats->residual = bb > 0 ? sqrt(rr / bb) : sqrt(rr);
    if (!isfinite(stats->residual) || stats->residual > 1e-6)
        return eo_error(ctx, EO_WARN_NOT_CONVERGED,
                        "spqr: relative residual %.3g (rank %ld of %d): system singular or inconsistent",
                        stats->residual, (long)s->c.SPQR_istat[4], n);
    return EO_OK;
}

static void spqr_destroy(void *st, eo_ctx *ctx)
{
    spqr_state *s = st;
    if (!s->started) return;
    release(s, ctx);
    cholmod_l_finish(&s->c);
    s->started = 0;
}

const eo_linsolve_type eo_linsolve_spqr = {
    .info = {.name = "spqr",
             .summary = "SuiteSparseQR sparse QR of the full matrix (indefinite/rank-deficient fallback)",
             .params = spqr_desc,
             .params_size = sizeof(spqr_params)},
    .state_size = sizeof(spqr_state),
    .setup = spqr_setup,
    .analyze = spqr_analyze,
    .factor = spqr_factor,
    .solve = spqr_solve,
    .destroy = spqr_destroy,
};
